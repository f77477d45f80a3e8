// Bonded-particle model (Eq. 20-25) against closed forms: axial stiffness k_bn A / L, cantilever bending vs
// Timoshenko beam theory, breakage at the tensile and shear strengths, momentum of a free bonded cluster,
// and no Hertz-Mindlin between bonded particles; broken bonds dropped in batches give the same run.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <random>
#include <sstream>

#include "core/binary_io.hpp"

#include "dem/world.hpp"

namespace {

dem::WorldParams quiet_params(double dt) {
  dem::WorldParams wp;
  wp.dt = dt;
  wp.gravity = {{0, 0, 0}};
  wp.threads = 1;
  return wp;
}

// A bursting block of n^3 spheres of radius 1 mm (+-10 %) 2 mm apart: velocity grad x index + rand x U(-1, 1) per axis,
// spin x U(-1, 1) per axis when spin > 0.
void add_bursting_block(dem::World& w, int n, double grad, double rand, double spin, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> U(-1, 1);
  const double r = 1e-3;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const double x[3] = {i * 2 * r, j * 2 * r, k * 2 * r};
        const double v[3] = {grad * i + rand * U(rng), grad * j + rand * U(rng), grad * k + rand * U(rng)};
        double om[3] = {0, 0, 0};
        if (spin > 0)
          for (double& c : om) c = spin * U(rng);
        w.add_particle(x, r * (1 + 0.1 * U(rng)), 0, v, om);
      }
}

dem::BondParams table4_bond() {
  dem::BondParams b;
  b.kn = 400e9;  // Table 4
  b.kt = 160e9;
  b.sigma_c = 25e6;
  b.tau_c = 9e6;
  b.radius_multiplier = 1.0;
  return b;
}

// Adds external forces to chosen particles and a viscous drag -c m v, -c I w on all (to reach equilibrium).
struct Loads : dem::Interaction {
  std::vector<std::array<double, 4>> f;  // index, fx, fy, fz
  double drag = 0;
  void add_forces(dem::Particles& p, double, double) override {
    for (auto& a : f) {
      const std::size_t i = static_cast<std::size_t>(a[0]);
      p.fx[i] += a[1]; p.fy[i] += a[2]; p.fz[i] += a[3];
    }
    for (std::size_t i = 0; i < p.size(); ++i) {
      p.fx[i] -= drag * p.m[i] * p.vx[i]; p.fy[i] -= drag * p.m[i] * p.vy[i]; p.fz[i] -= drag * p.m[i] * p.vz[i];
      const double I = 1.0 / p.inv_I[i];
      p.tx[i] -= drag * I * p.wx[i]; p.ty[i] -= drag * I * p.wy[i]; p.tz[i] -= drag * I * p.wz[i];
    }
  }
};

TEST(Bonds, AxialStiffnessIsKnAOverL) {
  const double r = 1e-3, F = 2.0;
  dem::World w(quiet_params(2e-7));
  const double a[3] = {0, 0, 0}, b[3] = {2 * r, 0, 0};
  w.add_particle(a, r, 0);
  w.add_particle(b, r, 0);
  w.particles().fixed[0] = 1;
  dem::BondParams bp = table4_bond();
  bp.damping = 0.5;
  ASSERT_EQ(w.bond_within(1e-9, bp), 1u);
  auto loads = std::make_shared<Loads>();
  loads->f.push_back({1, F, 0, 0});
  w.add_interaction(loads);
  w.step(20000);
  const double L = w.particles().x[1] - w.particles().x[0];
  const double stretch = L - 2 * r;
  const double kn_A = bp.kn * M_PI * r * r;  // Eq. 22-23, A = pi R_b^2
  EXPECT_NEAR(stretch, F / kn_A, 0.01 * F / kn_A);
  EXPECT_LT(std::fabs(w.particles().vx[1]), 1e-6);
}

