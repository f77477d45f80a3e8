// The pressings' scatter (chamber/bed_scatter.hpp): the effective number of lumps against the sum over the lumps,
// the factors' mean and std, a bed's scatter independent of how it is cut into cells (the law's variance
// additivity; a std per cell that ignores the cell's lumps fails it), sigma_1 from replicate pressings, and in the
// flow model: each pressing's factor drawn at its start and held through it, the work booked with it, a resume bit
// for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <sstream>

#include "../common/coaxial_liners.hpp"
#include "../common/flow_params.hpp"
#include "chamber/bed_scatter.hpp"
#include "chamber/flow_model.hpp"
#include "chamber/piston_die.hpp"
#include "core/binary_io.hpp"

namespace {

using test_liners::cylinder;
using test_liners::shifted;

const Eigen::Isometry3d kRest = Eigen::Isometry3d::Identity();
const Eigen::Vector3d kComM(0, 0, -0.5), kComC(0, 0, -0.6);

struct MeanStd {
  double mean = 0, std = 0;
};
MeanStd mean_std(const std::vector<double>& x) {
  MeanStd r;
  for (double v : x) r.mean += v;
  r.mean /= double(x.size());
  for (double v : x) r.std += (v - r.mean) * (v - r.mean);
  r.std = std::sqrt(r.std / double(x.size() - 1));
  return r;
}

}  // namespace

TEST(BedScatter, EffectiveLumpsIsTheMassWeightedSampleSize) {
  // 10 lumps of 0.1 kg and 100 of 0.01 kg: (sum m)^2 / sum m^2 over the lumps themselves.
  std::vector<double> lumps(10, 0.1);
  lumps.insert(lumps.end(), 100, 0.01);
  double s1 = 0, s2 = 0;
  for (double m : lumps) s1 += m, s2 += m * m;
  const std::vector<double> kg{1.0, 1.0}, lump_kg{0.1, 0.01};
  EXPECT_NEAR(chamber::effective_lumps(kg.data(), lump_kg), s1 * s1 / s2, 1e-12);
  const std::vector<double> one{0.7, 0.0};
  EXPECT_NEAR(chamber::effective_lumps(one.data(), lump_kg), 7.0, 1e-12);
  const std::vector<double> sliver{0.05, 0.0}, empty{0.0, 0.0};
  EXPECT_EQ(chamber::effective_lumps(sliver.data(), lump_kg), 1.0);  // lighter than a lump: that lump's scatter
  EXPECT_EQ(chamber::effective_lumps(empty.data(), lump_kg), 0.0);
  EXPECT_NEAR(chamber::bed_pressure_std(0.9, 9.0), 0.3, 1e-15);
  EXPECT_EQ(chamber::bed_pressure_std(0.9, 0.0), 0.0);
  EXPECT_NEAR(chamber::lump_mass(0.02, 2600), 2600 * M_PI / 6 * 8e-6, 1e-15);
}

TEST(BedScatter, FactorsHaveMeanOneAndTheRequestedStd) {
  chamber::ScatterDraws d(3);
  EXPECT_EQ(d.factor(0.0), 1.0);
  const int n = 400000;
  for (double sigma : {0.2, 0.6}) {
    std::vector<double> f(n), lf(n);
    for (int i = 0; i < n; ++i) f[i] = d.factor(sigma), lf[i] = std::log(f[i]);
    const MeanStd a = mean_std(f), b = mean_std(lf);
    EXPECT_NEAR(a.mean, 1.0, 5 * sigma / std::sqrt(double(n))) << sigma;
    EXPECT_NEAR(a.std, sigma, 0.02 * sigma) << sigma;
    EXPECT_NEAR(b.std, std::sqrt(std::log1p(sigma * sigma)), 0.005 * b.std) << sigma;  // lognormal
    EXPECT_GT(*std::min_element(f.begin(), f.end()), 0.0);
  }
  // Reproducible, and a saved state continues the same sequence.
  chamber::ScatterDraws x(11), y(11);
  for (int i = 0; i < 5; ++i) EXPECT_EQ(x.factor(0.5), y.factor(0.5));
  chamber::ScatterDraws z(99);
  ASSERT_TRUE(z.set_state(x.state()));
  for (int i = 0; i < 5; ++i) EXPECT_EQ(x.factor(0.5), z.factor(0.5));
}

