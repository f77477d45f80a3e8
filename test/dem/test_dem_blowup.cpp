// Numerical blow-up (DESIGN.md "Failure behaviour"): World::step stops with dem::BlowUp naming the step, the
// particle and a CSV state dump when a contact overlap exceeds the bound or a state becomes non-finite.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>

#include "dem/mesh_contact.hpp"
#include "dem/world.hpp"

namespace {

std::string fresh_dump(const std::string& name) {
  const std::string p = ::testing::TempDir() + "dem_blowup_" + name + ".csv";
  std::remove(p.c_str());
  return p;
}

dem::WorldParams params(const std::string& dump, int threads = 1) {
  dem::WorldParams wp;
  wp.dt = 1e-7;
  wp.gravity = {{0, 0, 0}};
  wp.threads = threads;
  wp.blowup_dump_path = dump;
  return wp;
}

std::vector<std::string> lines(const std::string& path) {
  std::ifstream f(path);
  std::vector<std::string> out;
  for (std::string l; std::getline(f, l);) out.push_back(l);
  return out;
}

bool has(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Steps w until it throws BlowUp and returns that; a run without one fails the test (empty BlowUp returned).
dem::BlowUp blow_up_of(dem::World& w, long steps) {
  try {
    w.step(steps);
  } catch (const dem::BlowUp& e) {
    return e;
  }
  ADD_FAILURE() << "no BlowUp in " << steps << " steps";
  return dem::BlowUp("no BlowUp", -1, 0, 0.0, "");
}

TEST(BlowUp, OverlapBeyondTheBoundStopsWithStepParticleAndDump) {
  const std::string dump = fresh_dump("overlap");
  dem::World w(params(dump));
  const double r = 1e-3, a[3] = {0, 0, 0}, b[3] = {1.1 * r, 0, 0};  // overlap 0.9 r
  w.add_particle(a, r, 0);
  w.add_particle(b, r, 0);
  const dem::BlowUp e = blow_up_of(w, 5);
  const std::string m = e.what();
  EXPECT_EQ(e.step, 1);
  EXPECT_EQ(e.id, 0u);
  EXPECT_NEAR(e.overlap, 0.9, 1e-9);
  EXPECT_EQ(e.dump_path, dump);
  EXPECT_TRUE(has(m, "step 1")) << m;
  EXPECT_TRUE(has(m, "particle id 0")) << m;
  EXPECT_TRUE(has(m, "overlap with particle id 1 is 0.9")) << m;
  EXPECT_TRUE(has(m, "max_overlap_fraction")) << m;
  EXPECT_TRUE(has(m, dump)) << m;
  const auto L = lines(dump);
  ASSERT_EQ(L.size(), 3u);
  EXPECT_EQ(L[0].rfind("id,x,y,z,vx,vy,vz,", 0), 0u) << L[0];
  EXPECT_EQ(L[1].rfind("0,0,0,0,", 0), 0u) << L[1];
  EXPECT_EQ(L[2].rfind("1,0.0011", 0), 0u) << L[2];
}

// Without a dump path the dump is a new file of an unguessable name in the temporary folder, one per blow-up (a fixed
// name there, such as the old dem_blowup_<pid>.csv, could be a planted link to a file the run would overwrite).
TEST(BlowUp, WithoutADumpPathEachDumpIsANewUnguessableFile) {
  namespace fs = std::filesystem;
  const fs::path tmp = fs::temp_directory_path();
  const std::string fixed = (tmp / ("dem_blowup_" + std::to_string(::getpid()) + ".csv")).string();
  std::remove(fixed.c_str());
  std::vector<std::string> dumps;
  for (int k = 0; k < 2; ++k) {
    dem::World w(params(""));
    const double r = 1e-3, a[3] = {0, 0, 0}, b[3] = {1.1 * r, 0, 0};
    w.add_particle(a, r, 0);
    w.add_particle(b, r, 0);
    const dem::BlowUp e = blow_up_of(w, 5);
    ASSERT_FALSE(e.dump_path.empty()) << e.what();
    EXPECT_TRUE(has(e.what(), "state dump " + e.dump_path)) << e.what();
    EXPECT_EQ(fs::path(e.dump_path).parent_path(), tmp) << e.dump_path;
    const std::string name = fs::path(e.dump_path).filename().string();
    EXPECT_EQ(name.rfind("dem_blowup_", 0), 0u) << name;
    EXPECT_EQ(name.size(), std::string("dem_blowup_XXXXXX.csv").size()) << name;
    EXPECT_EQ(lines(e.dump_path).size(), 3u);
    dumps.push_back(e.dump_path);
  }
  EXPECT_NE(dumps[0], dumps[1]);
  EXPECT_FALSE(fs::exists(fixed)) << fixed;
  for (const auto& d : dumps) std::remove(d.c_str());
}

TEST(BlowUp, SmallOverlapRunsAndDisabledBoundIsNotChecked) {
  const double r = 1e-3, a[3] = {0, 0, 0}, b[3] = {1.98 * r, 0, 0}, c[3] = {1.1 * r, 0, 0};
  dem::World ok(params(fresh_dump("small")));
  ok.add_particle(a, r, 0);
  ok.add_particle(b, r, 0);
  EXPECT_NO_THROW(ok.step(20));
  dem::WorldParams wp = params(fresh_dump("off"));
  wp.max_overlap_fraction = 0;
  dem::World off(wp);
  off.add_particle(a, r, 0);
  off.add_particle(c, r, 0);
  EXPECT_NO_THROW(off.step(1));
}

TEST(BlowUp, NanVelocityStopsWithTheParticle) {
  const std::string dump = fresh_dump("nan");
  dem::World w(params(dump));
  const double r = 1e-3;
  for (int k = 0; k < 3; ++k) {
    const double x[3] = {3 * r * k, 0, 0};
    w.add_particle(x, r, 0);
  }
  w.step(10);
  w.particles().vy[1] = std::numeric_limits<double>::quiet_NaN();
  const dem::BlowUp e = blow_up_of(w, 5);
  const std::string m = e.what();
  EXPECT_EQ(e.step, 11);
  EXPECT_EQ(e.id, 1u);
  EXPECT_TRUE(std::isnan(e.overlap));
  EXPECT_TRUE(has(m, "step 11")) << m;
  EXPECT_TRUE(has(m, "particle id 1")) << m;
  EXPECT_TRUE(has(m, "non-finite")) << m;
  const auto L = lines(dump);
  ASSERT_EQ(L.size(), 4u);
  EXPECT_TRUE(has(L[2], "nan")) << L[2];
  EXPECT_FALSE(has(L[1], "nan")) << L[1];
}

// An extra force term (Interaction) that returns an infinite force: caught by the closing half kick.
struct InfiniteForce : dem::Interaction {
  long calls = 0;
  void add_forces(dem::Particles& p, double, double) override {
    if (++calls == 3) p.fx[1] = std::numeric_limits<double>::infinity();
  }
};

TEST(BlowUp, InfiniteForceIsCaughtAtTheEndOfTheStep) {
  dem::World w(params(fresh_dump("inf")));
  const double r = 1e-3;
  for (int k = 0; k < 2; ++k) {
    const double x[3] = {3 * r * k, 0, 0};
    w.add_particle(x, r, 0);
  }
  w.add_interaction(std::make_shared<InfiniteForce>());
  const dem::BlowUp e = blow_up_of(w, 10);
  EXPECT_EQ(e.step, 3);
  EXPECT_EQ(e.id, 1u);
  EXPECT_TRUE(has(e.what(), "non-finite")) << e.what();
}

TEST(BlowUp, WallOverlapBeyondTheBound) {
  dem::World w(params(fresh_dump("wall")));
  const double r = 1e-3, o[3] = {0, 0, 0}, up[3] = {0, 0, 1}, x[3] = {0, 0, 0.1 * r};
  w.add_plane(o, up, 0);
  w.add_particle(x, r, 0);
  const dem::BlowUp e = blow_up_of(w, 1);
  EXPECT_TRUE(has(e.what(), "overlap with wall 0 is 0.9")) << e.what();
  EXPECT_NEAR(e.overlap, 0.9, 1e-9);
}

// Many particles on two threads (the parallel pair loop): the first offending pair in list order is named.
TEST(BlowUp, ParallelPairLoopNamesTheOffendingParticle) {
  dem::World w(params(fresh_dump("par"), 2));
  const double r = 1e-3, s = 2.1 * r;
  for (int k = 0; k < 2000; ++k) {
    const double x[3] = {s * (k % 20), s * ((k / 20) % 20), s * (k / 400)};
    w.add_particle(x, r, 0);
  }
  w.step(2);
  ASSERT_GT(w.n_pairs(), 2000u);
  auto& p = w.particles();
  p.x[1234] = p.x[1233] + 1.2 * r;  // 0.8 r into its neighbour in x
  w.invalidate_neighbors();
  const dem::BlowUp e = blow_up_of(w, 1);
  EXPECT_EQ(e.id, 1233u) << e.what();
  EXPECT_TRUE(has(e.what(), "overlap with particle id 1234 is 0.8")) << e.what();
}

// A 2 m square steel floor in the plane z = 0 (material 1).
std::shared_ptr<dem::MeshContact> floor_mesh(const dem::World& w) {
  return std::make_shared<dem::MeshContact>(
      dem::TriMesh({{-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}, "floor"), w.materials(), 1);
}

TEST(BlowUp, OverlapWithAMeshStopsAndNamesTheMesh) {
  const std::string dump = fresh_dump("mesh");
  dem::WorldParams wp = params(dump);
  wp.max_mesh_overlap_fraction = 0.5;
  dem::World w(wp);
  const double r = 1e-3;
  w.add_interaction(floor_mesh(w));
  const double ok[3] = {0.01, 0, 0.8 * r}, deep[3] = {0, 0, 0.3 * r};  // overlaps 0.2 r and 0.7 r
  w.add_particle(ok, r, 0);
  w.add_particle(deep, r, 0);
  const dem::BlowUp e = blow_up_of(w, 1);
  const std::string m = e.what();
  EXPECT_EQ(e.id, 1u);
  EXPECT_NEAR(e.overlap, 0.7, 1e-6);
  EXPECT_TRUE(has(m, "overlap with mesh 'floor' is 0.7")) << m;
  EXPECT_TRUE(has(m, "max_mesh_overlap_fraction")) << m;
  EXPECT_EQ(lines(dump).size(), 3u);  // header + 2 particles
  // The default mesh bound (1: centre on the surface) lets the squeezed sphere run.
  dem::World w2(params(fresh_dump("mesh_ok")));
  w2.add_interaction(floor_mesh(w2));
  w2.add_particle(deep, r, 0);
  EXPECT_NO_THROW(w2.step(1));
}

}  // namespace
