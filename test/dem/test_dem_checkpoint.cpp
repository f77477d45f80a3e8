// Checkpoint/restart of dem::World (world.hpp: save_state / load_state): a run that saves its state and goes
// on, and a fresh World loaded from that state, take bitwise identical steps, on 1 and 2 threads and across
// thread counts. The scene exercises every piece of carried state: bonded clusters that break (bond springs,
// break log, bonded pairs joining the contact list), spheres sliding and sticking on each other (pair
// histories), side walls, one of them moving (wall state and histories), and a translating, turning
// triangle-mesh belt under the bed (MeshContact histories and hand-over between triangles). Damaged files
// fail with std::runtime_error naming the problem.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/binary_io.hpp"
#include "dem/mesh_contact.hpp"
#include "dem/world.hpp"

namespace {

using Eigen::Vector3d;

constexpr double kV = 0.3;      // belt speed along x, m/s
constexpr double kOmega = 2.0;  // belt spin about z, rad/s
constexpr double kBox = 0.03;   // side walls at 0 and kBox in x and y, m
constexpr std::size_t kSceneFileBytes = 264313;  // TheFileKeepsItsBytes
constexpr uint64_t kSceneFileHash = 0x7dd225a5e918fb59ull;

// Square belt in z = 0 of the body frame, [-0.02, 0.05]^2, cut into a 14 x 14 grid of squares (392 triangles),
// so sliding contacts cross edges and vertices.
dem::TriMesh belt() {
  const int m = 14;
  const double lo = -0.02, hi = 0.05, h = (hi - lo) / m;
  std::vector<Vector3d> v;
  std::vector<dem::Triangle> t;
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i <= m; ++i) v.emplace_back(lo + i * h, lo + j * h, 0.0);
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const int a = j * (m + 1) + i, b = a + 1, c = a + m + 2, d = a + m + 1;
      t.push_back({a, b, c});
      t.push_back({a, c, d});
    }
  return dem::TriMesh(v, t, "belt");
}

struct Scene {
  std::unique_ptr<dem::World> w;
  std::shared_ptr<dem::MeshContact> mc;
};

// Walls and the mesh always; the particles and bonds only with `populate` (load_state replaces them anyway).
Scene make_scene(int threads, bool populate = true) {
  dem::WorldParams wp;
  wp.dt = 2e-6;
  wp.threads = threads;
  Scene s;
  s.w = std::make_unique<dem::World>(wp);
  dem::World& w = *s.w;
  const double o[3] = {0, 0, 0}, e[3] = {kBox, kBox, 0};
  const double nx[3] = {1, 0, 0}, mx[3] = {-1, 0, 0}, ny[3] = {0, 1, 0}, my[3] = {0, -1, 0};
  w.add_plane(o, nx, 1);
  w.add_plane(e, mx, 1);  // the belt drags the bed against this one
  w.add_plane(o, ny, 1);
  const int moving = w.add_plane(e, my, 1);
  const double vin[3] = {0, -0.3, 0};
  w.set_wall_velocity(moving, vin);
  s.mc = std::make_shared<dem::MeshContact>(belt(), wp.materials, 1);
  s.mc->set_threads(threads);
  w.add_interaction(s.mc);
  if (!populate) return s;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> U(0, 1);
  // loose bed: 15 x 15 x 5 spheres of 0.9-1 mm on a 2 mm lattice, thrown down onto the belt
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 15; ++j)
      for (int i = 0; i < 15; ++i) {
        const double r = 0.9e-3 + 0.1e-3 * U(rng);
        const double x[3] = {1.0e-3 + 2.0e-3 * i + 0.05e-3 * (U(rng) - 0.5),
                             1.0e-3 + 2.0e-3 * j + 0.05e-3 * (U(rng) - 0.5), 1.0e-3 + 2.0e-3 * k};
        const double v[3] = {0.2 * (U(rng) - 0.5), 0.2 * (U(rng) - 0.5), -0.3 - 0.1 * U(rng)};
        w.add_particle(x, r, 0, v);
      }
  return s;
}

