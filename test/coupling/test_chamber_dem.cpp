#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "coupling/chamber_dem.hpp"
#include "small_chamber.hpp"

namespace {

using test_chamber::small_chamber;

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
  auto gyrate = [&](double t) { test_chamber::gyrate(p, t, 2.0 * M_PI / 180, &m); };
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
  // Rock rests and is crushed on the liners: overlaps are recorded, small against the radius.
  std::printf("deepest liner overlap %.3f r\n", dem.deepest_liner_overlap());
  EXPECT_GT(dem.deepest_liner_overlap(), 0.0);
  EXPECT_LT(dem.deepest_liner_overlap(), 0.5);
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

// Pre-filled chamber: at t = 0 the chamber holds bonded rocks at rest between the liners, up to the choke
// level, none overlapping another rock or a liner, all counted as fed.
TEST(ChamberDem, PrefillPlacesRocksBetweenTheLinersWithoutOverlap) {
  auto p = small_chamber();
  p.feed.prefill = true;
  p.feed.max_fed_kg = 1e9;
  p.feed.max_rate_kg_s = 0.01;  // no choke feeding on top: only the prefill is checked
  coupling::ChamberDem dem(p);
  auto m = at_rest(p.mantle_com_z_m), c = at_rest(p.concave_com_z_m);
  dem.advance(m, c, dem.dt());  // places the charge at the liners' first pose, then one DEM step
  const auto& P = dem.world().particles();
  const auto s = dem.product();
  ASSERT_GT(P.size(), 0u);
  EXPECT_NEAR(s.fed_kg, dem.prefilled_kg(), 1e-12);
  EXPECT_NEAR(s.fed_kg, s.in_chamber_kg, 1e-9 * s.fed_kg);
  // Nothing touches a liner (a mesh contact is an overlap), nothing lies outside the concave or the hopper
  // above it, below the mantle's lower edge or above the choke level (the liner frames are the world's here).
  for (const auto* mc : {&dem.mantle(), &dem.mantle_cap(), &dem.concave(), &dem.hopper()})
    EXPECT_TRUE(mc->contacts().empty()) << mc->mesh().name() << " touched by prefilled rock";
  const double z_choke = p.chamber.concave.z.front() + p.feed.choke_height_m;
  double z_min = 1e9, v_solid = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double rho = std::hypot(P.x[i], P.y[i]), z = P.z[i], r = P.r[i];
    z_min = std::min(z_min, z);
    v_solid += 4.0 / 3.0 * M_PI * r * r * r;
    EXPECT_LE(z + r, z_choke + 1e-6) << "particle " << i;
    EXPECT_GE(z - r, p.chamber.mantle.z.back() - 1e-6) << "particle " << i;
    EXPECT_LE(rho + r, p.chamber.concave.radius_at(z) + 1e-6) << "particle " << i;
    if (z < p.chamber.mantle.z.front()) {
      EXPECT_GE(rho - r, p.chamber.mantle.radius_at(z) - 1e-6) << "particle " << i;
    }
  }
  // No two rocks overlap (spheres of one rock may, as packed and bonded).
  const auto label = dem.fragment_labels();
  int overlaps = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    for (std::size_t j = i + 1; j < P.size(); ++j) {
      if (label[i] == label[j]) continue;
      const double d = std::sqrt(std::pow(P.x[i] - P.x[j], 2) + std::pow(P.y[i] - P.y[j], 2) + std::pow(P.z[i] - P.z[j], 2));
      if (d < P.r[i] + P.r[j] - 1e-6) ++overlaps;
    }
  EXPECT_EQ(overlaps, 0);
  // Filled bottom up, and densely enough to be a bed: the solid volume is a good part of the chamber's
  // volume between the lowest sphere and the choke level (annulus between the profiles, hopper above).
  double v_chamber = 0;
  const int n = 400;
  for (int k = 0; k < n; ++k) {
    const double z = z_min + (k + 0.5) * (z_choke - z_min) / n;
    const double ro = z > p.chamber.concave.z.front() ? p.chamber.concave.r.front() : p.chamber.concave.radius_at(z);
    const double ri = z > p.chamber.mantle.z.front() ? 0.0 : p.chamber.mantle.radius_at(z);
    v_chamber += M_PI * (ro * ro - ri * ri) * (z_choke - z_min) / n;
  }
  // Rock volume = solid volume / packing density of the rocks' spheres.
  double density = 0;
  for (int k = 0; k < dem.rock_shapes(); ++k) density += dem.packing_density(k) / dem.rock_shapes();
  const double rock_fraction = v_solid / density / v_chamber;
  std::printf("prefill: %.3f kg, %zu particles, lowest sphere at %.1f mm, rock volume fraction %.3f\n", s.fed_kg,
              P.size(), z_min * 1e3, rock_fraction);
  EXPECT_GT(rock_fraction, 0.2);
  // Bottom up: rock reaches down to where the radial gap is narrower than a rock.
  EXPECT_LT(p.chamber.concave.radius_at(z_min) - p.chamber.mantle.radius_at(z_min), p.feed.rock_size_m);
  // Crushing starts at once: the settling charge bears on the liners within a few tens of ms.
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (int k = 0; k < 40; ++k) {
    auto [wm, wc] = dem.advance(m, c, 1e-3);
    if (k >= 20) f += (wm.force + wc.force) / 20.0;
  }
  EXPECT_LT(f.z(), -0.5 * 9.81 * s.fed_kg);
}

