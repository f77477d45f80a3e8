// Checkpoint files of a coupled run (coupling/checkpoint_files.hpp): naming, pruning, the common step.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "coupling/checkpoint_files.hpp"

namespace {

std::string fresh_dir(const std::string& name) {
  const auto d = std::filesystem::temp_directory_path() / ("crusher_ckpt_" + name + std::to_string(::getpid()));
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d.string();
}

void write(const std::string& out, const std::string& node, uint64_t step, double payload = 1.5) {
  coupling::write_checkpoint(out, {node, step, step * 1e-3}, [&](core::BinaryWriter& w) { w.put(payload); });
}

}  // namespace

TEST(CheckpointFiles, WritesReadsAndChecksTheHeader) {
  const auto out = fresh_dir("rw");
  write(out, "dem", 40, 2.25);
  double got = 0;
  auto h = coupling::read_checkpoint(out, "dem", 40, [&](core::BinaryReader& r) { got = r.get<double>(); });
  EXPECT_EQ(got, 2.25);
  EXPECT_EQ(h.step, 40u);
  EXPECT_EQ(h.time, 0.04);
  std::filesystem::rename(coupling::checkpoint_path(out, "dem", 40), coupling::checkpoint_path(out, "dem", 41));
  try {  // a file under another step's name is refused by its header
    coupling::read_checkpoint(out, "dem", 41, [](core::BinaryReader&) {});
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("step 40, expected 'dem' step 41"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(std::filesystem::exists(coupling::checkpoint_path(out, "dem", 40) + ".tmp"));
}

// The pruning keeps each node's newest two, but never the newest step both nodes hold: after a stop in
// which only one node wrote a final checkpoint, a second stop must still leave a step to resume from.
TEST(CheckpointFiles, PruningKeepsTheNewestCommonStep) {
  const auto out = fresh_dir("prune");
  for (uint64_t k : {100, 200}) write(out, "mbd", k), write(out, "dem", k);
  write(out, "dem", 250);  // dem's final checkpoint of a stop mbd did not match
  EXPECT_EQ(coupling::latest_common_checkpoint(out, {"mbd", "dem"}), std::optional<uint64_t>(200));
  write(out, "dem", 230);  // another unmatched one
  EXPECT_EQ(coupling::latest_common_checkpoint(out, {"mbd", "dem"}), std::optional<uint64_t>(200));
  EXPECT_EQ(coupling::checkpoint_steps(out, "dem"), (std::vector<uint64_t>{200, 230, 250}));
  // A resume from 200 drops the unmatched later files; the periodic pruning then goes on as usual.
  coupling::remove_checkpoints_after(out, "dem", 200);
  EXPECT_EQ(coupling::checkpoint_steps(out, "dem"), (std::vector<uint64_t>{200}));
  for (uint64_t k : {300, 400}) write(out, "mbd", k), write(out, "dem", k);
  EXPECT_EQ(coupling::checkpoint_steps(out, "mbd"), (std::vector<uint64_t>{300, 400}));
  EXPECT_EQ(coupling::checkpoint_steps(out, "dem"), (std::vector<uint64_t>{300, 400}));
  EXPECT_EQ(coupling::latest_common_checkpoint(out, {"mbd", "dem"}), std::optional<uint64_t>(400));
}

TEST(CheckpointFiles, SegmentsAndStrayNames) {
  const auto out = fresh_dir("seg");
  for (uint64_t k : {0, 20, 40}) std::ofstream(coupling::bag_segment_path(out, "run", k)) << "x";
  std::ofstream(out + "/run.seg99999999999999999999999.bag") << "x";  // too many digits: not a segment
  std::filesystem::create_directories(coupling::checkpoint_dir(out));
  std::ofstream(coupling::checkpoint_dir(out) + "/mbd.notanumber.ckpt") << "x";
  coupling::remove_bag_segments_from(out, "run", 20);
  EXPECT_TRUE(std::filesystem::exists(coupling::bag_segment_path(out, "run", 0)));
  EXPECT_FALSE(std::filesystem::exists(coupling::bag_segment_path(out, "run", 20)));
  EXPECT_FALSE(std::filesystem::exists(coupling::bag_segment_path(out, "run", 40)));
  EXPECT_TRUE(std::filesystem::exists(out + "/run.seg99999999999999999999999.bag"));
  EXPECT_EQ(coupling::bag_segment_path(out, "dem", 1234), out + "/dem.seg0000001234.bag");
  EXPECT_FALSE(coupling::latest_common_checkpoint(out, {"mbd", "dem"}).has_value());
}

namespace {
void flip_bit(const std::string& path, std::size_t bit) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(std::streamoff(bit / 8));
  char c = 0;
  f.get(c);
  f.seekp(std::streamoff(bit / 8));
  f.put(char(c ^ (1 << (bit % 8))));
}
}  // namespace

// Every single-bit flip of a checkpoint is refused naming the file (before: 10 of 10 flips in a DEM checkpoint
// were accepted), and a resume passes over the damaged newest step to the older one both nodes kept.
TEST(CheckpointFiles, AFlippedBitIsRefusedByNameAndTheOlderCheckpointUsed) {
  const auto out = fresh_dir("crc");
  for (uint64_t k : {20, 40}) write(out, "mbd", k), write(out, "dem", k);
  const auto path = coupling::checkpoint_path(out, "dem", 40);
  const auto bits = std::filesystem::file_size(path) * 8;
  for (std::size_t b = 0; b < bits; ++b) {
    flip_bit(path, b);
    try {
      coupling::read_checkpoint(out, "dem", 40, [](core::BinaryReader& r) { r.get<double>(); });
      ADD_FAILURE() << "bit " << b << " flipped was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": damaged"), std::string::npos) << e.what();
    }
    flip_bit(path, b);
  }
  EXPECT_EQ(coupling::resume_step(out), 40u);
  flip_bit(path, 100);
  std::vector<std::string> passed;
  EXPECT_EQ(coupling::resume_step(out, &passed), 20u);
  ASSERT_EQ(passed.size(), 1u);
  EXPECT_NE(passed[0].find("dem.0000000040.ckpt: damaged"), std::string::npos) << passed[0];
  std::filesystem::resize_file(coupling::checkpoint_path(out, "mbd", 20), 30);  // cut short
  try {
    coupling::resume_step(out);
    FAIL() << "no sound checkpoint, yet a step was given";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no sound checkpoint"), std::string::npos) << e.what();
  }
}

// A fast run (run.load flow) checkpoints mbd_node alone: its pruning keeps the newest two (there is no dem file to
// wait for), and a resume takes its newest sound step, passing over a damaged one.
TEST(CheckpointFiles, AFastRunHasMbdAloneAndResumesFromItsNewestSoundStep) {
  const auto out = fresh_dir("fast");
  for (uint64_t k : {1000, 2000, 2500})
    coupling::write_checkpoint(out, {"mbd", k, k * 1e-3}, [&](core::BinaryWriter& w) { w.put(1.0); }, 2,
                               coupling::fast_nodes());
  EXPECT_EQ(coupling::checkpoint_steps(out, "mbd"), (std::vector<uint64_t>{2000, 2500}));
  EXPECT_EQ(coupling::resume_step(out, nullptr, coupling::fast_nodes()), 2500u);
  EXPECT_THROW(coupling::resume_step(out), std::runtime_error);  // as a coupled run: no dem files
  flip_bit(coupling::checkpoint_path(out, "mbd", 2500), 70);
  std::vector<std::string> passed;
  EXPECT_EQ(coupling::resume_step(out, &passed, coupling::fast_nodes()), 2000u);
  ASSERT_EQ(passed.size(), 1u);
  EXPECT_NE(passed[0].find("mbd.0000002500.ckpt: damaged"), std::string::npos) << passed[0];
}