// Cantilever of N bonds (N + 1 spheres of radius r, L = 2r), particle 0 clamped, tip load P.
// Beam theory (Timoshenko): d = P l^3 / (3 E I) + P l / (G A) with l = N L, E = k_bn L, G = k_bt L,
// I = J/2 = pi R^4 / 4. The discrete chain differs from the continuum by -1/(4 N^2) of the bending part
// (0.25 % for N = 10) and the deflection is small (d/l ~ 1e-3): tolerance 1.5 %. A wrong bending law
// (J instead of J/2, or k_bt for bending) changes d by 40 % to 100 %.
TEST(Bonds, CantileverDeflectionMatchesBeamTheory) {
  const int N = 10;
  const double r = 1e-3, L = 2 * r;
  dem::World w(quiet_params(2e-7));
  for (int k = 0; k <= N; ++k) {
    const double x[3] = {k * L, 0, 0};
    w.add_particle(x, r, 0);
  }
  w.particles().fixed[0] = 1;
  dem::BondParams bp = table4_bond();
  bp.sigma_c = bp.tau_c = 1e12;  // no breakage here
  bp.damping = 0.2;
  ASSERT_EQ(w.bond_within(1e-9, bp), static_cast<std::size_t>(N));
  const double A = M_PI * r * r, I = M_PI * r * r * r * r / 4;
  const double E = bp.kn * L, G = bp.kt * L, l = N * L;
  const double P = 1e-3 * 3 * E * I / (l * l);  // deflection ~1e-3 l
  auto loads = std::make_shared<Loads>();
  loads->f.push_back({static_cast<double>(N), 0, P, 0});
  loads->drag = 2000;
  w.add_interaction(loads);
  w.step(100000);
  const double d = w.particles().y[N];
  const double expect = P * l * l * l / (3 * E * I) + P * l / (G * A);
  EXPECT_NEAR(d, expect, 0.015 * expect);
  EXPECT_LT(std::fabs(w.particles().vy[N]), 1e-4 * expect / 1e-3);
}

// Two particles moved apart at constant speed (prescribed motion): sigma = k_bn v t. The bond must break in
// the first step whose stress reaches sigma_c, i.e. at t* = sigma_c / (k_bn v) or at most one step later.
TEST(Bonds, BreaksAtTensileStrength) {
  const double r = 1e-3, v = 1.0, dt = 1e-8;
  dem::World w(quiet_params(dt));
  const double a[3] = {0, 0, 0}, b[3] = {2 * r, 0, 0}, vb[3] = {v, 0, 0};
  w.add_particle(a, r, 0);
  w.add_particle(b, r, 0, vb);
  w.particles().fixed[0] = w.particles().fixed[1] = 1;
  const dem::BondParams bp = table4_bond();
  w.bond_within(1e-9, bp);
  const double t_star = bp.sigma_c / (bp.kn * v);
  while (w.breaks().empty() && w.time() < 2 * t_star) {
    w.step(1);
    if (w.breaks().empty()) EXPECT_EQ(w.n_bonds_intact(), 1u);
  }
  ASSERT_EQ(w.breaks().size(), 1u);
  const dem::BondBreak& e = w.breaks()[0];
  EXPECT_TRUE(e.tensile);
  EXPECT_GE(e.t, t_star * (1 - 1e-9));
  EXPECT_LE(e.t, t_star + dt * (1 + 1e-6));
  EXPECT_GE(e.sigma, bp.sigma_c);
  EXPECT_EQ(e.id_i, w.particles().id[0]);
  EXPECT_EQ(e.id_j, w.particles().id[1]);
  EXPECT_NEAR(e.x[0], r + 0.5 * v * e.t, 1e-9);
  EXPECT_EQ(w.n_bonds_intact(), 0u);
  w.clear_breaks();
  EXPECT_TRUE(w.breaks().empty());
}

