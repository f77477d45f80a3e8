// ChamberDem checkpoints: a run restored from a checkpoint continues exactly as the run that wrote it.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "coupling/chamber_dem.hpp"
#include "small_chamber.hpp"

namespace {

// The small chamber pre-filled, so that rock presses on the liners from the start, with choke feeding on top
// (new rocks draw on the random generator after the checkpoint).
coupling::ChamberParams small_filled_chamber() {
  auto p = test_chamber::prefilled_small_chamber(0.4, 0.8);
  p.feed.max_rate_kg_s = 4.0;  // a rock every few ms: feeding goes on across the checkpoint
  p.bpm.bond.sigma_c = 2.5e6;  // a tenth of Table 4: bonds break within the short run
  p.bpm.bond.tau_c = 0.9e6;
  return p;
}

struct Record {  // what a run produces, step by step
  std::vector<double> wrench;  // mantle and concave force and torque per step
  std::vector<double> map;     // concave force map at the end
  std::vector<dem::BondBreak> breaks;
};

void run_steps(coupling::ChamberDem& dem, const coupling::ChamberParams& p, int from, int to, Record* rec) {
  coupling::BodyMotion m, c;
  c.com = Eigen::Vector3d(0, 0, p.concave_com_z_m);
  for (int k = from; k < to; ++k) {
    test_chamber::gyrate(p, k * 1e-3, 2.0 * M_PI / 180, &m);
    auto [wm, wc] = dem.advance(m, c, 1e-3);
    for (const auto* v : {&wm.force, &wm.torque, &wc.force, &wc.torque})
      rec->wrench.insert(rec->wrench.end(), v->data(), v->data() + 3);
  }
  rec->map = dem.force_map();
  auto b = dem.take_breaks();
  rec->breaks.insert(rec->breaks.end(), b.begin(), b.end());
}

void expect_same_particles(const dem::Particles& a, const dem::Particles& b) {
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a.id, b.id);
  for (std::size_t i = 0; i < a.size(); ++i) {
    ASSERT_TRUE(a.x[i] == b.x[i] && a.y[i] == b.y[i] && a.z[i] == b.z[i]) << "position of particle " << a.id[i];
    ASSERT_TRUE(a.vx[i] == b.vx[i] && a.vy[i] == b.vy[i] && a.vz[i] == b.vz[i]) << "velocity of " << a.id[i];
    ASSERT_TRUE(a.wx[i] == b.wx[i] && a.wy[i] == b.wy[i] && a.wz[i] == b.wz[i]) << "spin of " << a.id[i];
    ASSERT_TRUE(a.r[i] == b.r[i] && a.m[i] == b.m[i] && a.inv_I[i] == b.inv_I[i]) << "size or mass of " << a.id[i];
  }
}

// Runs p for 40 steps, saves, runs 40 more; a second chamber restored from the file runs the same 40 steps.
// growing: fragments must be growing at the checkpoint.
void expect_restored_run_continues_bit_for_bit(const coupling::ChamberParams& p, bool growing = false) {
  coupling::ChamberDem a(p);
  Record before;
  run_steps(a, p, 0, 40, &before);
  ASSERT_GT(a.world().particles().size(), 100u);
  if (growing) {
    ASSERT_GT(a.growing_fragments(), 0u);
  }
  std::stringstream file;
  {
    core::BinaryWriter w(file);
    a.save_state(w);
  }
  const double t_saved = a.time(), fed_saved = a.product().fed_kg;
  Record ra, rb;
  run_steps(a, p, 40, 80, &ra);

  auto q = p;
  q.threads = 1;  // results do not depend on the thread count
  coupling::ChamberDem b(q);
  core::BinaryReader r(file, "in memory");
  b.load_state(r);
  EXPECT_EQ(b.time(), t_saved);
  run_steps(b, p, 40, 80, &rb);

  // The state restored is the whole state: the run continues as if never stopped.
  EXPECT_EQ(ra.wrench, rb.wrench);
  EXPECT_EQ(ra.map, rb.map);
  ASSERT_EQ(ra.breaks.size(), rb.breaks.size());
  for (std::size_t k = 0; k < ra.breaks.size(); ++k) {
    EXPECT_EQ(ra.breaks[k].t, rb.breaks[k].t);
    EXPECT_EQ(ra.breaks[k].id_i, rb.breaks[k].id_i);
    EXPECT_EQ(ra.breaks[k].id_j, rb.breaks[k].id_j);
  }
  expect_same_particles(a.world().particles(), b.world().particles());
  const auto pa = a.product(), pb = b.product();
  EXPECT_EQ(pa.fed_kg, pb.fed_kg);
  EXPECT_EQ(pa.discharged_kg, pb.discharged_kg);
  EXPECT_EQ(pa.passing_pct, pb.passing_pct);
  EXPECT_EQ(a.broken_bonds(), b.broken_bonds());
  EXPECT_EQ(a.trajectories().size(), b.trajectories().size());
  // The test means something: rock was crushed against the liners, fed and broken around the checkpoint.
  double fmax = 0;
  for (double f : ra.wrench) fmax = std::max(fmax, std::abs(f));
  EXPECT_GT(fmax, 1.0);
  EXPECT_GT(fed_saved, a.prefilled_kg());
  EXPECT_GT(pa.fed_kg, fed_saved);
  EXPECT_GT(ra.breaks.size(), 0u);
  EXPECT_EQ(pa.metaparticles_crushed, pb.metaparticles_crushed);
  EXPECT_EQ(pa.metaparticles_fragmented, pb.metaparticles_fragmented);
  EXPECT_EQ(pa.crushed_kg, pb.crushed_kg);
  EXPECT_EQ(pa.fines_bed_kg, pb.fines_bed_kg);
  if (p.fines_flow) {
    EXPECT_GT(pa.fines_bed_kg, 0.0);
  }
  std::printf("checkpoint: %zu bytes for %zu particles, %zu bonds; %zu breaks after it; %ld crushed to fines, "
              "%ld to fragments\n", file.str().size(), a.world().particles().size(), a.world().bonds().size(),
              ra.breaks.size(), pa.metaparticles_crushed, pa.metaparticles_fragmented);
}

