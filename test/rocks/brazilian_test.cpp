// Brazilian test of a small bonded disk: it must split along the loaded diameter, in tension.
#include <gtest/gtest.h>

#include <cmath>

#include "core/units.hpp"
#include "rocks/platen_test.hpp"
#include "rocks/shape.hpp"

using namespace rocks;
using core::units::mm;

TEST(Brazilian, TensileStrengthEq26) {
  // Section 2.4.2: 14.8 kN on a 50 x 50 mm disk -> 3.77 MPa
  EXPECT_NEAR(brazilian_tensile_strength(14.8e3, 0.05, 0.05), 3.77e6, 0.005e6);
  EXPECT_THROW(brazilian_tensile_strength(1.0, 0.0, 0.05), std::invalid_argument);
}

// A 20 x 6 mm disk of the paper's bimodal mixture scaled by 0.4 (about 1000 metaparticles), bonds
// weak in tension (sigma_bc = 4 MPa) and strong in shear (40 MPa), loaded along z across the
// diameter. A Brazilian split puts the broken bonds in a band around the loaded diameter (the
// vertical mid-plane x = 0); a band |x| < D/6 holds 42 % of a uniform disk's area.
TEST(Brazilian, SmallDiskSplitsAlongLoadedDiameterInTension) {
  const double D = 20 * mm, L = 6 * mm;
  CylinderShape disk(D, L);
  SizeDistribution dist({{1.2 * mm, 0.21 * mm, 0.7}, {0.4 * mm, 0.09 * mm, 0.3}}, 2.0);
  PackingOptions po;
  po.density = 0.58;  // a thin disk: walls keep it below the bulk 0.62
  po.seed = 3;
  po.bond_gap_ratio = 0.1;
  const RockPacking rock = pack_shape(disk, dist, po);
  ASSERT_GT(rock.size(), 500u);
  dem::BondParams bp;
  bp.kt = 160e9;
  bp.kn = 2.5 * bp.kt;
  bp.sigma_c = 4e6;
  bp.tau_c = 40e6;
  bp.radius_multiplier = 1.0;
  PlatenTestOptions o;
  o.closing_speed = 0.2;
  o.max_compression_ratio = 0.06;
  o.threads = 1;
  const PlatenTestResult r = run_platen_test(rock, bp, o);
  ASSERT_GT(r.bonds_broken, 20u);
  std::size_t mid = 0;
  for (const auto& b : r.breaks)
    if (std::abs(b.x[0]) < D / 6) ++mid;
  const double mid_fraction = static_cast<double>(mid) / r.bonds_broken;
  const double tensile_fraction = static_cast<double>(r.tensile_breaks) / r.bonds_broken;
  std::printf("small disk: %zu particles, %zu bonds, peak %.3f kN at closure %.3f mm, %zu broken (%.0f %% tensile, "
              "%.0f %% within |x| < D/6), %ld steps, %.1f s\n",
              rock.size(), r.bonds_initial, r.peak_force * 1e-3, r.peak_closure * 1e3, r.bonds_broken,
              100 * tensile_fraction, 100 * mid_fraction, r.steps, r.wall_s);
  EXPECT_GT(tensile_fraction, 0.7);
  EXPECT_GT(mid_fraction, 0.6);
  EXPECT_GT(r.peak_force, 0.0);
  EXPECT_GT(r.critical_compression_ratio, 0.0);
  EXPECT_LT(r.critical_compression_ratio, 0.06);
  // the recorded curve starts at zero load and peaks at the reported critical force
  double fmax = 0.0;
  for (double f : r.force) fmax = std::max(fmax, f);
  EXPECT_DOUBLE_EQ(fmax, r.peak_force);
}
