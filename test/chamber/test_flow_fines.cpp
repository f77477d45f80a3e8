// The flow model as the carrier of the coupled run's fines (chamber/flow_model.hpp: fines_only, deposit by position,
// take_discharged; size_classes.hpp): deposits land in the cell holding the point and in the classes the size map
// gives, mass conserved; below the bottom band they are discharged at once; a fines-only model takes no feed; fines
// below the loose capacity of their cell's gap carry no load (the coarse rock carries it), above it the pressure law;
// the state with deposits resumes bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <sstream>

#include "../common/coaxial_liners.hpp"
#include "../common/flow_params.hpp"
#include "chamber/flow_model.hpp"
#include "chamber/size_classes.hpp"
#include "core/binary_io.hpp"

namespace {

using test_liners::cylinder;
using test_liners::shifted;

const Eigen::Isometry3d kRest = Eigen::Isometry3d::Identity();
const Eigen::Vector3d kComM(0, 0, -0.5), kComC(0, 0, -0.6);

double sum(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0); }

// Mantle r = 0.30 m (z -0.9 ... -0.1), concave r = 0.35 m (z -0.8 ... -0.2): cells over z -0.8 ... -0.2, gap 50 mm.
chamber::FlowModel fines_model(int bands, int sectors) {
  return chamber::FlowModel(chamber::fines_only(test_liners::flow_params(bands, sectors)), cylinder(0.3),
                            cylinder(0.35, -0.8, -0.2));
}

}  // namespace

