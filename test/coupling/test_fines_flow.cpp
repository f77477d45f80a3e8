// The retained-fines bed (coupling/fines_bed.hpp) against closed forms: the pressure law on the local gap, action
// and reaction between the liners, the work of a compression loop, nipped fines held and free fines falling, the
// compaction limit.
#include <gtest/gtest.h>

#include <cmath>

#include "coupling/fines_bed.hpp"
#include "../common/coaxial_liners.hpp"
#include "small_chamber.hpp"

namespace {

constexpr double kRho = 2600, kClasses = 3;

using test_liners::cylinder;
using test_liners::shifted;

// Coaxial cylinders: the mantle r = 0.30 m, the concave r = 0.35 m (gap 50 mm), z from -0.8 to -0.2 m.
core::Profile concave_cylinder() { return cylinder(0.35, -0.8, -0.2); }

coupling::FinesBedParams params(int bands, int sectors) {
  coupling::FinesBedParams p;
  p.enabled = true;
  p.bands = bands;
  p.sectors = sectors;
  return p;
}

std::vector<double> in_first_class(double kg) { return {kg, 0.0, 0.0}; }

// The centre of cell (band b, sector s) in the concave frame.
Eigen::Vector3d centre(const coupling::FinesBed& bed, int b, int s, double z_lo, double height, double r) {
  const double a = (s + 0.5) * 2 * M_PI / bed.sectors(), z = z_lo + (b + 0.5) * height / bed.bands();
  return {r * std::cos(a), r * std::sin(a), z};
}

}  // namespace

TEST(FinesBed, RejectsBadParametersByName) {
  auto p = params(4, 8);
  p.bulk_fraction = 1.2;
  try {
    coupling::FinesBed bed(p, cylinder(0.3), concave_cylinder(), kClasses, kRho);
    FAIL() << "accepted bulk_fraction 1.2";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("bulk_fraction"), std::string::npos) << e.what();
  }
}

// Fines in sector 0 only, over-filling the 50 mm gap by a known strain: p = E e^n in every cell of that sector, the
// force p A along the gap's normal on the concave and the opposite on the mantle, with opposite torques.
TEST(FinesBed, PressesTheLinersWithTheBedLawOnTheLocalGap) {
  const int B = 4, S = 8;
  const auto p = params(B, S);
  coupling::FinesBed bed(p, cylinder(0.3), concave_cylinder(), kClasses, kRho);
  const double A = 2 * M_PI * 0.35 * 0.6 / (B * S), rho_b = p.bulk_fraction * kRho, e = 0.1;
  EXPECT_NEAR(bed.cell_area(0), A, 1e-12);
  const double m = rho_b * A * 0.05 / (1 - e);
  for (int b = 0; b < B; ++b) bed.deposit(centre(bed, b, 0, -0.8, 0.6, 0.34), in_first_class(m));
  const Eigen::Vector3d com(0.1, -0.2, 0.3);
  const auto f = bed.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), com, com, 1e-5, 0.0);
  const double pe = p.modulus_Pa * std::pow(e, p.exponent);
  for (int b = 0; b < B; ++b) {
    EXPECT_NEAR(bed.cell_gap(b * S), 0.05, 1e-12);
    EXPECT_NEAR(bed.cell_pressure(b * S), pe, 1e-9 * pe);
    EXPECT_EQ(bed.cell_pressure(b * S + 1), 0.0);
  }
  const Eigen::Vector3d n(std::cos(M_PI / S), std::sin(M_PI / S), 0);
  EXPECT_NEAR((f.f_concave - B * pe * A * n).norm(), 0.0, 1e-9 * B * pe * A);
  EXPECT_NEAR((f.f_mantle + f.f_concave).norm(), 0.0, 1e-9 * f.f_concave.norm());
  EXPECT_NEAR((f.t_mantle + f.t_concave).norm(), 0.0, 1e-9 * f.t_concave.norm());
  EXPECT_NEAR(f.normal_force, B * pe * A, 1e-9 * B * pe * A);
}

