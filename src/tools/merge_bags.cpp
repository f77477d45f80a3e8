// merge_bags: one bag for a coupled run. Each node records its own bag (mbd_node run.bag, dem_node dem.bag);
// after both have stopped, this merges them into the first, in time order:
//   merge_bags BASE.bag ADDED.bag [ADDED.bag ...]
// BASE.bag is rewritten (through BASE.bag.part, renamed at the end) to hold every message of every bag.
// A topic held by an added bag is taken from that bag only: the base's copies of it are what the base's
// node received from the added bag's node (mbd_node records the DEM's wrenches and product as it applies
// them), while the added bag is the publisher's own, lossless record. An input that cannot be read leaves
// BASE.bag untouched (exit 1). Prints one line per topic: `topic NAME messages N from FILE`.
//   merge_bags --concat OUT.bag SEGMENT.bag [SEGMENT.bag ...]
// joins a node's bag segments (a checkpointed run: run.seg<step>.bag, ...) into OUT.bag: every message of
// every segment, in time order. OUT.bag is written through OUT.bag.part; an unreadable segment leaves it as it was.
#include <csignal>
#include <cstdio>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

#ifdef CRUSHER_WITH_ROS
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <memory>

#include "core/atomic_file.hpp"
#include "core/bag_writer.hpp"

namespace {

std::set<std::string> topics_of(rosbag::Bag& bag) {
  std::set<std::string> out;
  rosbag::View v(bag);
  for (const auto* c : v.getConnections()) out.insert(c->topic);
  return out;
}

// paths[0]: the output (and, unless concat, the base input); concat: all topics of all inputs paths[1..].
int merge(const std::vector<std::string>& paths, bool concat) {
  std::vector<std::unique_ptr<rosbag::Bag>> in;
  for (std::size_t k = concat ? 1 : 0; k < paths.size(); ++k) {
    const auto& p = paths[k];
    in.push_back(std::make_unique<rosbag::Bag>());
    try {
      in.back()->open(p, rosbag::bagmode::Read);
    } catch (const std::exception& e) {
      std::cerr << "merge_bags: cannot read " << p << " (" << e.what() << "); " << paths[0] << " is left as it was\n";
      return 1;
    }
  }
  // Each topic from the last bag that holds it (concat: from every bag).
  std::map<std::string, std::size_t> source;
  std::vector<std::vector<std::string>> take(in.size());
  for (std::size_t k = 0; k < in.size(); ++k)
    for (const auto& t : topics_of(*in[k])) {
      source[t] = k;
      if (concat) take[k].push_back(t);
    }
  if (!concat)
    for (const auto& [topic, k] : source) take[k].push_back(topic);

  const std::string part = paths[0] + ".part";
  std::map<std::string, long> count;
  core::BagWriter out;  // (rosbag's own writer seeks before every message: src/core/README.md)
  try {
    out.open(part);
    rosbag::View view;  // one view over all bags iterates in time order
    for (std::size_t k = 0; k < in.size(); ++k)
      if (!take[k].empty()) view.addQuery(*in[k], rosbag::TopicQuery(take[k]));
    for (const rosbag::MessageInstance& m : view) {
      const std::uint32_t conn = out.connection(m.getTopic(), m.getDataType(), m.getMD5Sum(), m.getMessageDefinition());
      const std::uint32_t n = m.size();
      ros::serialization::OStream s(out.message(conn, m.getTime().sec, m.getTime().nsec, n), n);
      m.write(s);  // the message's bytes as stored
      ++count[m.getTopic()];
    }
    out.close();
  } catch (const std::exception& e) {  // a write error (disk full, a file size limit): no abort
    out.abandon();
    std::remove(part.c_str());
    const auto* w = dynamic_cast<const core::BagWriteError*>(&e);
    std::cerr << "merge_bags: "
              << (w ? core::write_error_text(part, e.what(), w->err) : "writing " + part + " failed (" + e.what() + ")")
              << "; " << paths[0] << " is left as it was\n";
    return 1;
  }
  for (auto& b : in) b->close();
  if (std::rename(part.c_str(), paths[0].c_str()) != 0) {
    std::perror(("merge_bags: rename " + part).c_str());
    return 1;
  }
  for (const auto& [topic, k] : source)
    std::cout << "topic " << topic << " messages " << count[topic] << " from "
              << (concat ? std::to_string(in.size()) + " segments" : paths[k]) << "\n";
  return 0;
}

}  // namespace
#endif

int main(int argc, char** argv) {
  std::signal(SIGXFSZ, SIG_IGN);  // a file size limit (ulimit -f) is a write error, reported, not a kill
  std::vector<std::string> paths(argv + 1, argv + argc);
  const bool concat = !paths.empty() && paths[0] == "--concat";
  if (concat) paths.erase(paths.begin());
  if (paths.size() < 2 || paths[0].rfind("-", 0) == 0) {
    std::cerr << "usage: merge_bags BASE.bag ADDED.bag [ADDED.bag ...]  (merges into BASE.bag in time order; "
                 "a topic of an added bag replaces the base's copy of it)\n"
                 "       merge_bags --concat OUT.bag SEGMENT.bag [SEGMENT.bag ...]  (every message of the segments)\n";
    return 2;
  }
#ifdef CRUSHER_WITH_ROS
  return merge(paths, concat);
#else
  std::cerr << "merge_bags: needs a build with ROS (CRUSHER_WITH_ROS)\n";
  return 2;
#endif
}
