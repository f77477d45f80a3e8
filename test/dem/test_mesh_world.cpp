// Integration with demcore's World: a sphere dropped on a translating mesh plane picks up the plane's
// velocity through friction, and behaves like the same drop on World's own planar wall.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "dem/mesh_contact.hpp"
#include "dem/revolution.hpp"
#include "dem/world.hpp"

namespace {

using Eigen::Vector3d;

// Large square (two triangles) in z = 0 of the body frame.
dem::TriMesh belt() {
  return dem::TriMesh({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}, "belt");
}

struct DropResult {
  Vector3d v, w, x;
};

// Rock sphere (r = 5 mm) dropped from 1 mm above a steel floor moving at V along x.
DropResult drop(bool use_mesh, double V, double seconds, bool rolling_friction = true) {
  dem::WorldParams prm;
  prm.dt = 2e-6;
  prm.threads = 1;
  if (!rolling_friction) prm.materials.set_pair(0, 1, 0.7, 0.2, 0.0);
  dem::World world(prm);
  const double r = 0.005;
  const double x0[3] = {0.0, 0.0, r + 1e-3};
  world.add_particle(x0, r, 0);
  std::shared_ptr<dem::MeshContact> mc;
  int wall = -1;
  if (use_mesh) {
    mc = std::make_shared<dem::MeshContact>(belt(), prm.materials, 1);
    mc->set_threads(1);
    world.add_interaction(mc);
  } else {
    const double p0[3] = {0, 0, 0}, n[3] = {0, 0, 1}, v[3] = {V, 0, 0};
    wall = world.add_plane(p0, n, 1);
    world.set_wall_velocity(wall, v);
  }
  const long steps = static_cast<long>(seconds / prm.dt + 0.5);
  for (long s = 0; s < steps; ++s) {
    if (mc) {  // pose and twist at the end of this step's drift (World calls add_forces at t + dt)
      dem::Pose pose;
      pose.position = Vector3d(V * (world.time() + prm.dt), 0, 0);
      dem::Twist tw;
      tw.linear = Vector3d(V, 0, 0);
      mc->set_pose(pose);
      mc->set_twist(tw);
    }
    world.step(1);
  }
  const auto& p = world.particles();
  return {{p.vx[0], p.vy[0], p.vz[0]}, {p.wx[0], p.wy[0], p.wz[0]}, {p.x[0], p.y[0], p.z[0]}};
}

TEST(MeshWorld, SphereOnTranslatingMeshPicksUpTwoSeventhsOfItsSpeed) {
  const double V = 0.4, r = 0.005;
  // Sliding ends when v = w r relative to the floor; angular momentum about the contact point in the
  // floor's frame is conserved: v_final = V - 5/7 V = 2/7 V (solid sphere, I = 2/5 m r^2).
  const DropResult res = drop(true, V, 0.06, false);
  EXPECT_NEAR(res.v.x(), 2.0 / 7.0 * V, 0.01 * V);
  // Rolling without slip relative to the moving floor: v - V = w_y r.
  EXPECT_NEAR(res.v.x() - V, res.w.y() * r, 0.01 * V);
  EXPECT_NEAR(res.v.z(), 0.0, 1e-3);
  EXPECT_NEAR(res.x.z(), r, 2e-5);  // resting on the floor (static overlap ~ micrometres)
  // Without the moving floor nothing happens horizontally.
  const DropResult still = drop(true, 0.0, 0.02, false);
  EXPECT_NEAR(still.v.x(), 0.0, 1e-12);
}

TEST(MeshWorld, MeshFloorMatchesWorldPlanarWall) {
  const double V = 0.3;
  const DropResult a = drop(true, V, 0.03), b = drop(false, V, 0.03);
  EXPECT_NEAR((a.v - b.v).norm(), 0.0, 1e-6 * V + 1e-9);
  EXPECT_NEAR((a.w - b.w).norm(), 0.0, 1e-6 * V / 0.005 + 1e-9);
  EXPECT_NEAR((a.x - b.x).norm(), 0.0, 1e-9);
}

}  // namespace

namespace {

// Particles poured into a revolved bowl settle; the bowl then carries their whole weight: the mesh
// force equals -M g (static balance through many simultaneous face/edge/vertex contacts) and no
// particle leaks through the tessellated surface.
TEST(MeshWorld, SettledBedInABowlWeighsItsMass) {
  dem::WorldParams prm;
  prm.dt = 2e-5;
  prm.threads = 1;
  // Strong rolling friction so the spheres stop rolling round the bowl within the simulated time.
  prm.materials.set_pair(0, 0, 0.5, 0.15, 0.3);
  prm.materials.set_pair(0, 1, 0.7, 0.2, 0.3);
  dem::World world(prm);
  const auto bowl = dem::revolve_profile({{0.0, 0.0}, {0.0, 0.03}, {0.0, 0.05}, {0.1, 0.08}}, 24,
                                         dem::NormalSide::Inward, 0.0, "bowl");
  auto mc = std::make_shared<dem::MeshContact>(bowl, prm.materials, 1);
  mc->set_threads(1);
  world.add_interaction(mc);
  const double r = 0.006;
  int n = 0;
  for (int k = 0; k < 4; ++k)
    for (int i = -3; i <= 3; ++i)
      for (int j = -3; j <= 3; ++j) {
        if (i * i + j * j > 9) continue;
        const double x[3] = {i * 2.2 * r + 1e-4 * k, j * 2.2 * r, 0.012 + k * 2.2 * r};
        world.add_particle(x, r * (1.0 - 0.05 * ((i + j + k) & 1)), 0);
        ++n;
      }
  double M = 0;
  for (double m : world.particles().m) M += m;
  world.step(20000);  // 0.4 s
  const auto w = mc->wrench_about(Vector3d::Zero());
  const auto& p = world.particles();
  double vmax = 0, zmin = 1;
  for (size_t i = 0; i < p.size(); ++i) {
    vmax = std::max(vmax, std::sqrt(p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i]));
    zmin = std::min(zmin, p.z[i]);
  }
  EXPECT_GT(n, 100);
  EXPECT_LT(vmax, 0.02);                      // settled
  EXPECT_GT(zmin, 0.9 * r);                   // nothing sank into or through the bottom
  EXPECT_NEAR(w.force.z(), -M * 9.81, 0.02 * M * 9.81);
  EXPECT_NEAR(std::hypot(w.force.x(), w.force.y()), 0.0, 0.02 * M * 9.81);
  EXPECT_GT(mc->contacts().size(), 20u);
}


