// The azimuthal domain decomposition (dem/sector_decomposition.hpp): owners, ghosts, balance, and the cost model's
// ghost count for a uniform charge.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include "dem/cost_model.hpp"
#include "dem/sector_decomposition.hpp"

namespace {

struct Cloud {
  std::vector<double> x, y, z;
};

// n points in the annulus r1 <= rho <= r2 (area-uniform), 0 <= z <= h, azimuth density 1 + skew cos(phi).
Cloud annulus(std::size_t n, double r1, double r2, double h, double skew, unsigned seed) {
  std::mt19937_64 g(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Cloud c;
  while (c.x.size() < n) {
    const double phi = 2 * M_PI * u(g);
    if (u(g) * (1 + std::abs(skew)) > 1 + skew * std::cos(phi)) continue;  // rejection
    const double rho = std::sqrt(r1 * r1 + u(g) * (r2 * r2 - r1 * r1));
    c.x.push_back(rho * std::cos(phi));
    c.y.push_back(rho * std::sin(phi));
    c.z.push_back(h * u(g));
  }
  return c;
}

bool holds(const dem::RankLayout& L, int rank, uint32_t i) {
  const auto& o = L.owned[rank];
  const auto& g = L.ghosts[rank];
  return std::binary_search(o.begin(), o.end(), i) || std::binary_search(g.begin(), g.end(), i);
}

TEST(SectorDecomposition, BalancedWedgesSplitASkewedChargeEvenly) {
  const Cloud c = annulus(10007, 0.2, 0.7, 0.5, 0.8, 1);  // twice as dense on one side as on the other
  for (int P : {1, 2, 3, 5, 8, 16}) {
    const auto d = dem::balanced_sectors(c.x.data(), c.y.data(), c.x.size(), P);
    const auto L = dem::rank_layout(d, c.x.data(), c.y.data(), c.x.size(), 0.02);
    std::size_t total = 0, lo = c.x.size(), hi = 0;
    for (int r = 0; r < P; ++r) {
      total += L.owned[r].size();
      lo = std::min(lo, L.owned[r].size());
      hi = std::max(hi, L.owned[r].size());
      for (uint32_t i : L.owned[r]) EXPECT_EQ(L.owner[i], r);
    }
    EXPECT_EQ(total, c.x.size()) << P;
    EXPECT_LE(hi - lo, 1u) << P << " ranks";
  }
  // The dense side gets narrower wedges: with 8 ranks the wedge holding azimuth 0 is the narrowest.
  const auto d = dem::balanced_sectors(c.x.data(), c.y.data(), c.x.size(), 8);
  const int r0 = d.owner(1.0, 0.0), rpi = d.owner(-1.0, 0.0);
  EXPECT_LT(d.bounds()[r0 + 1] - d.bounds()[r0], 0.7 * (d.bounds()[rpi + 1] - d.bounds()[rpi]));
}

TEST(SectorDecomposition, DistanceToAWedgeIsTheDistanceToItsNearestPoint) {
  // Wedges of 60, 150 and 240 degrees; the distance against the nearest of a fine polar grid of the wedge's points.
  const dem::SectorDecomposition d({0.3, 0.3 + M_PI / 3, 0.3 + M_PI / 3 + 5 * M_PI / 6, 0.3 + 2 * M_PI});
  std::mt19937_64 g(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int t = 0; t < 300; ++t) {
    const double x = u(g), y = u(g);
    for (int r = 0; r < 3; ++r) {
      double best = std::hypot(x, y);  // the axis belongs to every wedge
      const double a0 = d.bounds()[r], a1 = d.bounds()[r + 1];
      for (int i = 0; i <= 800; ++i) {
        const double a = a0 + (a1 - a0) * i / 800.0;
        const double along = std::max(0.0, x * std::cos(a) + y * std::sin(a));  // nearest point on that ray
        best = std::min(best, std::hypot(x - along * std::cos(a), y - along * std::sin(a)));
      }
      // grid step: 240 deg / 800 at radius <= 1.5 m -> <= 8 mm of arc
      EXPECT_NEAR(d.distance(r, x, y), best, 8e-3) << "point (" << x << ", " << y << "), wedge " << r;
      EXPECT_LE(d.distance(r, x, y), best + 1e-12);
    }
  }
}

TEST(SectorDecomposition, EveryPairWithinReachIsCompleteOnItsOwnersRank) {
  // A contact or bond (i, j) closer than the reach is computed by i's owner: j must be there, owned or a ghost.
  const Cloud c = annulus(2500, 0.05, 0.4, 0.2, 0.5, 3);  // reaching close to the axis, where wedges are thin
  const double reach = 0.04;
  for (int P : {2, 3, 7, 12}) {
    const auto d = dem::balanced_sectors(c.x.data(), c.y.data(), c.x.size(), P);
    const auto L = dem::rank_layout(d, c.x.data(), c.y.data(), c.x.size(), reach);
    long pairs = 0, across = 0;
    for (uint32_t i = 0; i < c.x.size(); ++i)
      for (uint32_t j = 0; j < c.x.size(); ++j) {
        if (i == j) continue;
        const double dist = std::hypot(std::hypot(c.x[i] - c.x[j], c.y[i] - c.y[j]), c.z[i] - c.z[j]);
        if (dist >= reach) continue;
        ++pairs;
        across += L.owner[i] != L.owner[j];
        ASSERT_TRUE(holds(L, L.owner[i], j)) << P << " ranks: pair " << i << ", " << j << " at " << dist << " m";
      }
    EXPECT_GT(pairs, 10000) << P;
    EXPECT_GT(across, 100) << P;  // the boundaries are crossed: the check has something to check
    // Each ghost is within the reach of its rank's wedge, and owned elsewhere.
    for (int r = 0; r < P; ++r)
      for (uint32_t i : L.ghosts[r]) {
        EXPECT_NE(L.owner[i], r);
        EXPECT_LT(d.distance(r, c.x[i], c.y[i]), reach);
      }
  }
}

TEST(SectorDecomposition, GhostsOfAUniformChargeAreTheCostModelsCount) {
  // Uniform annulus 0.3-0.7 m: the band of width w beside a boundary holds N w (r2 - r1) / (pi (r2^2 - r1^2)) =
  // N w / (2 pi r_m), r_m = 0.5 m, on each side; a rank sees two boundaries.
  const std::size_t n = 200000;
  const Cloud c = annulus(n, 0.3, 0.7, 0.5, 0.0, 11);
  const double w = 0.02;
  dem::CostModelInputs in;
  in.particles = n;
  in.dt_s = 1e-6;
  in.core_s_per_particle_step = 1e-7;
  in.ghost_width_m = w;
  in.mean_radius_m = 0.5;
  const double per_boundary = dem::cost_model(in, 8).ghosts_per_boundary;
  EXPECT_NEAR(per_boundary, n * w / (M_PI), 1e-6);  // 1273
  const auto d = dem::balanced_sectors(c.x.data(), c.y.data(), n, 8);
  const auto L = dem::rank_layout(d, c.x.data(), c.y.data(), n, w);
  for (int r = 0; r < 8; ++r)  // Poisson scatter of ~2550: 2 %; 6 % is 3 sigma
    EXPECT_NEAR(static_cast<double>(L.ghosts[r].size()), 2 * per_boundary, 0.06 * 2 * per_boundary) << "rank " << r;
}

TEST(SectorDecomposition, OneRankOwnsAllAndBadBoundsAreRefused) {
  const Cloud c = annulus(100, 0.1, 0.2, 0.1, 0.0, 5);
  const auto L = dem::rank_layout(dem::balanced_sectors(c.x.data(), c.y.data(), 100, 1), c.x.data(), c.y.data(), 100,
                                  0.5);
  EXPECT_EQ(L.owned[0].size(), 100u);
  EXPECT_TRUE(L.ghosts[0].empty());
  EXPECT_THROW(dem::SectorDecomposition({0.0}), std::invalid_argument);
  EXPECT_THROW(dem::SectorDecomposition({0.0, 1.0, 0.5, 2 * M_PI}), std::invalid_argument);
  EXPECT_THROW(dem::SectorDecomposition({0.0, 1.0, 6.0}), std::invalid_argument);  // not one turn
  EXPECT_THROW(dem::balanced_sectors(c.x.data(), c.y.data(), 100, 0), std::invalid_argument);
  // More ranks than particles: still ascending wedges, every particle owned once.
  const auto d = dem::balanced_sectors(c.x.data(), c.y.data(), 3, 8);
  EXPECT_EQ(d.ranks(), 8);
  const auto L3 = dem::rank_layout(d, c.x.data(), c.y.data(), 3, 0.01);
  std::size_t owned = 0;
  for (const auto& o : L3.owned) owned += o.size();
  EXPECT_EQ(owned, 3u);
}

}  // namespace