// A bed of M kg cut into K equal cells, each pressing with its own factor of std sigma_1 / sqrt(N_eff(M / K)):
// their mean (the bed's load) has std sigma_1 / sqrt(N_eff(M)) whatever K, so the machine's scatter does not depend
// on the model's cells. A std per cell that ignores its lumps gives sigma / sqrt(K) instead.
TEST(BedScatter, ABedsScatterDoesNotDependOnHowItIsCutIntoCells) {
  const double lump_std = 1.2;
  const std::vector<double> lump_kg{0.02, 0.005, 0.001};
  const std::vector<double> bed{0.8, 0.6, 0.4};  // kg per class
  const double n_bed = chamber::effective_lumps(bed.data(), lump_kg);
  const double expect = chamber::bed_pressure_std(lump_std, n_bed);
  chamber::ScatterDraws d(5);
  const int trials = 40000;
  for (int K : {1, 4, 16}) {
    std::vector<double> part(bed);
    for (double& kg : part) kg /= K;
    ASSERT_GT(chamber::effective_lumps(part.data(), lump_kg), 1.0);  // no cell below one lump (the law's floor)
    const double sigma_cell = chamber::bed_pressure_std(lump_std, chamber::effective_lumps(part.data(), lump_kg));
    std::vector<double> load(trials);
    for (int t = 0; t < trials; ++t) {
      double sum = 0;
      for (int c = 0; c < K; ++c) sum += d.factor(sigma_cell);
      load[t] = sum / K;
    }
    const MeanStd s = mean_std(load);
    EXPECT_NEAR(s.mean, 1.0, 5 * expect / std::sqrt(double(trials))) << K << " cells";
    EXPECT_NEAR(s.std, expect, 0.04 * expect) << K << " cells";
  }
}

TEST(BedScatter, LumpStdFromReplicatePressings) {
  // peaks 1, 2, 3: mean 2, sample std 1; beds of 9 lumps: 0.5 x 3.
  EXPECT_NEAR(chamber::lump_std_from_replicates({1.0, 2.0, 3.0}, 9.0), 1.5, 1e-12);
  EXPECT_THROW(chamber::lump_std_from_replicates({1.0}, 9.0), std::invalid_argument);
  // Pourings of a die: each one's deepest loop's peak; the die's N_eff from its feed on the flow sieves (all in the
  // 31.5-40 mm class: M over one lump of that class's size).
  const auto& sv = chamber::flow_sieves_mm();
  std::vector<double> sieves;
  for (double mm : sv) sieves.push_back(mm * 1e-3);
  const chamber::Breakage classes(sieves, chamber::BreakageParams());
  std::size_t j40 = 0;
  while (sv[j40] < 40.0) ++j40;  // class j40 holds (31.5, 40] mm
  std::vector<chamber::PistonDieResult> pourings(3);
  const double peaks[3] = {0.8e6, 1.2e6, 1.0e6};
  for (int i = 0; i < 3; ++i) {
    auto& r = pourings[i];
    r.rock_mass = 2.0, r.solid_density = 2600;
    for (std::size_t k = 0; k < sv.size(); ++k) r.feed_passing.push_back(k < j40 ? 0.0 : 1.0);
    chamber::PressLoop shallow, deep;
    shallow.s_max = 0.15, shallow.p = {0.1e6, 5e6};  // the shallower loop is not the one read
    deep.s_max = 0.3, deep.p = {0.2e6, peaks[i], 0.5e6};
    r.loops = {shallow, deep};
  }
  const double n = 2.0 / chamber::lump_mass(classes.size(j40), 2600);
  EXPECT_NEAR(chamber::die_effective_lumps(pourings[0]), n, 1e-9 * n);
  EXPECT_NEAR(chamber::lump_std_of_pourings(pourings), 0.2 * std::sqrt(n), 1e-9);
  // a pouring pressed deeper (the others blew up there and kept their shallower loops): the peaks are compared at
  // the deepest s_max all completed, not at each one's deepest
  chamber::PressLoop deeper;
  deeper.s_max = 0.42, deeper.p = {0.3e6, 9e6, 0.5e6};
  pourings[1].loops.push_back(deeper);
  double s_common = 0;
  EXPECT_EQ(chamber::common_depth_peaks(pourings, &s_common), std::vector<double>(peaks, peaks + 3));
  EXPECT_EQ(s_common, 0.3);
  EXPECT_NEAR(chamber::lump_std_of_pourings(pourings), 0.2 * std::sqrt(n), 1e-9);
  pourings[2].loops.erase(pourings[2].loops.begin() + 1);  // pressed to 0.15 only: compared at 0.15, all peaks 5 MPa
  EXPECT_NEAR(chamber::lump_std_of_pourings(pourings), 0.0, 1e-12);
}