// The gap is the distance from the cell's point on the concave to the displaced mantle: |X - c| - r for a cylinder.
TEST(FinesBed, MeasuresTheGapToTheDisplacedMantle) {
  coupling::FinesBed bed(params(2, 6), cylinder(0.3), concave_cylinder(), kClasses, kRho);
  const Eigen::Vector3d d(0.02, 0.01, 0.05);
  bed.step(shifted(d), Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 1e-5, 0.0);
  for (int s = 0; s < 6; ++s) {
    const double a = (s + 0.5) * 2 * M_PI / 6;
    const double expect = std::hypot(0.35 * std::cos(a) - d.x(), 0.35 * std::sin(a) - d.y()) - 0.3;
    EXPECT_NEAR(bed.cell_gap(s), expect, 1e-12) << "sector " << s;
  }
}

// A loop of the mantle moving axially on a cone (gap closing then opening): the work the mantle does on the bed is
// the hysteretic law's loss, (m / rho_bulk) (1 - rebound) E D^(n+1) / (n + 1) per cell, D the largest strain.
TEST(FinesBed, ALoopOfTheGapCostsTheHystereticLoss) {
  core::Profile mantle, concave;
  mantle.z = {-0.9, -0.1};
  mantle.r = {0.6, 0.2};  // 30 deg from the axis: an axial move dz changes the gap by dz sin(alpha)
  concave.z = {-0.8, -0.2};
  concave.r = {0.55 + 0.05 / std::cos(std::atan(0.5)), 0.25 + 0.05 / std::cos(std::atan(0.5))};
  const int S = 8;
  auto p = params(1, S);
  coupling::FinesBed bed(p, mantle, concave, kClasses, kRho);
  const double g0 = 0.05, rho_b = p.bulk_fraction * kRho;
  // Fines that just fill each cell's rest gap (loose), the mantle pressed 4 mm up the cone and back.
  bed.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero(),
           Eigen::Vector3d::Zero(), 1e-5, 0.0);
  EXPECT_NEAR(bed.cell_gap(0), g0, 1e-9);
  double m_total = 0;
  for (int s = 0; s < S; ++s) {
    const double m = rho_b * bed.cell_area(s) * bed.cell_gap(s);
    bed.deposit(centre(bed, 0, s, -0.8, 0.6, 0.4), in_first_class(m));
    m_total += m;
  }
  const int N = 4000;
  const double lift = 0.004;
  double work = 0, z_prev = 0, fz_prev = 0, max_gap_change = 0;
  for (int k = 0; k <= N; ++k) {
    const double z = lift * std::sin(M_PI * k / N);  // up and back down
    const auto f = bed.step(shifted({0, 0, z}), Eigen::Isometry3d::Identity(), Eigen::Vector3d::Zero(),
                            Eigen::Vector3d::Zero(), 1e-5, 0.0);
    if (k > 0) work -= 0.5 * (f.f_mantle.z() + fz_prev) * (z - z_prev);  // trapezoid: work of the mantle on the bed
    z_prev = z, fz_prev = f.f_mantle.z();
    max_gap_change = std::max(max_gap_change, g0 - bed.cell_gap(0));
  }
  const double D = max_gap_change / g0;  // e = 1 - g / g0 for fines that filled the rest gap
  EXPECT_NEAR(D, lift * std::sin(std::atan(0.5)) / g0, 0.02 * D);
  const double loss = m_total / rho_b * (1 - p.rebound) * p.modulus_Pa * std::pow(D, p.exponent + 1) / (p.exponent + 1);
  std::printf("loop: strain %.4f, work on the bed %.2f J, law's loss %.2f J\n", D, work, loss);
  EXPECT_NEAR(work, loss, 0.01 * loss);
}