// Particle j moved sideways at speed v without rotation. The shear force stays in the tangent plane while the
// bond axis turns, so |F_t| = k_bt A L asinh(v t / L) and tau = k_bt L asinh(v t / L); it breaks in shear at
// t* = L sinh(tau_c / (k_bt L)) / v, not before and at most one step later.
TEST(Bonds, BreaksAtShearStrength) {
  const double r = 1e-3, L = 2 * r, v = 1.0, dt = 1e-8;
  dem::World w(quiet_params(dt));
  const double a[3] = {0, 0, 0}, b[3] = {L, 0, 0}, vb[3] = {0, v, 0};
  w.add_particle(a, r, 0);
  w.add_particle(b, r, 0, vb);
  w.particles().fixed[0] = w.particles().fixed[1] = 1;
  dem::BondParams bp = table4_bond();
  bp.sigma_c = 1e12;  // isolate the shear criterion
  w.bond_within(1e-9, bp);
  const double t_star = L * std::sinh(bp.tau_c / (bp.kt * L)) / v;
  while (w.breaks().empty() && w.time() < 2 * t_star) w.step(1);
  ASSERT_EQ(w.breaks().size(), 1u);
  const dem::BondBreak& e = w.breaks()[0];
  EXPECT_FALSE(e.tensile);
  EXPECT_GE(e.t, t_star - 0.01 * dt);
  EXPECT_LE(e.t, t_star + dt * 1.01);
  EXPECT_GE(e.tau, bp.tau_c);
}

// After breaking, the pair interacts through Hertz-Mindlin again; while bonded, an overlap gives no Hertz force.
TEST(Bonds, BondedPairsHaveNoHertzContact) {
  const double r = 1e-3;
  dem::World w(quiet_params(1e-7));
  const double a[3] = {0, 0, 0}, b[3] = {2 * r - 2e-5, 0, 0};  // 20 um overlap
  w.add_particle(a, r, 0);
  w.add_particle(b, r, 0);
  dem::BondParams bp = table4_bond();
  w.bond_within(0.0, bp);
  w.step(10);
  EXPECT_EQ(w.particles().fx[1], 0.0);  // bond at its formation length carries nothing, no Hertz
  EXPECT_EQ(w.particles().vx[1], 0.0);
}

TEST(Bonds, HertzAppliesAfterBreakage) {
  const double r = 1e-3, dt = 1e-8;
  dem::World w(quiet_params(dt));
  const double a[3] = {0, 0, 0}, b[3] = {2 * r, 0, 0}, va[3] = {-0.5, 0, 0}, vb[3] = {0.5, 0, 0};
  w.add_particle(a, r, 0, va);
  w.add_particle(b, r, 0, vb);
  dem::BondParams bp = table4_bond();
  bp.sigma_c = 1e5;  // weak: breaks while the pair is still pulling apart
  w.bond_within(1e-9, bp);
  for (int s = 0; s < 200000 && w.breaks().empty(); ++s) w.step(1);
  ASSERT_EQ(w.breaks().size(), 1u);
  // push them together: they must repel (Hertz) and not pass through each other
  w.particles().vx[0] = 0.5;
  w.particles().vx[1] = -0.5;
  double min_gap = 1;
  for (int s = 0; s < 20000; ++s) {
    w.step(1);
    min_gap = std::min(min_gap, w.particles().x[1] - w.particles().x[0] - 2 * r);
  }
  EXPECT_GT(w.particles().vx[1], 0.0);
  EXPECT_GT(min_gap, -0.05 * r);
  EXPECT_LT(min_gap, 0.0);
}

