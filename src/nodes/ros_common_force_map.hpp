#pragma once
// The concave force map in rviz (both nodes): a sphere at each area P_{ring,sector}, coloured on a fixed scale from
// blue (0 kN) to red (the scale and above), and its legend beside the crusher: a colour bar with kN labels.
#include <ros/ros.h>
#include <visualization_msgs/MarkerArray.h>

#include <Eigen/Core>
#include <vector>

namespace nodes {

// centres (world, m) and force_N (N) of the areas to show, equal length; scale_N: the force drawn red.
visualization_msgs::MarkerArray force_map_markers(const ros::Time& stamp, const std::vector<Eigen::Vector3d>& centres,
                                                  const std::vector<double>& force_N, double scale_N);

// The private parameter ~force_scale_kN (default 20): the force drawn red, N. Throws std::invalid_argument if <= 0.
double force_scale_N(ros::NodeHandle& pnh);

}  // namespace nodes