// Over-full fines at the bottom are nipped and held; once the mantle moves away they fall out under gravity, taking
// the free-fall time from their height, and no mass is lost or made.
TEST(FinesBed, NippedFinesAreHeldAndFreeFinesFallOut) {
  const int B = 12, S = 4;
  const auto p = params(B, S);
  coupling::FinesBed bed(p, cylinder(0.3), concave_cylinder(), kClasses, kRho);
  const double rho_b = p.bulk_fraction * kRho, A = bed.cell_area(0);
  const double m = 1.2 * rho_b * A * 0.05;  // 20 % more than the cell's gap holds loose
  bed.deposit(centre(bed, 0, 0, -0.8, 0.6, 0.34), {0.5 * m, 0.3 * m, 0.2 * m});
  const Eigen::Vector3d o = Eigen::Vector3d::Zero();
  for (int k = 0; k < 2000; ++k) bed.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), o, o, 1e-4, 9.81);
  EXPECT_GT(bed.cell_pressure(0), 0.0);
  EXPECT_NEAR(bed.mass_kg(), m, 1e-12 * m);
  EXPECT_EQ(bed.take_discharged()[0], 0.0);
  // The mantle moved 15 mm away from sector 0: the gap there is 61 mm, more than the 60 mm, the fines are loose and fall.
  double t = 0, out = 0, t_half = -1;
  std::vector<double> classes(3, 0.0);
  while (t < 1.0) {
    bed.step(shifted({-0.015, 0, 0}), Eigen::Isometry3d::Identity(), o, o, 1e-4, 9.81);
    t += 1e-4;
    const auto d = bed.take_discharged();
    for (int c = 0; c < 3; ++c) classes[c] += d[c], out += d[c];
    if (t_half < 0 && out >= 0.5 * m) t_half = t;
  }
  EXPECT_NEAR(out, m, 1e-9 * m);
  EXPECT_NEAR(classes[1], 0.3 * m, 1e-9 * m);  // they leave with their size classes
  // From the middle of the bottom band (25 mm) to its floor: sqrt(2 h / g); upwind transport smears it by ~a band.
  const double t_fall = std::sqrt(2 * 0.025 / 9.81);
  std::printf("half the fines out after %.4f s (free fall %.4f s)\n", t_half, t_fall);
  EXPECT_NEAR(t_half, t_fall, 0.3 * t_fall);
  // From the top band: the fall of 0.575 m.
  coupling::FinesBed top(p, cylinder(0.3), concave_cylinder(), kClasses, kRho);
  top.deposit(centre(top, B - 1, 2, -0.8, 0.6, 0.34), in_first_class(0.5 * m));
  t = 0, out = 0, t_half = -1;
  while (t < 2.0 && t_half < 0) {
    top.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), o, o, 1e-4, 9.81);
    t += 1e-4;
    out += top.take_discharged()[0];
    if (out >= 0.25 * m) t_half = t;
  }
  const double t_top = std::sqrt(2 * 0.575 / 9.81);
  std::printf("from the top band: half out after %.4f s (free fall %.4f s)\n", t_half, t_top);
  EXPECT_NEAR(t_half, t_top, 0.1 * t_top);
}

// A nipped band below stops the fall: the fines pile up above it, and nothing leaves.
TEST(FinesBed, FinesPileUpAboveANippedBand) {
  const int B = 6, S = 1;
  const auto p = params(B, S);
  coupling::FinesBed bed(p, cylinder(0.3), concave_cylinder(), kClasses, kRho);
  const double A = bed.cell_area(0), rho_b = p.bulk_fraction * kRho, full = rho_b * A * 0.05;
  bed.deposit(centre(bed, 0, 0, -0.8, 0.6, 0.34), in_first_class(1.1 * full));  // over-full: nipped
  bed.deposit(centre(bed, 3, 0, -0.8, 0.6, 0.34), in_first_class(0.5 * full));
  const Eigen::Vector3d o = Eigen::Vector3d::Zero();
  for (int k = 0; k < 10000; ++k) bed.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), o, o, 1e-4, 9.81);
  EXPECT_GT(bed.cell_pressure(0), 0.0);
  EXPECT_EQ(bed.take_discharged()[0], 0.0);
  EXPECT_NEAR(bed.cell_mass(0), 1.1 * full, 1e-9 * full);
  EXPECT_NEAR(bed.cell_mass(1), 0.5 * full, 1e-9 * full);  // all of it rests on the nipped band
  EXPECT_NEAR(bed.cell_mass(2) + bed.cell_mass(3), 0.0, 1e-12 * full);
}