// The far-particle skip (MeshContact::set_skin_fraction) leaves the results unchanged, bit for bit: a bowl that
// tilts and spins under a stream of particles, some removed and some added on the way, gives the same motion
// with the skip as without, while most particles are not evaluated at most steps.
TEST(MeshWorld, FarParticleSkipGivesTheSameMotionBitForBit) {
  struct Run {
    std::vector<double> x, y, z;
    Eigen::Vector3d force = Eigen::Vector3d::Zero();
    double evaluated = 0;  // mean share of particles evaluated per step
  };
  auto run = [](double skin_fraction, int threads) {
    dem::WorldParams prm;
    prm.dt = 1e-5;
    prm.threads = threads;
    dem::World world(prm);
    const auto bowl = dem::revolve_profile({{0.0, 0.0}, {0.0, 0.03}, {0.0, 0.05}, {0.1, 0.08}}, 24,
                                           dem::NormalSide::Inward, 0.0, "bowl");
    auto mc = std::make_shared<dem::MeshContact>(bowl, prm.materials, 1);
    mc->set_threads(threads);
    mc->set_skin_fraction(skin_fraction);
    world.add_interaction(mc);
    const double r = 0.005;
    auto layer = [&](double z0, int k) {
      for (int i = -3; i <= 3; ++i)
        for (int j = -3; j <= 3; ++j) {
          if (i * i + j * j > 9) continue;
          const double x[3] = {i * 2.3 * r + 1e-4 * k, j * 2.3 * r, z0 + k * 2.3 * r};
          world.add_particle(x, r * (1.0 - 0.1 * ((i + j + k) & 1)), 0);
        }
    };
    for (int k = 0; k < 6; ++k) layer(0.012, k);
    Run out;
    long steps = 0;
    for (int s = 0; s < 5000; ++s) {
      const double t = s * prm.dt, w = 2 * M_PI * 5, tilt = 0.05;
      const Eigen::Vector3d axis(std::sin(tilt) * std::cos(w * t), std::sin(tilt) * std::sin(w * t), std::cos(tilt));
      dem::Pose pose;
      pose.orientation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis) *
                         Eigen::Quaterniond(Eigen::AngleAxisd(3.0 * t, Eigen::Vector3d::UnitZ()));
      pose.position = Eigen::Vector3d(0.002 * std::sin(w * t), 0, 0);
      mc->set_pose(pose);
      dem::Twist tw;
      tw.linear = Eigen::Vector3d(0.002 * w * std::cos(w * t), 0, 0);
      tw.angular = Eigen::Vector3d(-std::sin(tilt) * w * std::sin(w * t), std::sin(tilt) * w * std::cos(w * t), 3.0);
      mc->set_twist(tw);
      world.step(1);
      out.evaluated += static_cast<double>(mc->evaluated()) / world.particles().size();
      ++steps;
      if (s == 2000) {  // some leave, more arrive on top
        std::vector<uint64_t> ids;
        for (std::size_t i = 3; i < world.particles().size(); i += 11) ids.push_back(world.particles().id[i]);
        world.remove_particles_by_id(ids);
        layer(0.08, 0);
      }
    }
    const auto& p = world.particles();
    out.x.assign(p.x.begin(), p.x.end());
    out.y.assign(p.y.begin(), p.y.end());
    out.z.assign(p.z.begin(), p.z.end());
    out.force = mc->wrench_about(Eigen::Vector3d::Zero()).force;
    out.evaluated /= steps;
    return out;
  };
  const Run plain = run(0.0, 1), skip = run(0.1, 2), skip1 = run(0.1, 1);
  std::printf("particles evaluated per step: %.0f %% with the skip, %.0f %% without\n", 100 * skip.evaluated,
              100 * plain.evaluated);
  EXPECT_EQ(plain.evaluated, 1.0);
  EXPECT_LT(skip.evaluated, 0.6);  // the test means something: many particles were skipped
  EXPECT_GT(plain.force.norm(), 1.0);  // the bed rests on the bowl
  EXPECT_EQ(plain.x, skip.x);
  EXPECT_EQ(plain.y, skip.y);
  EXPECT_EQ(plain.z, skip.z);
  EXPECT_EQ(plain.force, skip.force);
  EXPECT_EQ(skip.x, skip1.x);
}

}  // namespace
