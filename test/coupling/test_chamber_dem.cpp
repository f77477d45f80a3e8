#include <gtest/gtest.h>

#include <cmath>

#include "coupling/chamber_dem.hpp"

namespace {

// A small chamber (a 1:4 model of the GYP1200's) fed with 30 mm rocks of ~4 mm metaparticles.
coupling::ChamberParams small_chamber() {
  coupling::ChamberParams p;
  p.chamber.mantle.z = {-0.05, -0.20};
  p.chamber.mantle.r = {0.045, 0.150};
  p.chamber.concave.z = {-0.02, -0.21};
  p.chamber.concave.r = {0.080, 0.175};
  p.mantle_com_z_m = -0.30;
  p.concave_com_z_m = -0.10;
  p.liner_sectors = 36;
  p.threads = 1;
  p.feed.rock_size_m = 0.03;
  p.bpm.metaparticles = rocks::SizeDistribution({{4e-3, 0.4e-3, 1.0}});
  p.feed.choke_height_m = 0.03;
  p.bpm.packing.density = 0.45;  // few coarse spheres per rock cannot reach 0.6 without overlap
  p.feed.max_fed_kg = 0.6;
  p.feed.drop_speed_m_s = 3.0;
  p.bpm.bond.kn = 40e9;  // a tenth of Table 4's stiffness: a 3x longer stable step keeps the test short
  p.bpm.bond.kt = 16e9;
  p.bpm.bond.sigma_c = 25e6;  // Table 4 strengths
  p.bpm.bond.tau_c = 9e6;
  p.bpm.bond.disk_radius = 3.2e-3;  // 0.8 x the 4 mm metaparticle radius
  p.bpm.bond.reference_radius = 4e-3;
  p.discharge_below_m = 0.02;
  return p;
}

coupling::BodyMotion at_rest(double com_z) {
  coupling::BodyMotion b;
  b.com = Eigen::Vector3d(0, 0, com_z);
  return b;
}

}  // namespace

// One run checks the chamber's bookkeeping and the coupling wrench (setting up and filling is the cost).
TEST(ChamberDem, FeedsCrushesAndReportsConsistentWrenchesAndProduct) {
  auto p = small_chamber();
  coupling::ChamberDem dem(p);
  auto m = at_rest(p.mantle_com_z_m), c = at_rest(p.concave_com_z_m);
  // The mantle gyrates: its axis tilted 2 degrees and precessing at 10 Hz about the crusher axis.
  const double w = 2 * M_PI * 10, tilt = 2.0 * M_PI / 180;
  auto gyrate = [&](double t) {
    Eigen::Vector3d axis(std::sin(tilt) * std::cos(w * t), std::sin(tilt) * std::sin(w * t), std::cos(tilt));
    m.orientation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis);
    Eigen::Vector3d axis_dot(-std::sin(tilt) * w * std::sin(w * t), std::sin(tilt) * w * std::cos(w * t), 0);
    m.angular_velocity = axis.cross(axis_dot);
    m.com = m.orientation * Eigen::Vector3d(0, 0, p.mantle_com_z_m);
    m.velocity = m.angular_velocity.cross(m.com);
  };
  Eigen::Vector3d sum_force = Eigen::Vector3d::Zero();
  for (int k = 0; k < 200; ++k) {  // 0.2 s in 1 ms coupling steps
    gyrate(k * 1e-3);
    auto [wm, wc] = dem.advance(m, c, 1e-3);
    ASSERT_TRUE(wm.force.allFinite() && wc.force.allFinite() && wm.torque.allFinite());
    sum_force += wm.force + wc.force;
  }
  auto s = dem.product();
  EXPECT_NEAR(s.fed_kg, 0.6, 0.1);
  EXPECT_GT(dem.world().particles().size(), 100u);
  // Mass balance: fed = in chamber + discharged + lost, to round-off.
  EXPECT_NEAR(s.fed_kg, s.in_chamber_kg + s.discharged_kg + s.lost_kg, 1e-9 * s.fed_kg);
  EXPECT_EQ(s.lost_kg, 0.0);
  // Rock rests on the liners: they carry weight (the particles push down on them).
  EXPECT_LT(sum_force.z(), 0.0);
  for (std::size_t k = 1; k < s.passing_pct.size(); ++k) EXPECT_GE(s.passing_pct[k], s.passing_pct[k - 1]);
  for (double v : s.passing_pct) EXPECT_LE(v, 100.0 + 1e-9);

  // One more DEM step: the averaged concave wrench equals minus the sum of that step's particle reactions.
  dem.reset_force_map();
  gyrate(0.2);
  auto [wm, wc] = dem.advance(m, c, dem.dt());
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), tq = Eigen::Vector3d::Zero();
  for (const auto* mc : {&dem.concave(), &dem.hopper()}) {  // the hopper rides on the fixed cone
    for (const auto& rec : mc->contacts()) {
      f -= rec.force;
      tq -= (rec.point - c.com).cross(rec.force) + rec.roll_torque;
    }
  }
  ASSERT_GT(f.norm(), 0.0) << "no rock touches the concave";
  EXPECT_NEAR((wc.force - f).norm(), 0.0, 1e-9 * f.norm());
  EXPECT_NEAR((wc.torque - tq).norm(), 0.0, 1e-6 * tq.norm() + 1e-9);
  // The force map's areas add up to the concave's total normal force (the hopper is not mapped).
  double map = 0;
  for (double v : dem.force_map()) map += v;
  EXPECT_GT(map, 0.0);
  EXPECT_NEAR(map, dem.concave().total_normal_force(), 1e-9 * map);
}
