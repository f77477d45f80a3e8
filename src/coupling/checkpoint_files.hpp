#pragma once
// Where a checkpointed run keeps its checkpoints and bag segments, and how they are written (ROS-free). A coupled run
// has two nodes (mbd, dem; <step> counts coupling steps), a fast run (run.load flow) mbd_node alone (<step> counts
// mechanism steps).
//   OUT/checkpoint/<node>.<step>.ckpt   state of one node at the start of step <step>;
//                                       written to a .tmp file and renamed, the newest two of each node kept
//   OUT/<base>.seg<step>.bag            a node's bag from the checkpoint at <step> (0: the start) to the next one
// A run resumes at the newest step that all its nodes wrote, sound. Each file starts with a header naming the node,
// the step and the simulated time, and ends with a CRC-32 of everything before it: a damaged file is refused by
// name, and a resume passes over it to the older step both nodes kept.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/binary_io.hpp"

namespace coupling {

// The nodes that checkpoint a run: both in a coupled run, mbd_node alone in a fast (flow) run.
const std::vector<std::string>& coupled_nodes();  // {"mbd", "dem"}
const std::vector<std::string>& fast_nodes();     // {"mbd"}

struct CheckpointHeader {
  std::string node;  // "mbd" or "dem"
  uint64_t step = 0;  // coupling step about to be taken
  double time = 0;    // simulated time (s) at its start
};

std::string checkpoint_dir(const std::string& out);
std::string checkpoint_path(const std::string& out, const std::string& node, uint64_t step);
// Writes header + body atomically (.tmp then rename) and removes this node's older files beyond the newest
// `keep`, but never the newest step that every node of the run (`nodes`) has (the one a resume needs) or any later one.
void write_checkpoint(const std::string& out, const CheckpointHeader& h,
                      const std::function<void(core::BinaryWriter&)>& body, int keep = 2,
                      const std::vector<std::string>& nodes = coupled_nodes());
// Steps for which a checkpoint of `node` exists, ascending.
std::vector<uint64_t> checkpoint_steps(const std::string& out, const std::string& node);
// Removes `node`'s checkpoints after `step` (a resumed run rewrites them; a stale one could pair up wrongly).
void remove_checkpoints_after(const std::string& out, const std::string& node, uint64_t step);
// Newest step present for every node ("mbd", "dem"); nullopt when there is none.
std::optional<uint64_t> latest_common_checkpoint(const std::string& out, const std::vector<std::string>& nodes);
// The step a resumed run starts from: the newest every node of the run wrote whose files are all sound (CRC-32);
// the damaged ones passed over are described in *passed_over. Throws std::runtime_error if there is none.
uint64_t resume_step(const std::string& out, std::vector<std::string>* passed_over = nullptr,
                     const std::vector<std::string>& nodes = coupled_nodes());
// Steps between checkpoints for run.checkpoint_every_s (> 0) and the step (coupling interval, or mechanism step).
long checkpoint_interval_steps(double every_s, double coupling_dt);
// Opens the checkpoint of `node` at `step`, checks its CRC-32 and header and calls `body` with a reader positioned
// after it. Throws std::runtime_error naming the file on any mismatch. Returns the header.
CheckpointHeader read_checkpoint(const std::string& out, const std::string& node, uint64_t step,
                                 const std::function<void(core::BinaryReader&)>& body);

std::string bag_segment_path(const std::string& out, const std::string& base, uint64_t step);
// Removes the segments of `base` starting at step >= first (written after the checkpoint a run resumes from).
void remove_bag_segments_from(const std::string& out, const std::string& base, uint64_t first);

}  // namespace coupling