// One cell pressed twice: each pressing's pressure is the bed law's times a factor drawn when the pressing starts
// and held through it (the same ratio at two depths), the n-th draw of ScatterDraws(seed) with the cell's std; the
// work booked is the factor times the law's loop loss.
TEST(FlowModel, EachPressingHasItsOwnStrengthDrawnAtItsStart) {
  auto p = test_liners::flow_params(6, 8);
  p.material.lump_std = 0.8;
  p.seed = 17;
  chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
  const std::size_t k = 2 * 8 + 0;
  const double g_rest = 0.05, V0 = m.cell_area(k) * g_rest;
  std::vector<double> feed(m.classes(), 0.0);
  feed[m.classes() - 2] = 0.6 * V0 * m.loose_density();
  feed[m.classes() - 4] = 0.4 * V0 * m.loose_density();
  m.deposit(k, feed);
  m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
  std::vector<double> lump_kg;
  for (std::size_t j = 0; j < m.classes(); ++j)
    lump_kg.push_back(chamber::lump_mass(m.breakage().size(j), p.material.solid_density));
  chamber::ScatterDraws draws(17);
  const auto& mat = p.material;
  const double d = 0.012;
  const int n = 2000;
  double booked = 0;
  for (int pressing = 0; pressing < 2; ++pressing) {
    const double sigma = chamber::bed_pressure_std(0.8, chamber::effective_lumps(m.cell_classes(k), lump_kg));
    ASSERT_GT(sigma, 0.1);
    const double f = draws.factor(sigma);
    std::vector<double> ratio;
    for (int i = 1; i <= n; ++i) {
      m.step(shifted({d * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);
      const double s = 1 - m.cell_gap(k) / g_rest;
      if (i == n / 2 || i == n) ratio.push_back(m.cell_pressure(k) / (mat.modulus_Pa * std::pow(s, mat.exponent)));
    }
    const double s = 1 - m.cell_gap(k) / g_rest;
    EXPECT_NEAR(ratio[0], f, 1e-6 * f) << "pressing " << pressing;
    EXPECT_NEAR(ratio[1], f, 1e-6 * f) << "pressing " << pressing;
    for (int i = n - 1; i >= 0; --i) m.step(shifted({d * i / n, 0, 0}), kRest, kComM, kComC, 1e-3, 0.0);
    EXPECT_EQ(m.events(), pressing + 1);
    booked += f * V0 * (1 - mat.rebound) * mat.modulus_Pa * std::pow(s, mat.exponent + 1) / (mat.exponent + 1);
    EXPECT_NEAR(m.crushing_energy_J(), booked, 0.01 * booked) << "pressing " << pressing;
  }
}

TEST(FlowModel, ScatteredPressingsBalanceTheirMassAndResumeBitForBit) {
  const core::Profile mantle = test_liners::gyp_mantle(), concave = test_liners::gyp_concave();
  chamber::FlowParams p = test_liners::cone_chamber_params();
  p.material.lump_std = 1.0;
  chamber::FlowModel m(p, mantle, concave), plain([&] {
    auto q = p;
    q.material.lump_std = 0;
    return q;
  }(), mantle, concave);
  test_liners::nutate({&m, &plain}, 0, 1000);
  const auto resumed = test_liners::resumed(m, p, mantle, concave);
  chamber::FlowModel& copy = *resumed;
  test_liners::nutate({&m, &copy, &plain}, 1000, 2000);
  EXPECT_GT(m.events(), 100);
  EXPECT_NEAR(m.fed_kg(), m.mass_kg() + m.discharged_kg(), 1e-9 * m.fed_kg());
  EXPECT_EQ(m.mass_kg(), copy.mass_kg());
  EXPECT_EQ(m.discharged_by_class(), copy.discharged_by_class());
  EXPECT_EQ(m.crushing_energy_J(), copy.crushing_energy_J());
  EXPECT_NE(m.crushing_energy_J(), plain.crushing_energy_J());  // the scatter acts
  // Another seed is another run: its model refuses the state.
  auto q = p;
  q.seed = 2;
  chamber::FlowModel other(q, mantle, concave);
  std::stringstream again;
  core::BinaryWriter w1(again);
  m.save_state(w1);
  core::BinaryReader r1(again, "flow test checkpoint");
  EXPECT_THROW(other.load_state(r1), std::exception);
}