// Free bonded cluster with random velocities and spins, no gravity: linear and angular momentum
// (sum m x x v + I w) are conserved to round-off.
TEST(Bonds, FreeClusterConservesMomentum) {
  dem::WorldParams wp = quiet_params(5e-8);
  wp.threads = 2;
  dem::World w(wp);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  const double r = 1e-3;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 3; ++k) {
        const double rr = r * (1 + 0.2 * U(rng));
        const double x[3] = {i * 2.2 * r, j * 2.2 * r, k * 2.2 * r};
        const double v[3] = {0.05 * U(rng), 0.05 * U(rng), 0.05 * U(rng)}, om[3] = {20 * U(rng), 20 * U(rng), 20 * U(rng)};
        w.add_particle(x, rr, 0, v, om);
      }
  dem::BondParams bp = table4_bond();
  bp.sigma_c = bp.tau_c = 1e12;
  ASSERT_GT(w.bond_within(0.6 * r, bp), 40u);
  auto momenta = [&](double P[3], double Lm[3]) {
    const auto& p = w.particles();
    for (int a = 0; a < 3; ++a) P[a] = Lm[a] = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      P[0] += p.m[i] * p.vx[i]; P[1] += p.m[i] * p.vy[i]; P[2] += p.m[i] * p.vz[i];
      const double I = 1 / p.inv_I[i];
      Lm[0] += p.m[i] * (p.y[i] * p.vz[i] - p.z[i] * p.vy[i]) + I * p.wx[i];
      Lm[1] += p.m[i] * (p.z[i] * p.vx[i] - p.x[i] * p.vz[i]) + I * p.wy[i];
      Lm[2] += p.m[i] * (p.x[i] * p.vy[i] - p.y[i] * p.vx[i]) + I * p.wz[i];
    }
  };
  double P0[3], L0[3], P1[3], L1[3];
  momenta(P0, L0);
  w.step(20000);
  momenta(P1, L1);
  const auto& p = w.particles();
  double pscale = 0, lscale = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    pscale += p.m[i] * 0.05;
    lscale += p.m[i] * 0.05 * 0.01 + 20 / p.inv_I[i];
  }
  for (int a = 0; a < 3; ++a) {
    EXPECT_NEAR(P1[a], P0[a], 1e-10 * pscale);
    EXPECT_NEAR(L1[a], L0[a], 1e-10 * lscale);
  }
  EXPECT_GT(w.kinetic_energy(), 0.0);
}

// Broken bonds stay in the World (alive 0, no force) until they are 1/32 of its bonds, then one compaction drops
// them. A bursting bonded block, 2 threads: every step run A saves its state (which makes it rebuild its neighbour
// list, as a loaded World does) and goes on with its dead bonds; run B goes on from a World loaded from that state,
// which drops them at once. Both must take the same steps bit for bit, while A holds dead bonds (never more than
// 1/32 of its bonds plus the step's own breaks) and compacts them more than once.
TEST(Bonds, BrokenBondsDroppedInBatchesGiveTheSameRun) {
  dem::WorldParams wp = quiet_params(2e-8);
  wp.threads = 2;
  auto a = std::make_unique<dem::World>(wp);
  std::mt19937_64 rng(11);
  const double r = 1e-3;
  add_bursting_block(*a, 8, 0.5, 0.3, 0, rng);
  dem::BondParams bp = table4_bond();
  bp.sigma_c = 2e6;
  bp.tau_c = 1e6;
  const std::size_t nb0 = a->bond_within(0.25 * r, bp);
  ASSERT_GT(nb0, 1000u);
  auto restored = [&](dem::World& from) {  // a World loaded from from's checkpoint: it drops the dead bonds at once
    std::stringstream ss;
    core::BinaryWriter bw(ss);
    from.save_state(bw);
    core::BinaryReader br(ss, "checkpoint");
    auto w = std::make_unique<dem::World>(wp);
    w->load_state(br);
    return w;
  };
  auto b = restored(*a);
  std::size_t held_dead = 0, compactions = 0, last_size = a->bonds().size();
  for (int s = 0; s < 3000; ++s) {
    const std::size_t breaks_before = a->breaks().size();
    a->step(1);
    b->step(1);
    const std::size_t size = a->bonds().size(), dead = size - a->n_bonds_intact();
    const std::size_t new_breaks = a->breaks().size() - breaks_before;
    held_dead = std::max(held_dead, dead);
    ASSERT_LE(32 * (dead - std::min(dead, new_breaks)), size) << "step " << s;
    if (size < last_size) ++compactions;
    last_size = size;
    ASSERT_EQ(a->breaks().size(), b->breaks().size()) << "step " << s;
    const auto &pa = a->particles(), &pb = b->particles();
    for (std::size_t i = 0; i < pa.size(); ++i) {
      ASSERT_EQ(pa.x[i], pb.x[i]) << "step " << s << " particle " << i;
      ASSERT_EQ(pa.vy[i], pb.vy[i]) << "step " << s << " particle " << i;
      ASSERT_EQ(pa.wz[i], pb.wz[i]) << "step " << s << " particle " << i;
    }
    b = restored(*a);  // B restarts from A's state
  }
  EXPECT_GT(a->breaks().size(), nb0 / 10) << "the block must break up";
  EXPECT_GT(held_dead, 0u);
  EXPECT_GE(compactions, 2u);
}

