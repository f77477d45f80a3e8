// Single-particle compression (paper section 2.4.4, Fig. 12) as `calibrate` runs it, and the deep Hertz pinch of a
// fine metaparticle between a coarse one and a platen that stopped it (issue 22: "DEM blow-up at step 9544").
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "core/units.hpp"
#include "dem/materials.hpp"
#include "dem/world.hpp"
#include "rocks/calibration.hpp"
#include "rocks/platen_test.hpp"

using namespace rocks;
using core::units::mm;

namespace {

std::string source(const std::string& rel) { return std::string(CRUSHER_SOURCE_DIR) + "/" + rel; }

// Hertz normal force (Eq. 16 without damping): 4/3 E* sqrt(R*) delta^1.5 of a sphere pair (r2 = 0: a plane).
double hertz(const dem::Material& a, const dem::Material& b, double r1, double r2, double delta) {
  const double E1 = 2 * a.G * (1 + a.nu), E2 = 2 * b.G * (1 + b.nu);
  const double Es = 1.0 / ((1 - a.nu * a.nu) / E1 + (1 - b.nu * b.nu) / E2);
  const double Rs = r2 > 0 ? r1 * r2 / (r1 + r2) : r1;
  return 4.0 / 3.0 * Es * std::sqrt(Rs) * std::pow(delta, 1.5);
}
// Overlap that carries force F (the inverse of hertz).
double hertz_overlap(const dem::Material& a, const dem::Material& b, double r1, double r2, double F) {
  const double unit = hertz(a, b, r1, r2, 1.0);
  return std::pow(F / unit, 2.0 / 3.0);
}

// A fine (r 2 mm) under a coarse sphere (r 5.3 mm) on z between the two steel platens, no bonds: the three contacts
// (platen-fine, fine-coarse, coarse-platen) carry the same force F in series, so the closure is the sum of their
// Hertz overlaps, c(F) = delta_pf(F) + delta_fc(F) + delta_cp(F). Closed to 22 % of the 14.6 mm stack, the
// fine-coarse contact reaches 0.8 of the fine's radius at about 2.6 kN: the metaparticles of the calibrated rocks
// are pinched like this (the 46 mm rock: 1.28 kN at 0.50 r, then up to 0.875 r), which the World's default bound
// (0.5) stopped as a "blow-up" though the state is converged in dt.
TEST(SinglePlatenPinch, FineBetweenCoarseAndPlatenFollowsHertzInSeriesPastHalfItsRadius) {
  const double rf = 2.0 * mm, rc = 5.3 * mm;
  RockPacking stack;
  stack.positions = {Eigen::Vector3d(0, 0, rf), Eigen::Vector3d(0, 0, 2 * rf + rc)};
  stack.radii = {rf, rc};
  dem::BondParams bp;  // no bonds; valid parameters all the same
  bp.kn = 500e9, bp.kt = 200e9, bp.sigma_c = 21e6, bp.tau_c = 13e6;
  PlatenTestOptions o;
  o.closing_speed = 0.4;
  o.max_compression_ratio = 0.22;
  o.record_every = 20;
  o.blowup_dump_path = ::testing::TempDir() + "pinch_blowup.csv";
  std::filesystem::remove(o.blowup_dump_path);
  PlatenTestResult r;
  ASSERT_NO_THROW(r = run_platen_test(stack, bp, o));
  const dem::Material& rock = o.materials.material(0);
  const dem::Material& steel = o.materials.material(1);
  auto closure_of = [&](double F) {
    return hertz_overlap(steel, rock, rf, 0, F) + hertz_overlap(rock, rock, rf, rc, F) + hertz_overlap(rock, steel, rc, 0, F);
  };
  ASSERT_GT(r.closure.size(), 50u);
  double worst = 0;
  for (std::size_t k = r.closure.size() / 4; k < r.closure.size(); ++k) {  // past the first quarter: > 1 kN
    double lo = 0, hi = 1e5;  // F with closure_of(F) = closure (bisection; closure_of rises with F)
    for (int it = 0; it < 100; ++it) (closure_of(0.5 * (lo + hi)) < r.closure[k] ? lo : hi) = 0.5 * (lo + hi);
    worst = std::max(worst, std::abs(r.force[k] / lo - 1.0));
  }
  EXPECT_LT(worst, 0.02) << "platen force against Hertz in series";
  const double deepest = hertz_overlap(rock, rock, rf, rc, r.force.back()) / rf;
  EXPECT_GT(deepest, 0.75);  // the pinch this test is for: well past the old bound of 0.5
  EXPECT_LT(deepest, 0.9);
  EXPECT_FALSE(std::filesystem::exists(o.blowup_dump_path));
  std::printf("pinch: F %.2f kN at closure %.3f mm, fine-coarse overlap %.3f r, worst error %.4f\n",
              r.force.back() * 1e-3, r.closure.back() * 1e3, deepest, worst);
}

// A platen test that does blow up writes its state where it is told (the run's folder) and names the file.
TEST(SinglePlatenPinch, BlowUpDumpGoesWhereTheOptionsSay) {
  const double rf = 2.0 * mm, rc = 5.3 * mm;
  RockPacking stack;
  stack.positions = {Eigen::Vector3d(0, 0, rf), Eigen::Vector3d(0, 0, 2 * rf + rc)};
  stack.radii = {rf, rc};
  dem::BondParams bp;
  bp.kn = 500e9, bp.kt = 200e9, bp.sigma_c = 21e6, bp.tau_c = 13e6;
  PlatenTestOptions o;
  o.closing_speed = 0.4;
  o.max_compression_ratio = 0.22;
  o.max_overlap_fraction = 0.3;  // reached on the way
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "platen_run_dir";
  std::filesystem::create_directories(dir);
  o.blowup_dump_path = (dir / "blowup_pinch.csv").string();
  std::filesystem::remove(o.blowup_dump_path);
  try {
    run_platen_test(stack, bp, o);
    FAIL() << "no blow-up at an overlap bound of 0.3";
  } catch (const dem::BlowUp& e) {
    EXPECT_EQ(e.dump_path, o.blowup_dump_path);
    EXPECT_NE(std::string(e.what()).find("state dump " + o.blowup_dump_path), std::string::npos) << e.what();
    EXPECT_TRUE(std::filesystem::exists(o.blowup_dump_path));
  }
  o.max_overlap_fraction = 1.5;
  EXPECT_THROW(run_platen_test(stack, bp, o), std::invalid_argument);
}

// The four rocks of the shipped calibration, compressed with the shipped calibrated model exactly as `calibrate`
// does: each runs to its end (three of them stopped with a "DEM blow-up" before: fines pinched to 0.5 r), breaks
// bonds and peaks at a force within a factor 2 of the Brazilian disk's 14.5 kN.
TEST(SingleParticle, CalibratedRocksRunToTheirEnd) {
  const CalibrationConfig c = CalibrationConfig::load(source("launch_free_configs/calibration.yaml"));
  BpmModel m = c.base;
  m.bond = load_bpm_model(source("launch_free_configs/bpm_calibrated.yaml")).bond;
  for (int k = 0; k < 4; ++k) {
    const SingleParticleRock rock = single_particle_rock(c, m, k);
    PlatenTestOptions o = single_particle_options(c);
    EXPECT_EQ(o.load_axis, 2);
    EXPECT_DOUBLE_EQ(o.max_compression_ratio, 0.15);
    o.blowup_dump_path = ::testing::TempDir() + "single_particle_blowup_" + std::to_string(k + 1) + ".csv";
    PlatenTestResult r;
    ASSERT_NO_THROW(r = run_platen_test(rock.packing, m.bond.params(), o)) << "rock " << k + 1;
    std::printf("rock %d (%.0f mm): %zu metaparticles, F_c %.3f kN, ccr %.4f, %zu of %zu bonds broken, %ld steps\n",
                k + 1, c.rock_sizes[k] * 1e3, rock.packing.size(), r.peak_force * 1e-3, r.critical_compression_ratio,
                r.bonds_broken, r.bonds_initial, r.steps);
    EXPECT_GT(r.bonds_broken, r.bonds_initial / 10) << "rock " << k + 1;
    EXPECT_GT(r.peak_force, 5e3) << "rock " << k + 1;
    EXPECT_LT(r.peak_force, 30e3) << "rock " << k + 1;
    EXPECT_LE(r.critical_compression_ratio, 0.15 + 1e-9) << "rock " << k + 1;
  }
}

}  // namespace