// Fines cannot compact past max_strain: as the gap closes, the pressure rises along the law to E max_strain^n and no
// further, the excess flows into the cell below, and out of the chamber from the bottom band, by size class.
TEST(FinesBed, FinesPressedPastTheCompactionLimitAreExtruded) {
  const int B = 3, S = 1;
  const auto p = params(B, S);
  const double cap = p.modulus_Pa * std::pow(p.max_strain, p.exponent), keep = 1.0 / (1.0 - p.max_strain);
  coupling::FinesBed bed(p, cylinder(0.3), concave_cylinder(), kClasses, kRho);
  const double A = bed.cell_area(0), rho_b = p.bulk_fraction * kRho, full = rho_b * A * 0.05;  // loose at 50 mm
  const Eigen::Vector3d o = Eigen::Vector3d::Zero(), X(-0.35, 0, -0.7);  // the sector's point on the concave
  bed.deposit(X, {0.5 * full, 0.3 * full, 0.2 * full});
  // The mantle closes the gap from 50 to 20 mm (no gravity: only the nip moves the fines).
  double p_max = 0, out = 0, out1 = 0;
  for (int k = 0; k <= 1000; ++k) {
    bed.step(shifted({-0.03 * k / 1000.0, 0, 0}), Eigen::Isometry3d::Identity(), o, o, 1e-5, 0.0);
    p_max = std::max(p_max, bed.cell_pressure(0));
    const auto d = bed.take_discharged();
    out += d[0] + d[1] + d[2];
    out1 += d[1];
    if (k == 300) {  // gap 41 mm: e = 0.18, still on the law, nothing extruded yet
      EXPECT_NEAR(bed.cell_pressure(0), p.modulus_Pa * std::pow(1 - 0.041 / 0.05, p.exponent), 1e-6 * cap);
      EXPECT_EQ(out, 0.0);
    }
  }
  EXPECT_NEAR(bed.cell_gap(0), 0.02, 1e-12);
  EXPECT_NEAR(p_max, cap, 1e-9 * cap);
  EXPECT_NEAR(bed.cell_pressure(0), cap, 1e-9 * cap);
  const double held = keep * rho_b * A * 0.02;  // the most the 20 mm gap holds, compacted to the limit
  EXPECT_NEAR(bed.cell_mass(0), held, 1e-9 * full);
  EXPECT_NEAR(out, full - held, 1e-9 * full);
  EXPECT_NEAR(out1, 0.3 * (full - held), 1e-9 * full);  // the extruded fines keep their size classes
  // Higher up, the excess goes to the band below, where it is loose and stays (no gravity): mass is kept.
  coupling::FinesBed up(p, cylinder(0.3), concave_cylinder(), kClasses, kRho);
  const Eigen::Vector3d X2(-0.35, 0, -0.3);  // band 2
  up.deposit(X2, in_first_class(2 * full));
  up.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), o, o, 1e-5, 0.0);
  EXPECT_NEAR(up.cell_pressure(2), cap, 1e-9 * cap);
  EXPECT_NEAR(up.cell_mass(2), keep * full, 1e-9 * full);
  EXPECT_NEAR(up.cell_mass(1), (2 - keep) * full, 1e-9 * full);
  up.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), o, o, 1e-5, 0.0);
  EXPECT_EQ(up.cell_pressure(1), 0.0);
  EXPECT_NEAR(up.mass_kg(), 2 * full, 1e-12 * full);
  EXPECT_EQ(up.take_discharged()[0], 0.0);
}