// The checkpoint of a chamber built from p after two coupling steps.
std::string checkpoint_after_two_steps(const coupling::ChamberParams& p) {
  coupling::ChamberDem a(p);
  Record rec;
  run_steps(a, p, 0, 2, &rec);
  std::stringstream file;
  core::BinaryWriter w(file);
  a.save_state(w);
  return file.str();
}

}  // namespace

TEST(ChamberCheckpoint, RestoredRunContinuesBitForBit) { expect_restored_run_continues_bit_for_bit(small_filled_chamber()); }

// With metaparticle crushing into fragments (heavier than their spheres, drawn on the random generator): the
// fragments' masses and the crushing counts are part of the state.
TEST(ChamberCheckpoint, RestoredRunWithCrushingIntoFragmentsContinuesBitForBit) {
  auto p = small_filled_chamber();
  p.crushing.enabled = true;
  p.crushing.fragments = true;
  p.crushing.tensile_strength = 0.5e6;  // F_c(8 mm) = 36 N: the gyration crushes many
  p.crushing.min_fragment_m = 4e-3;
  p.crushing.batch_s = 2e-4;
  expect_restored_run_continues_bit_for_bit(p);
}

// Fragments growing to the rock's density across the checkpoint: their growth is part of the state.
TEST(ChamberCheckpoint, RestoredRunWithGrowingFragmentsContinuesBitForBit) {
  auto p = test_chamber::busy_small_chamber();  // small_filled_chamber() crushing into growing fragments
  p.threads = 2;
  expect_restored_run_continues_bit_for_bit(p, true);
}

// With the crushed fines in the flow model (dem.fines: flow): its masses by class, fall speeds, hysteretic memory,
// compression counts and the discharge not yet taken.
TEST(ChamberCheckpoint, RestoredRunWithFinesInTheFlowModelContinuesBitForBit) {
  auto p = small_filled_chamber();
  p.crushing.enabled = true;
  p.crushing.tensile_strength = 0.5e6;
  p.crushing.batch_s = 2e-4;
  p.fines_flow = true;
  p.fines = chamber::fines_only(chamber::FlowParams());
  p.fines.bands = 8;
  p.fines.sectors = 12;
  expect_restored_run_continues_bit_for_bit(p);
}

TEST(ChamberCheckpoint, RefusesAFileOfAnotherFeedOrATruncatedOne) {
  const auto p = small_filled_chamber();
  const std::string bytes = checkpoint_after_two_steps(p);

  // The error message of loading `file` (named `name`) into a chamber built from `q`; "" if it loads.
  auto load_error = [](const coupling::ChamberParams& q, const std::string& file, const std::string& name) {
    coupling::ChamberDem d(q);
    std::istringstream in(file);
    core::BinaryReader r(in, name);
    try {
      d.load_state(r);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  auto other = p;
  other.feed.seed = p.feed.seed + 1;  // other rock shapes
  const std::string e1 = load_error(other, bytes, "x.ckpt");
  ASSERT_FALSE(e1.empty()) << "a checkpoint of another feed was accepted";
  EXPECT_NE(e1.find("another feed"), std::string::npos) << e1;
  EXPECT_NE(e1.find("x.ckpt"), std::string::npos) << e1;
  auto heavier = p;
  heavier.feed.rock_density = 2600;  // the same rocks, weighing their volume (feed.rock_density)
  EXPECT_NE(load_error(heavier, bytes, "x.ckpt").find("another feed"), std::string::npos);
  const std::string e2 = load_error(p, bytes.substr(0, bytes.size() / 2), "half.ckpt");
  ASSERT_FALSE(e2.empty()) << "a truncated checkpoint was accepted";
  EXPECT_NE(e2.find("truncated"), std::string::npos) << e2;
  // Fines in a flow model of another material (its compaction limit), or of other cells, or none.
  auto bed = p;
  bed.crushing.enabled = true;
  bed.fines_flow = true;
  bed.fines = chamber::fines_only(chamber::FlowParams());
  const std::string bed_bytes = checkpoint_after_two_steps(bed);
  auto looser = bed;
  looser.fines.material.max_compression = 0.3;
  const std::string e3 = load_error(looser, bed_bytes, "bed.ckpt");
  EXPECT_NE(e3.find("fines' flow model"), std::string::npos) << e3;
  auto finer = bed;
  finer.fines.bands += 1;
  EXPECT_NE(load_error(finer, bed_bytes, "bed.ckpt").find("fines' flow model"), std::string::npos);
  auto none = bed;
  none.fines_flow = false;
  EXPECT_NE(load_error(none, bed_bytes, "bed.ckpt").find("fines' flow model"), std::string::npos);
  EXPECT_EQ(load_error(bed, bed_bytes, "bed.ckpt"), "");
}