// Four 3 x 3 x 3 clusters of 0.9 mm spheres, weakly bonded, thrown down onto the bed from just above it.
void add_clusters(Scene& s) {
  dem::World& w = *s.w;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  dem::BondParams bp;
  bp.kn = 100e9;
  bp.kt = 40e9;
  bp.sigma_c = 0.9e6;
  bp.tau_c = 0.6e6;
  for (int c = 0; c < 4; ++c) {
    const std::size_t first = w.particles().size();
    const double cx = 0.008 + 0.014 * (c % 2), cy = 0.008 + 0.014 * (c / 2), rc = 0.9e-3;
    double top = 0;  // highest sphere top under the cluster
    const dem::Particles& p = w.particles();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (std::fabs(p.x[i] - cx) < 3 * rc + p.r[i] && std::fabs(p.y[i] - cy) < 3 * rc + p.r[i])
        top = std::max(top, p.z[i] + p.r[i]);
    const double v[3] = {0.5 * (U(rng) - 0.5), 0.5 * (U(rng) - 0.5), -6.0};
    const double om[3] = {100 * (U(rng) - 0.5), 100 * (U(rng) - 0.5), 100 * (U(rng) - 0.5)};
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const double x[3] = {cx + 2 * rc * (i - 1), cy + 2 * rc * (j - 1), top + 0.2e-3 + 1.0e-3 * c + rc + 2 * rc * k};
          w.add_particle(x, rc, 0, v, om);
        }
    w.bond_within(0.1 * rc, bp, first, w.particles().size());
  }
}

// The caller's part of a step: the belt's pose and twist at the end of the coming drift.
void advance(Scene& s, long steps) {
  for (long k = 0; k < steps; ++k) {
    const double t = s.w->time() + s.w->dt();
    dem::Pose pose;
    pose.position = Vector3d(kV * t, 0, 0);
    pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(kOmega * t, Vector3d::UnitZ()));
    dem::Twist tw;
    tw.linear = Vector3d(kV, 0, 0);
    tw.angular = Vector3d(0, 0, kOmega);
    s.mc->set_pose(pose);
    s.mc->set_twist(tw);
    s.w->step(1);
  }
}

// Everything observable after a step, as raw doubles/ints (compared bit for bit).
struct Snapshot {
  std::vector<std::vector<double>> arrays;
  std::vector<uint64_t> ids;
  std::vector<double> bonds, breaks, walls, wall_forces, mesh;
  double t = 0;
  long steps = 0, rebuilds = 0;
  std::size_t contacts = 0, bonds_intact = 0, mesh_contacts = 0;
};

Snapshot snapshot(const Scene& s) {
  const dem::World& w = *s.w;
  const dem::Particles& p = w.particles();
  Snapshot out;
  for (const auto* a : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.wx, &p.wy, &p.wz, &p.fx, &p.fy, &p.fz, &p.tx,
                        &p.ty, &p.tz})
    out.arrays.emplace_back(a->begin(), a->end());
  out.ids = p.id;
  out.ids.push_back(p.next_id);
  for (const dem::Bond& b : w.bonds()) {
    if (!b.alive) continue;  // broken bonds are dropped in batches, a run and its restored copy at other steps
    out.bonds.insert(out.bonds.end(), {double(b.i), double(b.j), b.fn, b.ft[0], b.ft[1], b.ft[2], b.tn, b.tt[0],
                                       b.tt[1], b.tt[2], double(b.alive)});
  }
  for (const dem::BondBreak& e : w.breaks())
    out.breaks.insert(out.breaks.end(), {e.t, e.x[0], e.x[1], e.x[2], double(e.id_i), double(e.id_j),
                                         double(e.tensile), e.sigma, e.tau});
  for (std::size_t k = 0; k < w.n_walls(); ++k) {
    const dem::PlanarWall& wl = w.wall(static_cast<int>(k));
    out.walls.insert(out.walls.end(), {wl.p[0], wl.p[1], wl.p[2]});
    out.wall_forces.insert(out.wall_forces.end(), {wl.force[0], wl.force[1], wl.force[2]});
  }
  const dem::MeshWrench mw = s.mc->wrench_about(Vector3d(0.01, 0.02, 0.0));
  out.mesh = {mw.force.x(), mw.force.y(), mw.force.z(), mw.torque.x(), mw.torque.y(), mw.torque.z(),
              s.mc->total_normal_force(), s.mc->worst_overlap().first, double(s.mc->worst_overlap().second)};
  out.mesh_contacts = s.mc->contacts().size();
  out.t = w.time();
  out.steps = w.step_count();
  out.rebuilds = w.n_rebuilds();
  out.contacts = w.n_contacts();
  out.bonds_intact = w.n_bonds_intact();
  return out;
}