TEST(SizeClassMap, MovesMassByTheOverlapOfTheClassesAndConservesIt) {
  const std::vector<double> dem{1e-3, 4e-3, 16e-3}, flow{1e-3, 2e-3, 4e-3, 8e-3, 16e-3, 31.5e-3};
  const chamber::SizeClassMap same(flow, flow), to(dem, flow), back(flow, dem);
  for (std::size_t i = 0; i < same.to_classes(); ++i)
    for (std::size_t j = 0; j < same.from_classes(); ++j) EXPECT_EQ(same.share(i, j), i == j ? 1.0 : 0.0);
  ASSERT_EQ(to.from_classes(), 4u);
  ASSERT_EQ(to.to_classes(), 7u);
  // The DEM's 1-4 mm class splits into 1-2 and 2-4 mm by their widths (1/3, 2/3); its top class (16 ... 16 sqrt 2 mm)
  // lies inside the flow model's 16-31.5 mm class.
  EXPECT_NEAR(to.share(1, 1), 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(to.share(2, 1), 2.0 / 3.0, 1e-15);
  EXPECT_EQ(to.share(5, 3), 1.0);
  const std::vector<double> kg{0.1, 0.2, 0.3, 0.4};
  const auto f = to.map(kg);
  EXPECT_NEAR(sum(f), 1.0, 1e-15);
  EXPECT_NEAR(f[3] + f[4], 0.3, 1e-15);
  const auto d = back.map(f);
  EXPECT_NEAR(sum(d), 1.0, 1e-15);
  EXPECT_NEAR(d[0], 0.1, 1e-15);  // the pans agree
  EXPECT_EQ(same.map(std::vector<double>(7, 0.5)), std::vector<double>(7, 0.5));
  EXPECT_THROW(to.map(f), std::invalid_argument);  // 7 masses for 4 classes
  EXPECT_THROW(chamber::SizeClassMap({2e-3, 1e-3}, flow), std::invalid_argument);
}

TEST(FlowFines, ADepositLandsInTheCellHoldingItsPointInItsClasses) {
  auto m = fines_model(6, 8);
  const std::size_t C = m.classes();
  double total = 0;
  for (std::size_t k = 0; k < m.cells(); ++k) {
    ASSERT_EQ(m.cell_of(m.cell_point(k)), static_cast<long>(k));
    std::vector<double> kg(C, 0.0);
    kg[k % C] = 1e-3 * (k + 1), kg[(k + 3) % C] = 2e-4;
    m.deposit(m.cell_point(k), kg);
    total += sum(kg);
    for (std::size_t j = 0; j < C; ++j) EXPECT_EQ(m.cell_classes(k)[j], kg[j]) << "cell " << k << " class " << j;
  }
  EXPECT_NEAR(m.mass_kg(), total, 1e-15 * total);
  EXPECT_NEAR(m.fed_kg(), total, 1e-15 * total);
  EXPECT_EQ(m.discharged_kg(), 0.0);
  // A point near a sector's edge and a band's edge: sector s spans [s, s + 1] 45 deg, band b [b, b + 1] 0.1 m.
  const double a = (3 + 0.999) * M_PI / 4;
  EXPECT_EQ(m.cell_of({0.34 * std::cos(a), 0.34 * std::sin(a), -0.8 + 2.001 * 0.1}), 2 * 8 + 3);
  EXPECT_EQ(m.cell_of({0.34, 1e-9, -0.15}), 5 * 8 + 0);  // above the top band: the top band
  EXPECT_EQ(m.cell_of({0.34, 0, -0.8001}), -1);
  std::vector<double> bad(C, 0.0);
  bad[0] = -1;
  EXPECT_THROW(m.deposit(m.cell_point(0), bad), std::invalid_argument);
  EXPECT_THROW(m.deposit(m.cell_point(0), std::vector<double>(C + 1, 0.0)), std::invalid_argument);
}

TEST(FlowFines, ADepositBelowTheBottomBandIsDischargedAtOnce) {
  auto m = fines_model(6, 8);
  std::vector<double> kg(m.classes(), 0.0);
  kg[0] = 0.02, kg[4] = 0.03;
  m.deposit(Eigen::Vector3d(0.33, 0.0, -0.85), kg);
  EXPECT_EQ(m.mass_kg(), 0.0);
  EXPECT_EQ(m.discharged_by_class(), kg);
  EXPECT_NEAR(m.untaken_kg(), 0.05, 1e-15);
  EXPECT_EQ(m.take_discharged(), kg);
  EXPECT_EQ(m.untaken_kg(), 0.0);
  EXPECT_EQ(sum(m.take_discharged()), 0.0);  // taken once
  m.deposit(Eigen::Vector3d(0.33, 0.0, -0.85), kg);
  EXPECT_EQ(m.take_discharged(), kg);         // only what came since
  EXPECT_NEAR(m.fed_kg(), m.mass_kg() + m.discharged_kg(), 1e-15);
  EXPECT_EQ(m.product_compressions(), 0.0);   // never pressed
}

TEST(FlowFines, AFinesOnlyModelTakesNoFeedAndStartsEmpty) {
  auto p = test_liners::flow_params(6, 8, true);
  p.choke_feed = true;
  chamber::FlowModel fed(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  chamber::FlowModel fines(chamber::fines_only(p), cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  for (int i = 0; i < 200; ++i)
    for (auto* m : {&fed, &fines}) m->step(kRest, kRest, kComM, kComC, 1e-3, 9.81);
  EXPECT_GT(fed.fed_kg(), 0.0);  // the same parameters with feed do take it
  EXPECT_EQ(fines.fed_kg(), 0.0);
  EXPECT_EQ(fines.mass_kg(), 0.0);
  EXPECT_EQ(fines.discharged_kg(), 0.0);
}

// The DEM's spheres carry their own load: fines among them fill voids with no force until they alone fill the gap
// (s = 1 - A g rho0 / m <= 0), past it they are pressed along the flow material's law, p = E s^n from a fresh cell.
TEST(FlowFines, FinesBelowTheLooseCapacityOfTheGapCarryNoLoad) {
  auto m = fines_model(6, 8);
  const std::size_t k = 2 * 8 + 0;
  const auto& mat = m.params().material;
  const double A = 2 * M_PI * 0.35 * 0.1 / 8;  // the cell's concave area: 0.1 m band, 45 deg sector at r 0.35 m
  EXPECT_NEAR(m.cell_area(k), A, 1e-12);
  const double cap = A * 0.05 * mat.loose_fraction * mat.solid_density;  // kg of loose fines the 50 mm gap holds
  std::vector<double> kg(m.classes(), 0.0);
  kg[1] = 0.999 * cap;
  m.deposit(m.cell_point(k), kg);
  const auto loads = m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  EXPECT_EQ(m.cell_pressure(k), 0.0);
  EXPECT_EQ(loads.normal_force, 0.0);
  EXPECT_EQ(loads.f_mantle.norm(), 0.0);
  kg[1] = 0.101 * cap;  // now 1.1 x the loose capacity
  m.deposit(m.cell_point(k), kg);
  const auto pressed = m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  const double s = 1 - 1 / 1.1;
  EXPECT_NEAR(m.cell_pressure(k), mat.modulus_Pa * std::pow(s, mat.exponent), 1e-9 * mat.modulus_Pa);
  EXPECT_NEAR(pressed.normal_force, m.cell_pressure(k) * m.cell_area(k), 1e-9 * pressed.normal_force);
  EXPECT_NEAR(pressed.f_mantle.x(), -pressed.normal_force * std::cos(M_PI / 8), 1e-9 * pressed.normal_force);
}

// Fines deposited while the mantle gyrates (some below the bottom band), discharge taken now and then: the state
// saved between steps and restored continues bit for bit.
TEST(FlowFines, StateWithDepositsResumesBitForBit) {
  auto a = fines_model(6, 8);
  std::vector<double> kg(a.classes(), 0.0);
  auto drive = [&](chamber::FlowModel& m, int from, int to, std::vector<double>* taken, std::vector<double>* force) {
    for (int i = from; i < to; ++i) {
      const double w = 2 * M_PI * i / 100.0;
      for (std::size_t j = 0; j < kg.size(); ++j) kg[j] = 1e-2 * (1 + (i + j) % 5);
      m.deposit(Eigen::Vector3d(0.34 * std::cos(0.1 * i), 0.34 * std::sin(0.1 * i), -0.82 + 0.0061 * (i % 100)), kg);
      const auto l = m.step(shifted({0.02 * std::cos(w), 0.02 * std::sin(w), 0}), kRest, kComM, kComC, 1e-3, 9.81);
      force->push_back(l.f_mantle.x()), force->push_back(l.normal_force);
      if (i % 7 == 0) {
        const auto t = m.take_discharged();
        taken->insert(taken->end(), t.begin(), t.end());
      }
    }
  };
  std::vector<double> ta, fa, tb, fb;
  drive(a, 0, 150, &ta, &fa);
  std::stringstream file;
  core::BinaryWriter w(file);
  a.save_state(w);
  auto b = fines_model(6, 8);
  core::BinaryReader r(file, "fines checkpoint");
  b.load_state(r);
  ta.clear(), fa.clear();
  drive(a, 150, 300, &ta, &fa);
  drive(b, 150, 300, &tb, &fb);
  EXPECT_EQ(ta, tb);
  EXPECT_EQ(fa, fb);
  for (std::size_t k = 0; k < a.cells(); ++k)
    for (std::size_t j = 0; j < a.classes(); ++j) ASSERT_EQ(a.cell_classes(k)[j], b.cell_classes(k)[j]);
  EXPECT_EQ(a.discharged_by_class(), b.discharged_by_class());
  EXPECT_EQ(a.untaken_kg(), b.untaken_kg());
  // The test means something: fines were held and pressed, some left the bottom, the balance holds.
  EXPECT_GT(a.mass_kg(), 0.0);
  EXPECT_GT(sum(ta), 0.0);
  double pressed = 0;
  for (std::size_t n = 1; n < fa.size(); n += 2) pressed = std::max(pressed, fa[n]);
  EXPECT_GT(pressed, 0.0);
  std::printf("held %.2f kg, discharged %.2f kg, largest normal force %.0f N\n", a.mass_kg(), a.discharged_kg(), pressed);
  EXPECT_NEAR(a.fed_kg(), a.mass_kg() + a.discharged_kg(), 1e-12 * a.fed_kg());
}

// Fines fall only where the cell below has loose room (Evertsson): above a nipped (pressed) cell they pile up, above
// an empty one they fall through and out of the bottom band.
TEST(FlowFines, FinesPileUpAboveANippedCellAndFallThroughAnOpenOne) {
  auto m = fines_model(6, 8);
  const auto& mat = m.params().material;
  const double cap = m.cell_area(0) * 0.05 * mat.loose_fraction * mat.solid_density;  // loose kg of a cell's gap
  std::vector<double> kg(m.classes(), 0.0);
  kg[1] = 1.2 * cap;
  m.deposit(m.cell_point(0), kg);  // band 0, sector 0: pressed (s = 1 - 1 / 1.2)
  kg[1] = 0.5 * cap;
  m.deposit(m.cell_point(8), kg);  // band 1 above it
  m.deposit(m.cell_point(9), kg);  // band 1, sector 1: the cell below is empty
  for (int i = 0; i < 300; ++i) m.step(kRest, kRest, kComM, kComC, 1e-3, 9.81);
  EXPECT_GT(m.cell_pressure(0), 0.0);
  EXPECT_NEAR(m.cell_mass(0), 1.2 * cap, 1e-12 * cap);  // held while pressed
  EXPECT_NEAR(m.cell_mass(8), 0.5 * cap, 1e-12 * cap);  // no room below: piled up
  EXPECT_LT(m.cell_mass(9), 0.01 * cap);                // fell through (0.1 m bands: 0.14 s each from rest)
  EXPECT_NEAR(m.discharged_kg() + m.cell_mass(1), 0.5 * cap, 0.01 * cap);  // into the band below and out
  EXPECT_GT(m.discharged_kg(), 0.4 * cap);
  EXPECT_NEAR(m.fed_kg(), m.mass_kg() + m.discharged_kg(), 1e-12 * m.fed_kg());
}
