#include "nodes/ros_common.hpp"

#include <chrono>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <unistd.h>

namespace nodes {

geometry_msgs::Vector3 to_msg(const Eigen::Vector3d& v) {
  geometry_msgs::Vector3 m;
  m.x = v.x();
  m.y = v.y();
  m.z = v.z();
  return m;
}

geometry_msgs::Point to_point(const Eigen::Vector3d& v) {
  geometry_msgs::Point q;
  q.x = v.x();
  q.y = v.y();
  q.z = v.z();
  return q;
}

Eigen::Vector3d from_msg(const geometry_msgs::Vector3& v) { return {v.x, v.y, v.z}; }

geometry_msgs::Pose to_pose(const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
  geometry_msgs::Pose m;
  m.position.x = p.x();
  m.position.y = p.y();
  m.position.z = p.z();
  m.orientation.w = q.w();
  m.orientation.x = q.x();
  m.orientation.y = q.y();
  m.orientation.z = q.z();
  return m;
}

void from_pose(const geometry_msgs::Pose& m, Eigen::Vector3d* p, Eigen::Quaterniond* q) {
  *p = {m.position.x, m.position.y, m.position.z};
  *q = Eigen::Quaterniond(m.orientation.w, m.orientation.x, m.orientation.y, m.orientation.z);
}

geometry_msgs::Twist to_twist(const Eigen::Vector3d& v, const Eigen::Vector3d& w) {
  geometry_msgs::Twist t;
  t.linear = to_msg(v);
  t.angular = to_msg(w);
  return t;
}

void BagRecorder::open(const std::string& path) {
  path_ = path;
  conns_.clear();  // connections are per bag
  try {
    bag_.open(path);
  } catch (const core::BagWriteError& e) {
    fail(e.what(), e.err);
  }
  open_ = true;
}

void BagRecorder::reopen(const std::string& path) {
  close_or_throw();
  open(path);
}

void BagRecorder::fail(const std::string& detail, int err) {
  const std::string msg = write_error_text(path_, detail, err);
  if (error_.empty()) error_ = msg;
  open_ = false;  // (a BagWriter that threw has closed its file: what reached the disk stays, unindexed)
  throw WriteError(msg);
}

void BagRecorder::close_or_throw() {
  if (!open_) return;
  try {
    bag_.close();
  } catch (const core::BagWriteError& e) {
    fail(e.what(), e.err);
  }
  open_ = false;
}

void BagRecorder::close() {
  try {
    close_or_throw();
  } catch (const WriteError& e) {
    log_error(e.what());
  }
}

namespace {
volatile std::sig_atomic_t g_stop = 0, g_running = 0;
void on_signal(int sig) {
  if (!g_running) _exit(128 + sig);
  g_stop = sig;
}
}  // namespace

void install_stop_handler() {
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  // A file size limit (ulimit -f) then fails the write (EFBIG), reported by name, instead of killing the node.
  std::signal(SIGXFSZ, SIG_IGN);
}

void mark_running() { g_running = 1; }

bool stop_requested() { return g_stop != 0; }

int stop_signal() { return g_stop; }

std::string stop_reason() {
  if (!g_stop) return "";
  return std::string("stopped by a signal (") + (g_stop == SIGINT ? "SIGINT" : g_stop == SIGTERM ? "SIGTERM" : "?") + ")";
}

void log_error(const std::string& msg) {
  if (ros::ok()) ROS_ERROR("%s", msg.c_str());
  else std::fprintf(stderr, "[ERROR] %s\n", msg.c_str());
}

void log_warn(const std::string& msg) {
  if (ros::ok()) ROS_WARN("%s", msg.c_str());
  else std::fprintf(stderr, "[WARN] %s\n", msg.c_str());
}

double wall_now() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

std::string param_or(ros::NodeHandle& pnh, const std::string& name, const std::string& fallback) {
  std::string v;
  return pnh.getParam(name, v) ? v : fallback;
}

double param_or(ros::NodeHandle& pnh, const std::string& name, double fallback) {
  double v;
  if (pnh.getParam(name, v)) return v;
  int i;
  if (pnh.getParam(name, i)) return i;
  return fallback;
}

std::optional<std::string> param_text(ros::NodeHandle& pnh, const std::string& name) {
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam(name, v)) return std::nullopt;
  char b[40];
  switch (v.getType()) {
    case XmlRpc::XmlRpcValue::TypeString: return static_cast<std::string>(v);
    case XmlRpc::XmlRpcValue::TypeInt: return std::to_string(static_cast<int>(v));
    case XmlRpc::XmlRpcValue::TypeDouble:
      std::snprintf(b, sizeof b, "%.17g", static_cast<double>(v));
      return std::string(b);
    case XmlRpc::XmlRpcValue::TypeBoolean: return static_cast<bool>(v) ? "true" : "false";
    default: return "(a list or mapping)";
  }
}

void wait_for_callbacks(double max_s) { ros::getGlobalCallbackQueue()->callAvailable(ros::WallDuration(max_s)); }

bool bool_param(ros::NodeHandle& pnh, const std::string& name, bool* value) {
  *value = false;
  return !pnh.hasParam(name) || pnh.getParam(name, *value);
}

}  // namespace nodes