std::string exact(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// First index where two double arrays differ in their bits (-1: identical).
long first_diff(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return 0;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (std::memcmp(&a[k], &b[k], sizeof(double)) != 0) return static_cast<long>(k);
  return -1;
}

// mesh_contacts: compare the mesh's contact list length too (it is empty after a load until the next step).
// same_threads: the planar walls' force totals are sums of per-thread partial sums (World::gather_forces), so
// they agree bitwise only between runs on the same thread count; across thread counts to rounding.
void expect_identical(const Snapshot& a, const Snapshot& b, bool mesh_contacts = true, bool same_threads = true) {
  static const char* names[] = {"x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz", "fx", "fy", "fz", "tx", "ty", "tz"};
  ASSERT_EQ(a.arrays.size(), b.arrays.size());
  for (std::size_t k = 0; k < a.arrays.size(); ++k) {
    const long d = first_diff(a.arrays[k], b.arrays[k]);
    EXPECT_EQ(d, -1) << "particle array " << names[k] << " differs first at index " << d
                     << (d >= 0 && a.arrays[k].size() == b.arrays[k].size()
                             ? ": " + exact(a.arrays[k][d]) + " vs " + exact(b.arrays[k][d])
                             : std::string(": sizes differ"));
  }
  EXPECT_EQ(a.ids, b.ids);
  EXPECT_EQ(first_diff(a.bonds, b.bonds), -1) << "bond states differ";
  EXPECT_EQ(first_diff(a.breaks, b.breaks), -1) << "break logs differ (" << a.breaks.size() / 9 << " vs "
                                                << b.breaks.size() / 9 << " breaks)";
  EXPECT_EQ(first_diff(a.walls, b.walls), -1) << "wall positions differ";
  if (same_threads) {
    EXPECT_EQ(first_diff(a.wall_forces, b.wall_forces), -1) << "wall forces differ";
  } else {
    ASSERT_EQ(a.wall_forces.size(), b.wall_forces.size());
    for (std::size_t k = 0; k < a.wall_forces.size(); ++k)
      EXPECT_NEAR(a.wall_forces[k], b.wall_forces[k], 1e-12 * (std::fabs(a.wall_forces[k]) + 1e-9)) << k;
  }
  EXPECT_EQ(first_diff(a.mesh, b.mesh), -1) << "mesh wrench differs";
  EXPECT_EQ(std::memcmp(&a.t, &b.t, sizeof a.t), 0);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(a.rebuilds, b.rebuilds) << "neighbour-list rebuild counts differ";
  EXPECT_EQ(a.contacts, b.contacts);
  EXPECT_EQ(a.bonds_intact, b.bonds_intact);
  if (mesh_contacts) {
    EXPECT_EQ(a.mesh_contacts, b.mesh_contacts);
  }
}

constexpr long kSettle = 3000, kBefore = 550, kAfter = 600;

// Run A: kBefore steps, save, kAfter more. Returns the file and A's final snapshot (and the state at the save).
struct RunA {
  std::string file;
  Snapshot at_save, end;
  std::size_t breaks_at_save = 0, bonds_at_save = 0, mesh_contacts_at_save = 0, particles = 0;
  bool rebuilt_after_save = false;
};

RunA run_a(int threads) {
  Scene s = make_scene(threads);
  s.w->set_dt(2e-6);
  advance(s, kSettle);  // the bed settles on the belt
  s.w->set_dt(1e-6);    // (restored from the file: the loading World is built with 2e-6)
  add_clusters(s);
  advance(s, kBefore);
  RunA a;
  a.breaks_at_save = s.w->breaks().size();
  a.bonds_at_save = s.w->n_bonds_intact();
  a.particles = s.w->particles().size();
  a.at_save = snapshot(s);
  a.mesh_contacts_at_save = a.at_save.mesh_contacts;
  std::ostringstream os;
  core::BinaryWriter bw(os);
  s.w->save_state(bw);
  a.file = os.str();
  // save_state schedules a rebuild: the next step rebuilds the neighbour list, as the loaded World's first does
  advance(s, 1);
  a.rebuilt_after_save = s.w->n_rebuilds() == a.at_save.rebuilds + 1;
  advance(s, kAfter - 1);
  a.end = snapshot(s);
  return a;
}

Snapshot run_b(const std::string& file, int threads, bool populate, Snapshot* loaded = nullptr) {
  Scene s = make_scene(threads, populate);
  std::istringstream is(file);
  core::BinaryReader br(is, "test");
  s.w->load_state(br);
  if (loaded) *loaded = snapshot(s);
  advance(s, kAfter);
  return snapshot(s);
}

// The scene does what it is meant to: breaks before and after the save, intact bonds left, mesh and wall
// contacts, a dense bed.
void check_scene(const RunA& a) {
  EXPECT_GT(a.breaks_at_save, 0u) << "no bond broke before the save";
  EXPECT_GT(a.end.breaks.size() / 9, a.breaks_at_save) << "no bond broke after the save";
  EXPECT_GT(a.end.bonds_intact, 20u);
  EXPECT_GT(a.mesh_contacts_at_save, 30u);
  EXPECT_GT(a.end.contacts, 300u);
  double wall_force = 0;
  for (double f : a.end.wall_forces) wall_force += std::fabs(f);
  EXPECT_GT(wall_force, 0.0) << "no wall contacts";
  EXPECT_TRUE(a.rebuilt_after_save) << "save_state did not schedule a neighbour-list rebuild";
}

TEST(DemCheckpoint, RestoredWorldContinuesBitwiseOnOneThread) {
  const RunA a = run_a(1);
  check_scene(a);
  Snapshot loaded;
  const Snapshot b = run_b(a.file, 1, true, &loaded);
  expect_identical(loaded, a.at_save, false);  // load reproduces the saved state itself
  expect_identical(a.end, b);
  std::printf("checkpoint: %zu bytes for %zu particles (%.0f bytes/particle), %zu intact bonds, %zu mesh contacts\n",
              a.file.size(), a.particles, double(a.file.size()) / a.particles, a.bonds_at_save,
              a.mesh_contacts_at_save);
}

TEST(DemCheckpoint, TheFileKeepsItsBytes) {
  // A checkpoint written by an earlier build must load in this one: the scene's file (walls and their histories,
  // bonds, pairs, mesh contacts) keeps the size and FNV-1a hash measured on 2026-12-05. A change to the format must
  // be deliberate (a new version in world_checkpoint.cpp that still reads this one), and then these figures with it.
  const RunA a = run_a(1);
  uint64_t h = 1469598103934665603ull;
  for (unsigned char c : a.file) h = (h ^ c) * 1099511628211ull;
  std::printf("checkpoint: %zu bytes, FNV-1a %016llx\n", a.file.size(), static_cast<unsigned long long>(h));
  EXPECT_EQ(a.file.size(), kSceneFileBytes);
  EXPECT_EQ(h, kSceneFileHash);
}

TEST(DemCheckpoint, RestoredWorldContinuesBitwiseOnTwoThreadsAndAcrossThreadCounts) {
  const RunA a = run_a(2);
  check_scene(a);
  expect_identical(a.end, run_b(a.file, 2, true));
  // saved on 2 threads, loaded into an empty World (walls and mesh only) on 1 thread
  expect_identical(a.end, run_b(a.file, 1, false), true, false);
}

// ------------------------------------------------------------------ damaged or mismatched files
// A one-thread World with a floor plane (and the belt mesh).
std::unique_ptr<dem::World> small_world(bool with_mesh) {
  dem::WorldParams wp;
  wp.threads = 1;
  auto w = std::make_unique<dem::World>(wp);
  const double o[3] = {0, 0, 0}, n[3] = {0, 0, 1};
  w->add_plane(o, n, 1);
  if (with_mesh) w->add_interaction(std::make_shared<dem::MeshContact>(belt(), wp.materials, 1));
  return w;
}

std::string small_file(bool with_mesh) {
  auto owner = small_world(with_mesh);
  dem::World& w = *owner;
  for (int k = 0; k < 4; ++k) {
    const double x[3] = {0.003 * k, 0, 0.0009};
    w.add_particle(x, 1e-3, 0);
  }
  w.step(50);
  std::ostringstream os;
  core::BinaryWriter bw(os);
  w.save_state(bw);
  return os.str();
}

// Loads `file` into a World with one floor plane (and the mesh) and returns the error message ("" if none).
std::string load_error(const std::string& file, bool with_mesh) {
  auto owner = small_world(with_mesh);
  dem::World& w = *owner;
  std::istringstream is(file);
  core::BinaryReader br(is, "small.ckpt");
  try {
    w.load_state(br);
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(w.particles().size(), 0u) << "a failed load changed the World";
    return e.what();
  }
  return "";
}

TEST(DemCheckpoint, DamagedOrMismatchedFilesAreRefused) {
  const std::string good = small_file(true);
  ASSERT_EQ(load_error(good, true), "");
  // truncated anywhere: the particle arrays, the mesh block, the end tag
  for (std::size_t cut : {std::size_t(60), good.size() / 3, good.size() - 40, good.size() - 2}) {
    const std::string msg = load_error(good.substr(0, cut), true);
    EXPECT_NE(msg.find("truncated"), std::string::npos) << "cut at " << cut << ": " << msg;
    EXPECT_NE(msg.find("small.ckpt"), std::string::npos) << msg;
  }
  // written with a mesh, loaded without (and the other way round): the interaction count is named
  std::string msg = load_error(good, false);
  EXPECT_NE(msg.find("1 interactions, this World has 0"), std::string::npos) << msg;
  msg = load_error(small_file(false), true);
  EXPECT_NE(msg.find("0 interactions, this World has 1"), std::string::npos) << msg;
  // wrong tags: not a World file, and a damaged block tag
  msg = load_error("CHMBxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx", true);
  EXPECT_NE(msg.find("expected block 'WRLD', found 'CHMB'"), std::string::npos) << msg;
  std::string bad = good;
  const std::size_t at = bad.find("PART");
  ASSERT_NE(at, std::string::npos);
  bad[at] = 'X';
  msg = load_error(bad, true);
  EXPECT_NE(msg.find("expected block 'PART', found 'XART'"), std::string::npos) << msg;
  bad = good;
  bad[bad.find("MESH")] = 'N';
  msg = load_error(bad, true);
  EXPECT_NE(msg.find("expected block 'MESH'"), std::string::npos) << msg;
  // another wall count
  {
    dem::WorldParams wp;
    wp.threads = 1;
    dem::World w(wp);
    w.add_interaction(std::make_shared<dem::MeshContact>(belt(), wp.materials, 1));
    std::istringstream is(good);
    core::BinaryReader br(is, "small.ckpt");
    try {
      w.load_state(br);
      ADD_FAILURE() << "loaded a file with another wall count";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("1 planar walls, this World has 0"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
