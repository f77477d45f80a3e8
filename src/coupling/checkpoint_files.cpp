#include "coupling/checkpoint_files.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace coupling {

namespace fs = std::filesystem;

namespace {
constexpr uint32_t kVersion = 2;  // 2: growing fragments (crushing.fragment_growth_s)

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
                      const std::function<void(core::BinaryWriter&)>& body, int keep) {
  fs::create_directories(checkpoint_dir(out));
  const std::string path = checkpoint_path(out, h.node, h.step), tmp = path + ".tmp";
  {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw std::runtime_error("checkpoint: cannot write " + tmp);
    core::BinaryWriter w(f);
    w.tag("ICCK");
    w.put(kVersion);
    w.put_string(h.node);
    w.put(h.step);
    w.put(h.time);
    body(w);
    w.tag("DONE");
    f.close();
    if (!f) throw std::runtime_error("checkpoint: writing " + tmp + " failed (disk full?)");
  }
  fs::rename(tmp, path);
  const auto common = latest_common_checkpoint(out, {"mbd", "dem"});
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

uint64_t resume_step(const std::string& out) {
  const auto k = latest_common_checkpoint(out, {"mbd", "dem"});
  if (!k)
    throw std::runtime_error("~resume: no checkpoint written by both nodes in " + checkpoint_dir(out) +
                             " (a run writes them with run.checkpoint_every_s > 0)");
  return *k;
}

long checkpoint_interval_steps(double every_s, double coupling_dt) {
  return std::max(1L, std::lround(every_s / coupling_dt));
}

CheckpointHeader read_checkpoint(const std::string& out, const std::string& node, uint64_t step,
                                 const std::function<void(core::BinaryReader&)>& body) {
  const std::string path = checkpoint_path(out, node, step);
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error("checkpoint: cannot open " + path);
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