// In the gyrating small chamber with crushing: the crushed fines stay in the bed and load the liners; mass is
// balanced with the bed counted in the chamber, and what leaves the bed is screened as product. Without the bed
// the same fines leave at once.
TEST(FinesBed, ChamberKeepsCrushedFinesAndBalancesItsMass) {
  auto p = test_chamber::prefilled_small_chamber(0.5, 0.5);
  p.crushing.enabled = true;
  p.crushing.tensile_strength = 0.5e6;
  p.fines_bed = params(8, 12);
  p.fines_bed.bulk_fraction = 0.1;  // loose enough that the few crushed grams fill the bottom's gap within 0.15 s
  auto run = [&](coupling::ChamberDem& dem, double* mean_fines_force) {
    coupling::BodyMotion m, c;
    c.com = Eigen::Vector3d(0, 0, p.concave_com_z_m);
    double sum = 0;
    for (int k = 0; k < 150; ++k) {
      test_chamber::gyrate(p, k * 1e-3, 3.0 * M_PI / 180, &m);
      dem.advance(m, c, 1e-3);
      sum += dem.fines_normal_force();
    }
    if (mean_fines_force) *mean_fines_force = sum / 150;
  };
  coupling::ChamberDem dem(p);
  double fines_force = 0;
  run(dem, &fines_force);
  const auto s = dem.product();
  auto q = p;
  q.fines_bed.enabled = false;
  coupling::ChamberDem no_bed(q);
  run(no_bed, nullptr);
  const auto s0 = no_bed.product();
  std::printf("crushed %.4f kg (%ld); fines bed %.4f kg, discharged %.4f kg (without the bed %.4f kg crushed, %.4f "
              "discharged); mean fines force %.1f N\n", s.crushed_kg, s.metaparticles_crushed, s.fines_bed_kg,
              s.discharged_kg, s0.crushed_kg, s0.discharged_kg, fines_force);
  ASSERT_GT(s.metaparticles_crushed, 0);
  EXPECT_NEAR(s.fed_kg, s.in_chamber_kg + s.discharged_kg + s.lost_kg, 1e-9 * s.fed_kg);
  EXPECT_GT(s.fines_bed_kg, 0.0);
  EXPECT_LE(s.fines_bed_kg, s.crushed_kg + 1e-15);
  EXPECT_EQ(s0.fines_bed_kg, 0.0);
  EXPECT_GE(s0.discharged_kg, s0.crushed_kg - 1e-15);  // without the bed the fines are discharged at once
  EXPECT_GT(fines_force, 0.0);
  // Screening sums to the discharge.
  EXPECT_NEAR(s.passing_pct.back(), s.discharged_kg > 0 ? 100.0 : 0.0, 1e-9);
}

// dem.fines_bed is read with its units and ranges, and refused without the crushing whose fines it keeps.
TEST(FinesBed, ConfigReadsTheBedAndNamesWhatIsWrong) {
  // The shipped max_strain line replaced (a second max_strain key would be refused as a duplicate).
  const auto with_max_strain = [](const std::string& v) {
    std::string text = test_chamber::quick_demo_text();
    const auto at = text.find("    max_strain: 0.35");
    if (at == std::string::npos) throw std::logic_error("quick_demo.yaml has no max_strain 0.35 line");
    text.replace(at, 20, "    max_strain: " + v);
    return test_chamber::chamber_params_of(text);
  };
  const auto p = with_max_strain("0.35");
  EXPECT_FALSE(p.fines_bed.enabled);  // as shipped
  EXPECT_EQ(p.fines_bed.bands, 22);
  EXPECT_DOUBLE_EQ(p.fines_bed.modulus_Pa, 400e6);
  EXPECT_DOUBLE_EQ(p.fines_bed.max_strain, 0.35);
  try {
    with_max_strain("1.5");
    FAIL() << "accepted max_strain 1.5";
  } catch (const core::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("dem.fines_bed.max_strain"), std::string::npos) << e.what();
  }
  // Switched on while dem.crushing is off: a clear error.
  std::string text = test_chamber::quick_demo_text();
  const auto crush = text.find("  crushing:"), bed = text.find("  fines_bed:");
  ASSERT_NE(crush, std::string::npos);
  ASSERT_NE(bed, std::string::npos);
  text.replace(text.find("enabled: false", bed), 14, "enabled: true");
  text.replace(text.find("enabled: true", crush), 13, "enabled: false");
  try {
    test_chamber::chamber_params_of(text);
    FAIL() << "accepted a fines bed without crushing";
  } catch (const core::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("dem.fines_bed.enabled"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("crushing"), std::string::npos) << e.what();
  }
}