// The bond loop adds each bond's forces straight to its particles, cut into one chunk of bonds per thread; a particle
// with bonds in two chunks gets those after the loop (World::bond_forces). Each particle must still get its terms in
// bond order, so 2 and 3 threads take the steps of 1 thread (no chunks) bit for bit, while the block bursts and its
// bonds break, with two bond strengths (two constant sets). Fails when the deferred terms are added in another order.
TEST(Bonds, ThreadCountsGiveTheSameRunBitForBit) {
  auto run = [](int threads) {
    dem::WorldParams wp = quiet_params(2e-8);
    wp.threads = threads;
    auto w = std::make_unique<dem::World>(wp);
    std::mt19937_64 rng(5);
    const double r = 1e-3;
    add_bursting_block(*w, 11, 0.1, 0.1, 50, rng);
    dem::BondParams bp = table4_bond();
    bp.sigma_c = 3.5e6;
    bp.tau_c = 1.7e6;
    const std::size_t n = w->particles().size();
    w->bond_within(0.25 * r, bp, 0, n / 2);
    bp.sigma_c = 5e6;
    w->bond_within(0.25 * r, bp, n / 2, n);
    return w;
  };
  auto one = run(1), two = run(2), three = run(3);
  ASSERT_GT(one->n_bonds_intact(), 2500u);
  for (int s = 0; s < 8; ++s) {
    one->step(250);
    two->step(250);
    three->step(250);
    for (const dem::World* w : {two.get(), three.get()}) {
      ASSERT_EQ(w->breaks().size(), one->breaks().size()) << "block " << s;
      const auto &a = one->particles(), &b = w->particles();
      for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_EQ(a.x[i], b.x[i]) << "block " << s << " particle " << i << " threads " << w->threads();
        ASSERT_EQ(a.vz[i], b.vz[i]) << "block " << s << " particle " << i;
        ASSERT_EQ(a.wy[i], b.wy[i]) << "block " << s << " particle " << i;
        ASSERT_EQ(a.fx[i], b.fx[i]) << "block " << s << " particle " << i;
        ASSERT_EQ(a.tz[i], b.tz[i]) << "block " << s << " particle " << i;
      }
      const auto &ba = one->bonds(), &bb = w->bonds();
      ASSERT_EQ(ba.size(), bb.size());
      for (std::size_t k = 0; k < ba.size(); ++k) {
        ASSERT_EQ(ba[k].fn, bb[k].fn) << "bond " << k;
        ASSERT_EQ(ba[k].tt[1], bb[k].tt[1]) << "bond " << k;
      }
    }
  }
  EXPECT_GT(one->breaks().size(), 300u) << "the block must break up";
  EXPECT_GT(one->n_bonds_intact(), 1024u) << "still enough bonds for the loop to run in chunks";
}

TEST(Bonds, InvalidParametersAreRejected) {
  dem::World w(quiet_params(1e-7));
  const double a[3] = {0, 0, 0}, b[3] = {2e-3, 0, 0};
  w.add_particle(a, 1e-3, 0);
  w.add_particle(b, 1e-3, 0);
  dem::BondParams bp = table4_bond();
  bp.kn = -1;
  EXPECT_THROW(w.bond_within(1e-9, bp), std::invalid_argument);
  bp = table4_bond();
  EXPECT_THROW(w.bond_pairs({{0, 5}}, bp), std::invalid_argument);
}

}  // namespace
