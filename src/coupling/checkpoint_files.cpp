#include "coupling/checkpoint_files.hpp"

#include "core/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>

namespace coupling {

namespace fs = std::filesystem;

namespace {
// 2: growing fragments (crushing.fragment_growth_s); 3: CRC-32 trailer; 4: mbd_node's NODE section names the run's
// load, and a fast (flow) run's adds the flow model and its outputs' state (mbd_node.cpp)
constexpr uint32_t kVersion = 4;

// CRC-32 (IEEE 802.3, as zlib's crc32) of a file's bytes: a changed bit or a cut changes it.
uint32_t crc32(const std::string& bytes) {
  static const auto table = [] {
    std::vector<uint32_t> t(256);
    for (uint32_t n = 0; n < 256; ++n) {
      uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (unsigned char b : bytes) c = table[(c ^ b) & 0xFF] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

// The file's contents without its CRC trailer; throws std::runtime_error naming the file when the CRC differs.
std::string checked_contents(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("checkpoint: cannot open " + path);
  std::string bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  uint32_t stored = 0;
  if (bytes.size() >= sizeof stored) {
    std::memcpy(&stored, bytes.data() + bytes.size() - sizeof stored, sizeof stored);
    bytes.resize(bytes.size() - sizeof stored);
  }
  if (bytes.size() < 8 || bytes.compare(bytes.size() - 4, 4, "DONE") != 0 || crc32(bytes) != stored)
    throw std::runtime_error("checkpoint " + path + ": damaged (its CRC-32 does not match: a changed bit, or a file "
                             "cut short)");
  return bytes;
}

// "<node>.<digits><suffix>" -> digits as a number, or nullopt
std::optional<uint64_t> number_in(const std::string& name, const std::string& prefix, const std::string& suffix) {
  if (name.size() <= prefix.size() + suffix.size() || name.compare(0, prefix.size(), prefix) != 0 ||
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) != 0)
    return std::nullopt;
  const std::string digits = name.substr(prefix.size(), name.size() - prefix.size() - suffix.size());
  if (digits.empty() || digits.size() > 19 ||
      !std::all_of(digits.begin(), digits.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  return std::stoull(digits);
}
}  // namespace

const std::vector<std::string>& coupled_nodes() {
  static const std::vector<std::string> n{"mbd", "dem"};
  return n;
}

const std::vector<std::string>& fast_nodes() {
  static const std::vector<std::string> n{"mbd"};
  return n;
}

std::string checkpoint_dir(const std::string& out) { return out + "/checkpoint"; }

std::string checkpoint_path(const std::string& out, const std::string& node, uint64_t step) {
  char num[32];
  std::snprintf(num, sizeof num, "%010llu", static_cast<unsigned long long>(step));
  return checkpoint_dir(out) + "/" + node + "." + num + ".ckpt";
}

std::vector<uint64_t> checkpoint_steps(const std::string& out, const std::string& node) {
  std::vector<uint64_t> steps;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(checkpoint_dir(out), ec))
    if (auto n = number_in(e.path().filename().string(), node + ".", ".ckpt")) steps.push_back(*n);
  std::sort(steps.begin(), steps.end());
  return steps;
}

void write_checkpoint(const std::string& out, const CheckpointHeader& h,
                      const std::function<void(core::BinaryWriter&)>& body, int keep,
                      const std::vector<std::string>& nodes) {
  fs::create_directories(checkpoint_dir(out));
  const std::string path = checkpoint_path(out, h.node, h.step);
  std::ostringstream buf(std::ios::binary);
  core::BinaryWriter w(buf);
  w.tag("ICCK");
  w.put(kVersion);
  w.put_string(h.node);
  w.put(h.step);
  w.put(h.time);
  body(w);
  w.tag("DONE");
  std::string bytes = buf.str();
  const uint32_t crc = crc32(bytes);
  bytes.append(reinterpret_cast<const char*>(&crc), sizeof crc);
  const std::string err = core::write_file_atomically(path, bytes);
  if (!err.empty()) throw std::runtime_error("checkpoint: " + err);
  const auto common = latest_common_checkpoint(out, nodes);
  auto steps = checkpoint_steps(out, h.node);
  for (std::size_t k = 0; k + keep < steps.size(); ++k)
    if (common && steps[k] < *common) fs::remove(checkpoint_path(out, h.node, steps[k]));
}

void remove_checkpoints_after(const std::string& out, const std::string& node, uint64_t step) {
  for (auto k : checkpoint_steps(out, node))
    if (k > step) fs::remove(checkpoint_path(out, node, k));
}

std::optional<uint64_t> latest_common_checkpoint(const std::string& out, const std::vector<std::string>& nodes) {
  std::optional<std::vector<uint64_t>> common;
  for (const auto& n : nodes) {
    auto s = checkpoint_steps(out, n);
    if (!common) {
      common = s;
      continue;
    }
    std::vector<uint64_t> both;
    std::set_intersection(common->begin(), common->end(), s.begin(), s.end(), std::back_inserter(both));
    common = both;
  }
  if (!common || common->empty()) return std::nullopt;
  return common->back();
}

uint64_t resume_step(const std::string& out, std::vector<std::string>* passed_over,
                     const std::vector<std::string>& nodes) {
  std::vector<std::string> damaged;
  std::vector<uint64_t> all;  // the steps every node wrote
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const auto s = checkpoint_steps(out, nodes[i]);
    if (i == 0) {
      all = s;
      continue;
    }
    std::vector<uint64_t> both;
    std::set_intersection(all.begin(), all.end(), s.begin(), s.end(), std::back_inserter(both));
    all = both;
  }
  for (auto k = all.rbegin(); k != all.rend(); ++k) {
    bool sound = true;
    for (const auto& node : nodes) {
      try {
        checked_contents(checkpoint_path(out, node, *k));
      } catch (const std::runtime_error& e) {
        damaged.push_back(std::string(e.what()) + "; passed over");
        sound = false;
      }
    }
    if (passed_over) *passed_over = damaged;
    if (sound) return *k;
  }
  std::string why = " (a run writes them with run.checkpoint_every_s > 0)";
  if (!damaged.empty()) why = ": " + damaged.front() + (damaged.size() > 1 ? ", and others" : "");
  throw std::runtime_error(std::string("~resume: no sound checkpoint written by ") +
                           (nodes.size() > 1 ? "every node" : "mbd_node") + " in " + checkpoint_dir(out) + why);
}

long checkpoint_interval_steps(double every_s, double coupling_dt) {
  return std::max(1L, std::lround(every_s / coupling_dt));
}

CheckpointHeader read_checkpoint(const std::string& out, const std::string& node, uint64_t step,
                                 const std::function<void(core::BinaryReader&)>& body) {
  const std::string path = checkpoint_path(out, node, step);
  std::istringstream f(checked_contents(path), std::ios::binary);
  core::BinaryReader r(f, path);
  r.expect("ICCK");
  const auto version = r.get<uint32_t>();
  if (version != kVersion)
    r.fail("format version " + std::to_string(version) + ", this build reads " + std::to_string(kVersion));
  CheckpointHeader h;
  h.node = r.get_string();
  h.step = r.get<uint64_t>();
  h.time = r.get<double>();
  if (h.node != node || h.step != step)
    r.fail("header says node '" + h.node + "' step " + std::to_string(h.step) + ", expected '" + node + "' step " +
           std::to_string(step));
  body(r);
  r.expect("DONE");
  return h;
}

std::string bag_segment_path(const std::string& out, const std::string& base, uint64_t step) {
  char num[32];
  std::snprintf(num, sizeof num, "%010llu", static_cast<unsigned long long>(step));
  return out + "/" + base + ".seg" + num + ".bag";
}

void remove_bag_segments_from(const std::string& out, const std::string& base, uint64_t first) {
  std::error_code ec;
  std::vector<fs::path> doomed;
  for (const auto& e : fs::directory_iterator(out, ec)) {
    auto n = number_in(e.path().filename().string(), base + ".seg", ".bag");
    if (n && *n >= first) doomed.push_back(e.path());
  }
  for (const auto& p : doomed) fs::remove(p);
}

}  // namespace coupling
