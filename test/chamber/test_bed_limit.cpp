// The bed past its compaction limit held elastically (chamber/bed_limit.hpp, pressure.at_limit: elastic) against
// closed forms: its stiffness is the bed law's own reloading tangent at the limit, a held cell keeps its rock and
// presses by that law, and a loop past the limit and back loses only the bed law's loop (the elastic part nothing).
#include <gtest/gtest.h>

#include <cmath>

#include "../common/coaxial_liners.hpp"
#include "../common/flow_params.hpp"
#include "chamber/bed_limit.hpp"
#include "chamber/flow_model.hpp"
#include "mbd/bed_law.hpp"

namespace {

using test_liners::cylinder;

const Eigen::Isometry3d kRest = Eigen::Isometry3d::Identity();
const Eigen::Vector3d kComM(0, 0, -0.5), kComC(0, 0, -0.6);

}  // namespace

// The locked layer's stiffness is the tangent of bed_hysteretic's unloading branch at the limit (a bed pressed from
// loose to s_max and eased off by a hair), so the pressure is smooth in slope through the limit on reloading.
TEST(BedLimit, TheLockedStiffnessIsTheBedLawsReloadingTangentAtTheLimit) {
  const double E = 18e6, n = 2.87, rebound = 0.1, s_max = 0.53, p_lim = E * std::pow(s_max, n);
  mbd::BedCell c;
  EXPECT_NEAR(mbd::bed_hysteretic(c, s_max, E, n, rebound).p, p_lim, 1e-9 * p_lim);
  const double de = 1e-7, p_below = mbd::bed_hysteretic(c, s_max - de, E, n, rebound).p;
  const double tangent = (p_lim - p_below) / de;  // dp/de on the reloading branch at the limit
  const double eps = 0.01, de_of_eps = (1.0 - s_max) * eps;  // the law's strain for eps of the locked layer
  const double k = chamber::locked_bed_stiffness(n, rebound, s_max, p_lim);
  EXPECT_NEAR(chamber::locked_bed_pressure(eps, k) / de_of_eps, tangent, 1e-5 * tangent);
  EXPECT_EQ(chamber::locked_bed_pressure(0.0, k), 0.0);
  EXPECT_EQ(chamber::locked_bed_pressure(-0.1, k), 0.0);
}

// Coaxial cylinders 50 mm apart, full of loose rock, the mantle moved 30 mm aside and back on one sector: every band
// is pressed from loose to s = 0.6, past s_max = 0.4. Held, no rock leaves while the gap closes; each cell presses by
// E s_max^n (1 + n (1 - s_max) eps / (rebound s_max)), eps = 1 - m_max / m; released, the crushing energy booked is
// the liners' work on the rock and equals the bed law's loss from loose to s_max alone, (1 - rebound) E s_max^(n+1) /
// (n + 1) per loose volume (extruded instead, the work of pressing rock out is booked on top of it).
TEST(BedLimit, HeldRockPressesElasticallyPastTheLimitAndLosesOnlyTheLawsLoop) {
  auto run = [](bool elastic, double* pressure_at_20mm, double* discharged_at_20mm, double* work_out) {
    auto p = test_liners::flow_params(6, 1, true);
    p.material.elastic_limit = elastic;
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
    m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
    const int steps = 3000;
    test_liners::PushAlongX push{m, kComM, kComC};
    for (int i = 1; i <= steps; ++i) push.to(0.030 * i / steps);  // gap 50 -> 20 mm
    *pressure_at_20mm = m.cell_pressure(5);
    *discharged_at_20mm = m.discharged_kg();
    for (int i = steps; i >= 0; --i) push.to(0.030 * i / steps);  // released
    *work_out = push.work;
    EXPECT_GE(m.events(), 6);
    double loose_volume = 0;
    for (std::size_t k = 0; k < m.cells(); ++k) loose_volume += m.cell_area(k) * 0.050;
    return std::make_pair(m.crushing_energy_J(), loose_volume);
  };
  const auto mat = test_liners::flow_params(6, 1).material;
  const double E = mat.modulus_Pa, n = mat.exponent, r = mat.rebound, s = mat.max_compression;
  double p_held, out_held, work_held, p_ext, out_ext, work_ext;
  const auto [energy_held, volume] = run(true, &p_held, &out_held, &work_held);
  const double eps = 1.0 - 0.020 / (0.050 * (1.0 - s));  // m_max / m = g / (g_loose (1 - s_max))
  const double p_expected = E * std::pow(s, n) * (1.0 + n * (1.0 - s) * eps / (r * s));
  EXPECT_NEAR(p_held, p_expected, 1e-9 * p_expected);
  EXPECT_EQ(out_held, 0.0);  // nothing pressed out
  const double loss = (1.0 - r) * E * std::pow(s, n + 1.0) / (n + 1.0) * volume;
  EXPECT_NEAR(energy_held, work_held, 1e-3 * work_held);
  EXPECT_NEAR(energy_held, loss, 2e-3 * loss);

  const auto [energy_ext, volume_ext] = run(false, &p_ext, &out_ext, &work_ext);
  EXPECT_NEAR(p_ext, E * std::pow(s, n), 1e-6 * E);  // extruded: the limit's pressure
  EXPECT_GT(out_ext, 0.0);
  EXPECT_GT(energy_ext, 1.5 * energy_held);  // the work of pressing rock out of the nip
  (void)volume_ext;
}

