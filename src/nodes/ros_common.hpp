#pragma once
// Small ROS adapters shared by mbd_node and dem_node: message conversions, a lossless bag recorder
// that is closed on every exit path, and a stop flag for SIGINT/SIGTERM.
#include <geometry_msgs/Pose.h>
#include <geometry_msgs/Twist.h>
#include <geometry_msgs/Vector3.h>
#include <geometry_msgs/Wrench.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <ros/serialization.h>

#include "core/atomic_file.hpp"
#include "core/bag_writer.hpp"

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cerrno>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

namespace nodes {

geometry_msgs::Vector3 to_msg(const Eigen::Vector3d& v);
geometry_msgs::Point to_point(const Eigen::Vector3d& v);
Eigen::Vector3d from_msg(const geometry_msgs::Vector3& v);
geometry_msgs::Pose to_pose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q);
void from_pose(const geometry_msgs::Pose& m, Eigen::Vector3d* p, Eigen::Quaterniond* q);
geometry_msgs::Twist to_twist(const Eigen::Vector3d& v, const Eigen::Vector3d& w);

// A file that could not be written (disk full, a file size limit, an I/O error), named in what().
class WriteError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "writing PATH failed: DETAIL (errno's text)", the message of a WriteError (core/atomic_file.hpp).
using core::write_error_text;

// Writes every message it is given (the node's own record: nothing is dropped as `rosbag record` may), through
// core::BagWriter (a rosbag 2.0 file without rosbag's seek per message).
// A write error throws WriteError naming the file, once: the bag is then abandoned (what reached the disk stays,
// unindexed: `rosbag reindex` mends it), later writes are dropped and close() never throws, so a node can still
// checkpoint and write its summary.
class BagRecorder {
 public:
  BagRecorder() = default;
  ~BagRecorder() { close(); }
  void open(const std::string& path);  // throws WriteError
  template <class M>
  void write(const std::string& topic, const ros::Time& t, const M& m) {
    if (!open_) return;
    const ros::Time at = t < ros::TIME_MIN ? ros::TIME_MIN : t;  // a bag cannot hold time 0
    std::uint32_t& conn = conns_.try_emplace(topic, kNone).first->second;
    const std::uint32_t n = ros::serialization::serializationLength(m);
    try {
      if (conn == kNone)  // the topic's first message in this bag
        conn = bag_.connection(topic, ros::message_traits::datatype<M>(), ros::message_traits::md5sum<M>(),
                               ros::message_traits::definition<M>());
      ros::serialization::OStream s(bag_.message(conn, at.sec, at.nsec, n), n);
      ros::serialization::serialize(s, m);
    } catch (const core::BagWriteError& e) {
      fail(e.what(), e.err);
    }
  }
  // Closes the bag (writing its index); never throws: a failure is logged and kept in error().
  void close();
  // Closes the bag; a failure throws WriteError (a checkpoint must not follow a segment that is not whole).
  void close_or_throw();
  // Closes the current bag (if any) and opens a new one: the segments of a checkpointed run. Throws WriteError.
  void reopen(const std::string& path);
  bool is_open() const { return open_; }
  const std::string& error() const { return error_; }  // the first write error ("" when none)

 private:
  static constexpr std::uint32_t kNone = ~std::uint32_t(0);
  [[noreturn]] void fail(const std::string& detail, int err);
  core::BagWriter bag_;
  std::string path_, error_;
  bool open_ = false;
  std::map<std::string, std::uint32_t> conns_;  // topic -> its connection in the open bag (kNone: none yet)
};

// Writes `text` to `path` through a temporary file renamed into place (core::write_file_atomically). Returns "" or
// the write error's text naming the file.
inline std::string write_file(const std::string& path, const std::string& text) {
  return core::write_file_atomically(path, text);
}

// SIGINT/SIGTERM set a flag instead of killing the node, so bags are closed and partial results kept; SIGXFSZ is
// ignored (a file size limit is a write error, named, not a kill). Before mark_running() (the set-up: loading,
// packing, a warm start) there is nothing to keep: a signal ends the process at once with status 128 + signal.
void install_stop_handler();
void mark_running();
bool stop_requested();
int stop_signal();                 // the signal that asked the node to stop (0: none)
std::string stop_reason();         // "stopped by a signal (SIGTERM)", "" when none
inline int stop_exit_status() { return 128 + stop_signal(); }  // 130 for SIGINT, 143 for SIGTERM
// An error for the log: ROS_ERROR, or stderr once ROS has shut down (rosconsole prints nothing then).
void log_error(const std::string& msg);
void log_warn(const std::string& msg);
// Said when ros::ok() turns false without a signal: someone outside ended the node.
constexpr const char* kShutdownFromOutside =
    "ROS shut the node down from outside (an XML-RPC shutdown request, e.g. rosnode kill, or a node started with "
    "the same name)";

// Publishes a GeometryWrench saying dem_node has stopped and why, a few times over 0.25 s (mbd_node stops at once).
template <class WrenchMsg>
void publish_stopped(ros::Publisher& pub, const std::string& why, double t) {
  WrenchMsg w;
  w.header.stamp = ros::Time(t);
  w.stopped = why;
  for (int i = 0; i < 5; ++i) {
    pub.publish(w);
    ros::WallDuration(0.05).sleep();
  }
}

// Runs the callbacks that have arrived; with none, blocks until one arrives or `max_s` passes. Waiting this way
// instead of polling leaves the CPU to the other node (a 2-core machine runs both).
void wait_for_callbacks(double max_s);

// Monotonic wall-clock seconds (coupling timeouts, progress, real-time factor).
double wall_now();

// Reads a private parameter as string ("" when unset).
std::string param_or(ros::NodeHandle& pnh, const std::string& name, const std::string& fallback);
double param_or(ros::NodeHandle& pnh, const std::string& name, double fallback);
// A private parameter as text, whatever type it arrived as (`_duration:=abc` arrives as text, `_duration:=5` as a
// number), for core::parse_number and the like; nullopt when unset.
std::optional<std::string> param_text(ros::NodeHandle& pnh, const std::string& name);
// Reads a private boolean parameter (false when unset); returns false if it is set but not a boolean.
bool bool_param(ros::NodeHandle& pnh, const std::string& name, bool* value);

}  // namespace nodes
