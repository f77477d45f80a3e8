#pragma once
// mbd_node's outputs in a flow run (run.load flow): the screened product of the chamber flow model on
// /crusher/product, the liners on /crusher/liners, the chamber's cells (coloured by pressure) on /crusher/chamber and
// the concave force map (13 x 9 areas, mean over the time since the last message) on /crusher/concave_forces. All go
// to the bag at every call; the latched display topics go to ROS while subscribed, else once a simulated second.
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include <deque>
#include <memory>
#include <utility>

#include "analysis/run_metrics.hpp"
#include "chamber/flow_model.hpp"
#include "chamber/force_map.hpp"
#include "core/binary_io.hpp"
#include "mbd/mechanism.hpp"
#include "nodes/ros_common.hpp"

namespace nodes {

class FlowOutputs {
 public:
  FlowOutputs(ros::NodeHandle& nh, const mbd::MechanismParams& p, double throughput_window_s = 1.0);
  // Publishes and records the product (throughput over the last window), the liners at their pose, the cells and the
  // concave force map.
  void publish(const ros::Time& stamp, const mbd::Mechanism& m, const chamber::FlowModel& f, BagRecorder& bag);
  // What the next messages depend on besides the model (the throughput window, the force map's last impulse), for the
  // checkpoint of a fast run: a resumed run publishes what the uninterrupted one did, bit for bit.
  void save_state(core::BinaryWriter& w) const;
  void load_state(core::BinaryReader& r);

 private:
  ros::Publisher pub_product_, pub_liners_, pub_cells_, pub_map_, pub_map_markers_;
  double force_scale_N_;
  core::Profile concave_;
  std::unique_ptr<chamber::ConcaveForceMap> map_;  // made at the first publish (it needs the model's cells)
  std::vector<double> last_impulse_;                // the cells' normal impulse at the last map
  double last_map_t_ = 0;
  // The liners' triangle lists in their liner frames, built once: a message updates only their stamp and poses.
  visualization_msgs::MarkerArray liners_;
  double window_s_;
  double next_latch_t_ = 0;                        // simulated time the latched topics are next refreshed unheard
  static constexpr double kLatchRefresh_s = 1.0;
  std::deque<std::pair<double, double>> discharged_;  // (t, kg) history for the throughput window
};

// The flow model's product discharged in the window as summary.json reports it.
analysis::ProductSummary flow_product(const chamber::FlowModel& f, const std::vector<double>& by_class,
                                      double throughput_tph);

}  // namespace nodes
