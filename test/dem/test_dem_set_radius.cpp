// World::set_radius: a sphere that grows (a crushed rock's fragment taking its parent's volume) keeps its mass,
// finds the neighbours and mesh triangles it grows into without a rebuild at every step, and is refused a radius
// the time step cannot carry.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "dem/mesh_contact.hpp"
#include "dem/world.hpp"

namespace {

// Two 1 mm rock spheres 0.6 mm apart (three skins of 0.2 mm) at rest; sphere 0 grows from 1.0 to 1.7 mm over
// 2000 steps (so into its neighbour), then both move for 1000 more. Reference: the list rebuilt at every step.
struct Grown {
  double x1 = 0, v1 = 0;
  long rebuilds = 0;
};
Grown grow_into_neighbour(bool rebuild_every_step) {
  dem::WorldParams wp;
  wp.dt = 2e-8;
  wp.gravity = {{0, 0, 0}};
  wp.threads = 1;
  dem::World w(wp);
  const double r = 1e-3, a[3] = {0, 0, 0}, b[3] = {2 * r + 0.6e-3, 0, 0};
  w.add_particle(a, r, 0);
  w.add_particle(b, r, 0);
  for (int s = 0; s < 3000; ++s) {
    if (s < 2000) w.set_radius(0, r * (1.0 + 0.7 * (s + 1) / 2000.0));
    if (rebuild_every_step) w.invalidate_neighbors();
    w.step(1);
  }
  return {w.particles().x[1], w.particles().vx[1], w.n_rebuilds()};
}

// A World with one 2 mm rock sphere at the origin, stepping at dt.
std::unique_ptr<dem::World> one_sphere(double dt) {
  dem::WorldParams wp;
  wp.dt = dt;
  auto w = std::make_unique<dem::World>(wp);
  const double x[3] = {0, 0, 0};
  w->add_particle(x, 2e-3, 0);
  return w;
}

}  // namespace

TEST(SetRadius, KeepsTheMassAndSetsTheMomentOfInertia) {
  auto owner = one_sphere(1e-7);
  dem::World& w = *owner;
  const double m = w.particles().m[0];
  w.set_radius(0, 3e-3);
  EXPECT_EQ(w.particles().m[0], m);
  EXPECT_DOUBLE_EQ(w.particles().r[0], 3e-3);
  EXPECT_NEAR(w.particles().inv_I[0] * 0.4 * m * 9e-6, 1.0, 1e-12);
}

TEST(SetRadius, AGrowingSphereFindsTheNeighbourItGrowsInto) {
  const Grown ref = grow_into_neighbour(true), g = grow_into_neighbour(false);
  std::printf("neighbour pushed to x = %.6f mm at %.4f m/s (reference %.6f mm, %.4f m/s); rebuilds %ld vs %ld\n",
              1e3 * g.x1, g.v1, 1e3 * ref.x1, ref.v1, g.rebuilds, ref.rebuilds);
  ASSERT_GT(ref.v1, 0.01);  // the test means something: the growth pushed the neighbour away
  EXPECT_NEAR(g.x1, ref.x1, 1e-12);
  EXPECT_NEAR(g.v1, ref.v1, 1e-9 * std::abs(ref.v1) + 1e-15);
  EXPECT_LT(g.rebuilds, ref.rebuilds / 10);
}

TEST(SetRadius, AGrowingSphereFindsTheMeshItGrowsInto) {
  // 1 mm sphere 0.5 mm above a mesh floor (beyond the mesh contact's skin of 0.1 x the largest radius); it grows to
  // 1.6 mm and must bounce. A 3 mm sphere far away sets the largest radius, as the parents do for fragments.
  dem::WorldParams wp;
  wp.dt = 2e-8;
  wp.gravity = {{0, 0, 0}};
  wp.threads = 1;
  dem::World w(wp);
  auto mc = std::make_shared<dem::MeshContact>(
      dem::TriMesh({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}, "floor"), wp.materials, 1);
  mc->set_threads(1);
  w.add_interaction(mc);
  const double x[3] = {0, 0, 1.5e-3};
  w.add_particle(x, 1e-3, 0);
  const double far_away[3] = {0.5, 0.5, 0.01};
  w.add_particle(far_away, 3e-3, 0);
  for (int s = 0; s < 100; ++s) w.step(1);  // the mesh contact marks the sphere far from every triangle
  for (int s = 0; s < 2000; ++s) {
    w.set_radius(0, 1e-3 * (1.0 + 0.6 * (s + 1) / 2000.0));
    w.step(1);
  }
  std::printf("after growing into the floor: z = %.4f mm, vz = %.4f m/s\n", 1e3 * w.particles().z[0],
              w.particles().vz[0]);
  EXPECT_GT(w.particles().vz[0], 0.01);
  EXPECT_GT(w.particles().z[0], 1.5e-3);
}

TEST(SetRadius, RefusesARadiusTheTimeStepCannotCarry) {
  auto owner = one_sphere(1e-6);
  dem::World& w = *owner;
  // 2 mm rock: Rayleigh step ~1e-5 s at its density. At 100x the radius the density falls 1e6x: step ~1e-6 s x 0.1
  try {
    w.set_radius(0, 0.2);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("Rayleigh"), std::string::npos) << e.what();
  }
  EXPECT_DOUBLE_EQ(w.particles().r[0], 2e-3);  // unchanged
  EXPECT_THROW(w.set_radius(0, 0.0), std::invalid_argument);
  EXPECT_THROW(w.set_radius(1, 1e-3), std::invalid_argument);
}
