// Ghost exchange of the azimuthal domain decomposition (ghost_domains.hpp) in one process: a charge cut into 1, 2
// and 3 ranks steps like the whole charge in one World (the charge: test/common/pressed_charge.hpp). One rank equals the whole World
// bit for bit; more ranks sum each particle's pair forces in another order (their own neighbour slabs), so they
// agree to round-off, grown over the steps compared (bound below, with the divergence measured when it was set).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "../common/pressed_charge.hpp"
#include "core/binary_io.hpp"
#include "dem/ghost_domains.hpp"
#include "dem/mesh_contact.hpp"
#include "dem/world.hpp"

namespace {

using namespace pressed_charge;

TEST(GhostDomains, OneRankIsTheWholeWorldBitForBit) {
  const Reference ref = reference(kSteps);
  dem::LocalDomains d(state(), params(), walls, 1, kReach);
  d.step(kSteps);
  std::vector<uint64_t> ids;
  std::vector<double> x;
  d.owned_state(ids, x);
  ASSERT_EQ(ids, ref.ids);
  ASSERT_EQ(x.size(), ref.x.size());
  EXPECT_EQ(0, std::memcmp(x.data(), ref.x.data(), x.size() * sizeof(double)));
  EXPECT_EQ(breaks_after_cut(d.breaks()), ref.breaks);
  EXPECT_FALSE(ref.breaks.empty());
}

TEST(GhostDomains, TwoAndThreeRanksStepLikeTheWholeCharge) {
  const Reference ref = reference(kSteps);
  for (int ranks : {2, 3}) {
    SCOPED_TRACE("ranks " + std::to_string(ranks));
    dem::LocalDomains d(state(), params(), walls, ranks, kReach);
    // the boundaries carry contacts and bonds: ghosts on every rank, bonds with their ends on two ranks
    std::size_t cross_bonds = 0;
    for (int r = 0; r < ranks; ++r) {
      const dem::GhostPlan& g = d.plan(r);
      std::size_t ghosts = 0;
      for (const auto& v : g.recv) ghosts += v.size();
      EXPECT_GT(ghosts, 20u);
      for (const dem::Bond& b : d.world(r).bonds()) {
        if (b.alive && g.owned[b.i] && !g.owned[b.j]) ++cross_bonds;
        EXPECT_TRUE(g.owned[b.i] || g.owned[b.j]) << "a bond of two ghosts is kept";  // World::set_ghosts drops them
      }
    }
    EXPECT_GT(cross_bonds, 5u);
    d.step(kSteps);
    EXPECT_LT(d.max_displacement(), d.margin());
    std::vector<uint64_t> ids;
    std::vector<double> x;
    d.owned_state(ids, x);
    ASSERT_EQ(ids, ref.ids);  // every particle owned once
    const double worst = largest_position_difference(x, ref.x);
    // Round-off: 2.5e-17 m after 300 steps (50 bonds broke, 17 and 37 bonds across ranks); without the ghost
    // exchange 6.7e-5 and 1.3e-4 m
    EXPECT_LT(worst, 1e-13) << "largest position difference (m)";
    std::printf("ranks %d: largest position difference %.3g m, largest displacement %.3g m (margin %.3g m), %zu breaks, "
                "%zu cross-rank bonds\n",
                ranks, worst, d.max_displacement(), d.margin(), ref.breaks.size(), cross_bonds);
    EXPECT_EQ(breaks_after_cut(d.breaks()), ref.breaks);
  }
}

TEST(GhostDomains, CutsTheChargeAnewWhenTheMarginIsSpent) {
  // A reach 0.2 mm over the contact distance: a margin of 0.1 mm, spent 8 times in 600 steps (0.9 ms); particles
  // change owner with their state, bonds, contact histories and breaks, by migration (the sectors kept: default
  // tolerance) or by whole re-cuts (tolerance -1: rebalanced every time). Against the whole World the round-off grows
  // as the charge's chaos makes it, with or without re-cuts alike (2 ranks, reach 0.2 or 4 mm over the contact
  // distance: 2.5e-17, 1.9e-15, 4.2e-13, 2.2e-9, 7e-7 m after 300 ... 1500 steps; by then the spins differ by
  // ~15 rad/s and the runs can only be compared as statistics). Compared at 600 steps; one rank bit for bit.
  constexpr long kLong = 600;
  const Reference ref = reference(kLong);
  for (double tolerance : {-1.0, dem::kRebalanceTolerance}) {
    for (int ranks : {1, 2, 3}) {
      SCOPED_TRACE("ranks " + std::to_string(ranks) + ", tolerance " + std::to_string(tolerance));
      dem::LocalDomains d(state(), params(), walls, ranks, 2e-3 + 0.2e-3);
      d.set_rebalance_tolerance(tolerance);
      EXPECT_NEAR(d.margin(), 0.1e-3, 1e-6);  // the largest sphere is within 2 um of 1 mm
      d.step(kLong);
      if (tolerance < 0) {
        EXPECT_GE(d.recuts(), 5);
        EXPECT_EQ(d.migrations(), 0);
      } else {
        EXPECT_GE(d.migrations(), 5);  // the charge hardly moves in azimuth: its sectors stay balanced
      }
      std::vector<uint64_t> ids;
      std::vector<double> x;
      d.owned_state(ids, x);
      ASSERT_EQ(ids, ref.ids);  // every particle owned once after the re-cuts
      const double worst = largest_position_difference(x, ref.x);
      EXPECT_LT(worst, 1e-13) << "largest position difference to the whole World (m)";
      if (ranks == 1) {
        EXPECT_EQ(0, std::memcmp(x.data(), ref.x.data(), x.size() * sizeof(double)));
      }
      EXPECT_EQ(breaks_after_cut(d.breaks()), ref.breaks);
      std::vector<std::pair<uint64_t, uint64_t>> bonds;
      for (int r = 0; r < ranks; ++r) add_intact_bonds(d.world(r), d.plan(r).owned, bonds);
      std::sort(bonds.begin(), bonds.end());
      EXPECT_EQ(bonds, ref.bonds);
      std::printf("ranks %d, %ld steps: %d re-cuts, %d migrations, largest position difference %.3g m, %zu breaks, "
                  "%zu bonds\n",
                  ranks, kLong, d.recuts(), d.migrations(), worst, ref.breaks.size(), ref.bonds.size());
    }
  }
}

TEST(GhostDomains, AMigrationWithoutAPeerThatShouldSendIsRefused) {
  // A bonded pair across the boundary of 2 sectors: rank 0 owns one end, rank 1 the other. Rank 0's migration from
  // its own part alone would lose the bond of the particle it owns: refused, naming it; with rank 1's part it keeps
  // the bond. migration_peers names the rank that sees the particle as a ghost.
  dem::World w(params());
  const double a[3] = {0.02, -0.9e-3, 0}, b[3] = {0.02, 0.9e-3, 0};  // equal-count sectors: bounds at azimuth 0, pi
  const std::size_t i = w.add_particle(a, 1e-3, 0), j = w.add_particle(b, 1e-3, 0);
  dem::BondParams bp;
  bp.kn = 100e9, bp.kt = 40e9, bp.sigma_c = 1e6, bp.tau_c = 1e6;
  ASSERT_EQ(w.bond_pairs({{i, j}}, bp), 1u);
  std::ostringstream os;
  core::BinaryWriter bw(os);
  w.save_state(bw);
  const double reach = 2e-3 + 0.2e-3;
  dem::Domain d0 = dem::cut_charge(os.str(), params(), nullptr, 2, 0, reach);
  dem::Domain d1 = dem::cut_charge(os.str(), params(), nullptr, 2, 1, reach);
  const long a0 = d0.world->index_of(w.particles().id[i]), b0 = d0.world->index_of(w.particles().id[j]);
  ASSERT_GE(a0, 0);
  ASSERT_GE(b0, 0);
  ASSERT_NE(d0.plan.owned[a0], d0.plan.owned[b0]) << "the pair must straddle the boundary";
  const uint64_t mine = w.particles().id[d0.plan.owned[a0] ? i : j];
  EXPECT_EQ(dem::migration_peers(d0, reach), (std::vector<char>{0, 1}));
  EXPECT_EQ(dem::migration_peers(d1, reach), (std::vector<char>{1, 0}));
  try {
    dem::migrate_domain({d0.world.get()}, {d0.plan.owned}, d0, params(), nullptr, reach);
    ADD_FAILURE() << "a migration without its peer was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("particle " + std::to_string(mine) + " lost a bond"), std::string::npos)
        << e.what();
  }
  const dem::Domain n0 =
      dem::migrate_domain({d0.world.get(), d1.world.get()}, {d0.plan.owned, d1.plan.owned}, d0, params(), nullptr,
                          reach);
  EXPECT_EQ(n0.world->n_bonds_intact(), 1u);
  EXPECT_EQ(n0.sectors.bounds(), d0.sectors.bounds());
}

TEST(GhostDomains, ABondedPairThatCrossesASectorBoundaryKeepsItsBond) {
  // 60 free spheres at rest on a ring of 20 mm about the axis set 3 sectors of ~120 deg; a bonded pair flies at 5 m/s
  // along x = 5 mm from y = -10 to +10 mm (126 deg of azimuth, no gravity): it must change owner, keep its bond, and
  // fly as in the whole World
  dem::WorldParams wp = params();
  wp.gravity = {0, 0, 0};
  dem::World w(wp);
  for (int k = 0; k < 60; ++k) {
    const double a = 2 * M_PI * (k + 0.5) / 60, x[3] = {0.02 * std::cos(a), 0.02 * std::sin(a), 0};
    w.add_particle(x, 1e-3, 0);
  }
  const double v[3] = {0, 5, 0}, a[3] = {5e-3, -10e-3, -1e-3}, b[3] = {5e-3, -10e-3, 1e-3};
  const std::size_t i = w.add_particle(a, 1e-3, 0, v), j = w.add_particle(b, 1e-3, 0, v);
  dem::BondParams bp;
  bp.kn = 100e9, bp.kt = 40e9, bp.sigma_c = 1e6, bp.tau_c = 1e6;
  ASSERT_EQ(w.bond_pairs({{i, j}}, bp), 1u);
  const uint64_t id_i = w.particles().id[i];
  std::ostringstream os;
  core::BinaryWriter bw(os);
  w.save_state(bw);
  const std::string ckpt = os.str();
  dem::LocalDomains d(ckpt, wp, nullptr, 3, 2e-3 + 0.2e-3);
  d.set_rebalance_tolerance(1e9);  // the flight unbalances the sectors (21 + 21 + 20 particles): migrate regardless
  std::set<int> owners;
  for (int k = 0; k < 27; ++k) {  // 2700 steps of 1.5 us: 20 mm
    d.step(100);
    w.step(100);
    for (int r = 0; r < 3; ++r) {
      const long at = d.world(r).index_of(id_i);
      if (at >= 0 && d.plan(r).owned[at]) owners.insert(r);
    }
  }
  EXPECT_GE(owners.size(), 2u) << "the pair never changed owner";
  EXPECT_GT(d.migrations(), 10);
  EXPECT_EQ(d.recuts(), 0);
  std::vector<std::pair<uint64_t, uint64_t>> bonds;
  for (int r = 0; r < 3; ++r) add_intact_bonds(d.world(r), d.plan(r).owned, bonds);
  ASSERT_EQ(bonds.size(), 1u);
  EXPECT_EQ(bonds[0].first, id_i);
  std::vector<uint64_t> ids;
  std::vector<double> x, wx;
  d.owned_state(ids, x);
  std::vector<uint32_t> all(w.particles().size());
  for (std::size_t k = 0; k < all.size(); ++k) all[k] = static_cast<uint32_t>(k);
  dem::pack_ghosts(w.particles(), all, wx);
  ASSERT_EQ(x.size(), wx.size());
  EXPECT_LT(largest_position_difference(x, wx), 1e-15);
  EXPECT_NEAR(x[9 * i + 1], 10.25e-3, 1e-6);  // y = -10 mm + 5 m/s x 2700 x 1.5 us = 20.25 mm
}

TEST(GhostDomains, ParticlesAddedAndRemovedBetweenStepsGoToTheirOwners) {
  // every 100 steps the 10 lowest particles leave and 10 new ones take their places (a feed and a discharge,
  // pressed_charge::recycle_lowest), in the whole World and through LocalDomains::edit: the same ids, particle counts
  // and positions (1 rank bit for bit, 2-3 ranks to round-off), breaks the same
  constexpr int kRounds = 5;
  dem::World whole(params());
  walls(whole);
  {
    std::istringstream is(state());
    core::BinaryReader r(is, "test");
    whole.load_state(r);
  }
  for (int k = 0; k < kRounds; ++k) {
    recycle_lowest(whole);
    whole.step(100);
  }
  std::vector<uint64_t> ref_ids(whole.particles().id.begin(), whole.particles().id.end());
  std::vector<uint32_t> all(ref_ids.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = static_cast<uint32_t>(i);
  std::vector<double> ref_x;
  dem::pack_ghosts(whole.particles(), all, ref_x);
  ASSERT_EQ(ref_ids.size(), 500u);
  ASSERT_GT(ref_ids.back(), 499u + 40);  // 50 new ids
  for (int ranks : {1, 2, 3}) {
    SCOPED_TRACE("ranks " + std::to_string(ranks));
    dem::LocalDomains d(state(), params(), walls, ranks, kReach);
    for (int k = 0; k < kRounds; ++k) {
      d.edit(recycle_lowest);
      d.step(100);
    }
    std::vector<uint64_t> ids;
    std::vector<double> x;
    d.owned_state(ids, x);
    ASSERT_EQ(ids, ref_ids);  // the new particles owned once, the removed ones nowhere
    const double worst = largest_position_difference(x, ref_x);
    if (ranks == 1) {
      EXPECT_EQ(worst, 0.0);
    }
    EXPECT_LT(worst, 1e-12) << "largest position difference to the whole World (m)";
    EXPECT_GE(d.recuts(), kRounds);
  }
}

TEST(GhostDomains, ACutRefusesABondLongerThanTheReach) {
  // two spheres bonded across the boundary at azimuth 0, the second 1.2 mm from rank 0's wedge; reach 1 mm
  dem::World w(params());
  const double a[3] = {0.5e-3, 1e-3, 0}, b[3] = {0.5e-3, -1.2e-3, 0};
  w.add_particle(a, 1e-3, 0);
  w.add_particle(b, 1e-3, 0);
  dem::BondParams bp;
  bp.kn = 100e9, bp.kt = 40e9, bp.sigma_c = 1e6, bp.tau_c = 1e6;
  w.bond_pairs({{0, 1}}, bp);
  const dem::SectorDecomposition halves({0.0, M_PI, 2 * M_PI});
  const dem::Particles& p = w.particles();
  const dem::RankLayout layout = dem::rank_layout(halves, p.x.data(), p.y.data(), p.size(), 1e-3);
  ASSERT_EQ(layout.owner, (std::vector<int>{0, 1}));
  try {
    dem::cut_domain(w, layout, 0);
    ADD_FAILURE() << "no refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("shorter than the bond"), std::string::npos) << e.what();
  }
  // with a reach over 1.2 mm the second sphere is rank 0's ghost, sent by rank 1
  const dem::RankLayout wide = dem::rank_layout(halves, p.x.data(), p.y.data(), p.size(), 1.3e-3);
  dem::World w1 = w;
  const dem::GhostPlan g0 = dem::cut_domain(w, wide, 0), g1 = dem::cut_domain(w1, wide, 1);
  EXPECT_EQ(g0.recv[1], (std::vector<uint32_t>{1}));
  EXPECT_EQ(g1.send[0], (std::vector<uint32_t>{1}));
  EXPECT_EQ(g0.owned, (std::vector<char>{1, 0}));
  EXPECT_EQ(w.n_bonds_intact(), 1u);
}

TEST(GhostDomains, ALinerMeshGetsTheWholeChargesWrenchSummedOverTheRanks) {
  // The charge on a floor of 288 triangles: each rank's MeshContact skips its ghosts, so the ranks' wrenches sum to
  // the whole World's (the contacts summed in another order: round-off). With a margin of 0.1 mm the charge is cut
  // anew 8 times in the 600 steps: the mesh's histories are put together with the particles.
  constexpr long kLong = 600;
  const Reference ref = reference(kLong, true);
  ASSERT_LT(ref.plate.force.z(), -0.5 * 500 * 1e-5 * 9.81);  // the charge (~1e-5 kg a sphere) and the lid press on it
  for (int ranks : {1, 2, 3}) {
    for (double reach : {kReach, 2e-3 + 0.2e-3}) {
      SCOPED_TRACE("ranks " + std::to_string(ranks) + ", reach " + std::to_string(reach));
      std::vector<std::shared_ptr<dem::MeshContact>> made;
      dem::LocalDomains d(plate_state(), params(), on_plate(&made), ranks, reach);
      d.step(kLong);
      std::vector<uint64_t> ids;
      std::vector<double> x;
      d.owned_state(ids, x);
      ASSERT_EQ(ids, ref.ids);
      const double worst = largest_position_difference(x, ref.x);
      EXPECT_LT(worst, 1e-12) << "largest position difference to the whole World (m)";  // measured 5.1e-14
      ASSERT_GE(made.size(), static_cast<std::size_t>(ranks));
      Eigen::Vector3d f = Eigen::Vector3d::Zero(), t = Eigen::Vector3d::Zero();
      for (std::size_t k = made.size() - ranks; k < made.size(); ++k) {  // the current cut's Worlds
        const dem::MeshWrench w = made[k]->wrench_about(Eigen::Vector3d::Zero());
        f += w.force, t += w.torque;
      }
      EXPECT_LT((f - ref.plate.force).norm(), 1e-9 * ref.plate.force.norm());
      EXPECT_LT((t - ref.plate.torque).norm(), 1e-9 * ref.plate.force.norm() * kHalf);
      if (reach < kReach) {
        EXPECT_GE(d.recuts() + d.migrations(), 5);
      }
      std::printf("plate, ranks %d, %d re-cuts, %d migrations: position difference %.3g m, force %.6g N (whole %.6g N), difference %.3g N\n",
                  ranks, d.recuts(), d.migrations(), worst, f.z(), ref.plate.force.z(), (f - ref.plate.force).norm());
    }
  }
}

TEST(GhostDomains, AssembleRefusesAParticleOwnedTwiceAndAWrongMask) {
  dem::World a(params()), b(params()), whole(params());
  const double x[3] = {0, 0, 0};
  a.add_particle(x, 1e-3, 0);
  b.add_particle(x, 1e-3, 0);  // the same id 0 in both parts
  try {
    whole.assemble({&a, &b}, {{1}, {1}});
    ADD_FAILURE() << "no refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("owned by two parts"), std::string::npos) << e.what();
  }
  EXPECT_THROW(whole.assemble({&a}, {{1, 0}}), std::invalid_argument);
  whole.assemble({&a, &b}, {{1}, {0}});
  EXPECT_EQ(whole.particles().size(), 1u);
}

}  // namespace

// Two edits with no step between (a coupled chamber's crushing batch and its bookkeeping can fall on one step): a cut
// World's mesh holds histories only of the particles it owns, so the second put-together finds each history once.
// Failed before MeshContact::set_ghosts dropped the ghosts' histories ("a contact history in two parts").
TEST(GhostDomains, TwoEditsWithoutAStepBetweenKeepOneMeshHistoryPerParticle) {
  const Reference ref = reference(kSteps, true);
  std::vector<std::shared_ptr<dem::MeshContact>> made;
  dem::LocalDomains d(plate_state(), params(), on_plate(&made), 3, kReach);
  d.step(kSteps / 2);
  const auto nothing = [](dem::World&) {};
  ASSERT_NO_THROW(d.edit(nothing));
  ASSERT_NO_THROW(d.edit(nothing));
  d.step(kSteps - kSteps / 2);
  std::vector<uint64_t> ids;
  std::vector<double> x;
  d.owned_state(ids, x);
  ASSERT_EQ(ids, ref.ids);
  EXPECT_LT(largest_position_difference(x, ref.x), 1e-12);
}
