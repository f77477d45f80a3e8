// The flow model's concave force map (chamber/force_map.hpp): cells land in the areas P_{ring,sector} they overlap,
// in proportion to the overlap, the map keeps the total, and the cells' normal impulse over a window is the window's
// mean force.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

#include "../common/coaxial_liners.hpp"
#include "../common/flow_params.hpp"
#include "chamber/force_map.hpp"

namespace {

using test_liners::cylinder;
using test_liners::shifted;


double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

const auto kMantle = cylinder(0.3, -0.8, -0.2), kConcave = cylinder(0.35, -0.8, -0.2);

}  // namespace

// 26 bands of a 0.6 m chamber are half a ring (13 rings) each, 18 sectors half a map sector (9): every cell lies in
// one area. Cell (band b from the bottom, sector s) is area P_{13 - b / 2, s / 2 + 1}.
TEST(ConcaveForceMap, CellsLandInTheAreaTheyLieIn) {
  chamber::FlowModel f(test_liners::flow_params(26, 18, false), kMantle, kConcave);
  chamber::ConcaveForceMap map(f, kConcave);
  ASSERT_EQ(map.rings(), 13);
  ASSERT_EQ(map.sectors(), 9);
  for (std::size_t k = 0; k < f.cells(); ++k) {
    std::vector<double> one(f.cells(), 0.0);
    one[k] = 1.0;
    const auto m = map.map(one);
    const int b = static_cast<int>(k) / 18, s = static_cast<int>(k) % 18;
    const int area = (12 - b / 2) * 9 + s / 2;
    EXPECT_NEAR(m[area], 1.0, 1e-12) << "cell " << k;
    EXPECT_NEAR(sum(m), 1.0, 1e-12) << "cell " << k;
  }
}

// 16 sectors against 9: cell sector 1 spans 22.5-45 deg, area sectors 0-40 and 40-80 deg: shares 17.5 / 22.5 and 5 /
// 22.5. Bands of 0.6 / 20 m against rings of 0.6 / 13 m split by height the same way. Any values keep their total.
TEST(ConcaveForceMap, CellsAcrossAreasSplitByOverlapAndTheTotalIsKept) {
  chamber::FlowModel f(test_liners::flow_params(20, 16, false), kMantle, kConcave);
  chamber::ConcaveForceMap map(f, kConcave);
  std::vector<double> one(f.cells(), 0.0);
  one[19 * 16 + 1] = 1.0;  // the top band, 30 mm: ring 1 (46 mm) holds it whole
  const auto m = map.map(one);
  EXPECT_NEAR(m[0], 17.5 / 22.5, 1e-12);
  EXPECT_NEAR(m[1], 5.0 / 22.5, 1e-12);
  // Band 6 spans 0.18-0.21 m above the bottom; rings 9 and 10 (1-based, from the top) meet 0.6 x 4 / 13 m above it.
  std::vector<double> band6(f.cells(), 0.0);
  band6[6 * 16] = 1.0;  // sector 0 lies in area sector 1 whole
  const auto m6 = map.map(band6);
  const double meet = 0.6 * 4 / 13, in9 = (0.21 - meet) / 0.03;
  EXPECT_NEAR(m6[8 * 9], in9, 1e-9);
  EXPECT_NEAR(m6[9 * 9], 1 - in9, 1e-9);
  std::vector<double> v(f.cells());
  for (std::size_t k = 0; k < v.size(); ++k) v[k] = std::sin(0.37 * k) + 1.5;
  EXPECT_NEAR(sum(map.map(v)), sum(v), 1e-9 * sum(v));
  // Area P_{2,3} (index 1 x 9 + 2): ring 2's mid-height, sector 3's mid-azimuth (100 deg), on the concave.
  const Eigen::Vector3d c = map.area_centre(11);
  EXPECT_NEAR(c.z(), -0.2 - 1.5 * 0.6 / 13, 1e-12);
  EXPECT_NEAR(std::atan2(c.y(), c.x()), 100.0 * M_PI / 180, 1e-12);
  EXPECT_NEAR(std::hypot(c.x(), c.y()), 0.35, 1e-12);
  EXPECT_THROW(map.area_centre(117), std::invalid_argument);
  EXPECT_THROW(chamber::ConcaveForceMap(f, kConcave, 0, 9), std::invalid_argument);
  EXPECT_THROW(map.map(std::vector<double>(3, 0.0)), std::invalid_argument);
}

// A mantle pressed and held still: each cell's impulse grows by p A h per step, so impulse / time is the mean force
// and the map of it totals the liners' normal force.
TEST(ConcaveForceMap, NormalImpulseOverAWindowIsItsMeanForce) {
  chamber::FlowModel f(test_liners::flow_params(8, 12, true), kMantle, kConcave);
  f.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), {0, 0, -0.5}, {0, 0, -0.6}, 1e-3, 0.0);
  const auto M = shifted({0.01, 0, 0});
  chamber::FlowLoads L;
  for (int i = 0; i < 3; ++i) L = f.step(M, Eigen::Isometry3d::Identity(), {0, 0, -0.5}, {0, 0, -0.6}, 1e-3, 0.0);
  const auto before = f.normal_impulse();
  const int n = 50;
  for (int i = 0; i < n; ++i) f.step(M, Eigen::Isometry3d::Identity(), {0, 0, -0.5}, {0, 0, -0.6}, 1e-3, 0.0);
  int pressed = 0;
  std::vector<double> mean(f.cells());
  for (std::size_t k = 0; k < f.cells(); ++k) {
    mean[k] = (f.normal_impulse()[k] - before[k]) / (n * 1e-3);
    EXPECT_NEAR(mean[k], f.cell_pressure(k) * f.cell_area(k), 1e-9 * (1 + mean[k])) << "cell " << k;
    pressed += mean[k] > 0;
  }
  ASSERT_GT(pressed, 2);
  chamber::ConcaveForceMap map(f, kConcave);
  EXPECT_NEAR(sum(map.map(mean)), L.normal_force, 1e-9 * L.normal_force);
}