// Rock that leaves outside the concave (spilled or thrown out) is lost, not product; rock below the
// discharge inside the concave's bottom edge is screened as product.
TEST(ChamberDem, SpillOutsideTheConcaveIsLostNotProduct) {
  auto p = small_chamber();
  p.feed.max_fed_kg = 1e-9;  // no feed beyond at most one rock
  coupling::ChamberDem dem(p);
  const auto m = at_rest(p.mantle_com_z_m), c = at_rest(p.concave_com_z_m);
  dem.advance(m, c, 1e-3);
  const auto s0 = dem.product();
  const double rock = dem.rock_mass_kg(0);
  dem.add_rock_at(0, Eigen::Vector3d(0.25, 0, -0.10), Eigen::Vector3d::Zero());    // beside the concave, r 0.12 m there
  dem.add_rock_at(0, Eigen::Vector3d(-0.16, 0, -0.28), Eigen::Vector3d::Zero());   // below the discharge, inside r 0.175
  for (int k = 0; k < 10; ++k) dem.advance(m, c, 1e-3);
  const auto s = dem.product();
  EXPECT_NEAR(s.lost_kg - s0.lost_kg, rock, 1e-12);
  EXPECT_NEAR(s.discharged_kg - s0.discharged_kg, rock, 1e-12);
  EXPECT_NEAR(s.fed_kg - s0.fed_kg, 2 * rock, 1e-12);
  EXPECT_NEAR(s.fed_kg, s.in_chamber_kg + s.discharged_kg + s.lost_kg, 1e-9 * s.fed_kg);
  EXPECT_THROW(dem.add_rock_at(99, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero()), std::invalid_argument);
}

// Choke-fed rocks appear above the chamber top between the mantle cap and the hopper: no sphere of a new rock
// may start inside a liner. (The full machine's run once placed a rock 0.74 r into the hopper: its feed circle
// allowed for the rock's nominal size, not for how far an elongated rock's spheres reach.)
TEST(ChamberDem, ChokeFedRocksStartClearOfTheLiners) {
  auto p = small_chamber();
  p.feed.max_fed_kg = 1e9;
  p.feed.max_rate_kg_s = 1e4;    // the feeder keeps the choke zone full: a rock at every free spot
  p.bookkeeping_s = 2e-4;
  p.feed.drop_speed_m_s = 20.0;  // new rocks leave the feed level quickly, making room for more
  coupling::ChamberDem dem(p);
  const auto m = at_rest(p.mantle_com_z_m), c = at_rest(p.concave_com_z_m);
  // Ids added at the end of one step (by the feed) are first stepped, and touch what they were placed in,
  // in the next one.
  auto max_id = [&dem] {
    uint64_t k = 0;
    for (uint64_t id : dem.world().particles().id) k = std::max(k, id + 1);
    return k;
  };
  uint64_t before = 0, after = max_id();
  int placed_rocks = 0, bad = 0;
  double worst = 0;
  const double h = dem.dt();
  for (int step = 0; step < 20000 && placed_rocks < 120; ++step) {
    dem.advance(m, c, h);
    for (const auto* mc : {&dem.mantle(), &dem.mantle_cap(), &dem.concave(), &dem.hopper()})
      for (const auto& rec : mc->contacts())
        if (rec.particle_id >= before && rec.particle_id < after) {
          ++bad;
          worst = std::max(worst, rec.overlap / dem.world().particles().r[rec.particle_index]);
          ADD_FAILURE_AT(__FILE__, __LINE__) << "new particle " << rec.particle_id << " placed " << rec.overlap * 1e3
                                             << " mm inside '" << mc->mesh().name() << "'";
          if (bad > 5) return;
        }
    before = after;
    after = max_id();
    placed_rocks = static_cast<int>(dem.product().fed_kg / dem.rock_mass_kg(0) + 0.5);
  }
  std::printf("%d rocks fed, %d placements inside a liner (deepest %.2f r)\n", placed_rocks, bad, worst);
  EXPECT_GE(placed_rocks, 60);  // enough placements to reach the edges of the feed circle
}