// With compaction memory the held rock keeps the limit's compaction when released: the first loop from loose is the
// same as without memory (pressure and loss as above), and a second loop to the same gap reloads along the law's
// lossless branch and the locked layer's elastic one, so it books nothing more; without memory the rock is poured loose
// again at the release and the second loop loses as much as the first.
TEST(BedLimit, HeldRockWithCompactionMemoryReloadsWithoutLoss) {
  auto run = [](bool memory, double* p_first, double* energy_first, double* energy_second) {
    auto p = test_liners::flow_params(6, 1, true);
    p.material.elastic_limit = true;
    p.compaction_memory = memory;
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
    m.step(kRest, kRest, kComM, kComC, 1e-3, 0.0);
    const int steps = 3000;
    test_liners::PushAlongX push{m, kComM, kComC};
    for (int loop = 0; loop < 2; ++loop) {
      for (int i = 1; i <= steps; ++i) push.to(0.030 * i / steps);  // gap 50 -> 20 mm
      if (loop == 0) *p_first = m.cell_pressure(5);
      for (int i = steps; i >= 0; --i) push.to(0.030 * i / steps);  // released
      *(loop == 0 ? energy_first : energy_second) = m.crushing_energy_J();
      EXPECT_NEAR(m.crushing_energy_J(), push.work, 1e-3 * push.work);
    }
    EXPECT_EQ(m.discharged_kg(), 0.0);  // held: nothing pressed out
  };
  const auto mat = test_liners::flow_params(6, 1).material;
  const double E = mat.modulus_Pa, n = mat.exponent, r = mat.rebound, s = mat.max_compression;
  double p_mem, first_mem, second_mem, p_forget, first_forget, second_forget;
  run(true, &p_mem, &first_mem, &second_mem);
  run(false, &p_forget, &first_forget, &second_forget);
  const double eps = 1.0 - 0.020 / (0.050 * (1.0 - s));
  const double p_expected = E * std::pow(s, n) * (1.0 + n * (1.0 - s) * eps / (r * s));
  EXPECT_NEAR(p_mem, p_expected, 1e-9 * p_expected);
  EXPECT_NEAR(first_mem, first_forget, 1e-9 * first_forget);
  EXPECT_NEAR(second_mem, first_mem, 1e-3 * first_mem);  // the reload lost nothing
  EXPECT_NEAR(second_forget, 2.0 * first_forget, 2e-3 * first_forget);
}

// Held past the limit is the power law's (with or without compaction memory); the diverging law is refused by name.
TEST(BedLimit, TheElasticLimitIsRefusedWhereItIsNotImplemented) {
  auto p = test_liners::flow_params(4, 4);
  p.material.elastic_limit = true;
  p.material.solid_divergence = true;
  p.material.max_compression = 0.9 * chamber::solid_compaction_limit(p.material.loose_fraction);
  try {
    chamber::FlowModel m(p, cylinder(0.3), cylinder(0.35, -0.8, -0.2));
    FAIL() << "accepted pressure.at_limit elastic with the diverging law";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("pressure.at_limit elastic"), std::string::npos) << e.what();
  }
}
