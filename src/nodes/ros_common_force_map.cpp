#include "nodes/ros_common_force_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "core/cli_args.hpp"
#include "nodes/ros_common.hpp"

namespace nodes {
namespace {

std_msgs::ColorRGBA colour(double u) {  // u = force / scale, clamped to [0, 1]: blue to red
  u = std::clamp(u, 0.0, 1.0);
  std_msgs::ColorRGBA c;
  c.r = u, c.g = 0.0, c.b = 1.0 - u, c.a = 1.0;  // saturation 1: apart from fragment colours (0.75) in a screenshot
  return c;
}

visualization_msgs::Marker base(const ros::Time& stamp, const std::string& ns, int id, int type) {
  visualization_msgs::Marker m;
  m.header.stamp = stamp;
  m.header.frame_id = "world";
  m.ns = ns;
  m.id = id;
  m.type = type;
  m.pose.orientation.w = 1;
  return m;
}

}  // namespace

visualization_msgs::MarkerArray force_map_markers(const ros::Time& stamp, const std::vector<Eigen::Vector3d>& centres,
                                                  const std::vector<double>& force_N, double scale_N) {
  visualization_msgs::MarkerArray arr;
  auto m = base(stamp, "concave_force_map", 0, visualization_msgs::Marker::SPHERE_LIST);
  m.scale.x = m.scale.y = m.scale.z = 0.04;
  for (std::size_t r = 0; r < centres.size() && r < force_N.size(); ++r) {
    m.points.push_back(to_point(centres[r]));
    m.colors.push_back(colour(force_N[r] / scale_N));
  }
  arr.markers.push_back(m);
  // Legend: 11 cubes from 0 (bottom) to the scale (top), to the right of the chamber in rviz/crusher.rviz's view
  // (orbit yaw 0.8 rad: screen right is (-sin 0.8, cos 0.8, 0)), with labels.
  const Eigen::Vector3d right(-0.717, 0.697, 0.0), foot = 1.15 * right + Eigen::Vector3d(0, 0, -0.75);
  constexpr int kSteps = 11;
  constexpr double kDz = 0.07;
  auto bar = base(stamp, "concave_force_legend", 0, visualization_msgs::Marker::CUBE_LIST);
  bar.scale.x = bar.scale.y = bar.scale.z = kDz;
  for (int i = 0; i < kSteps; ++i) {
    bar.points.push_back(to_point(foot + Eigen::Vector3d(0, 0, i * kDz)));
    bar.colors.push_back(colour(i / double(kSteps - 1)));
  }
  arr.markers.push_back(bar);
  char top[48];
  std::snprintf(top, sizeof top, "%g kN", scale_N * 1e-3);
  const struct { const char* text; double z; } labels[] = {
      {"0 kN", 0.0}, {top, (kSteps - 1) * kDz}, {"concave force", (kSteps + 0.5) * kDz}};
  int id = 1;
  for (const auto& l : labels) {
    auto t = base(stamp, "concave_force_legend", id++, visualization_msgs::Marker::TEXT_VIEW_FACING);
    t.pose.position = to_point(foot + Eigen::Vector3d(0, 0, l.z) + 0.22 * right);
    t.scale.z = 0.06;
    t.color.r = t.color.g = t.color.b = t.color.a = 1.0;
    t.text = l.text;
    arr.markers.push_back(t);
  }
  return arr;
}

double force_scale_N(ros::NodeHandle& pnh) {
  const auto v = param_text(pnh, "force_scale_kN");
  return (v ? core::parse_number("parameter ~force_scale_kN", *v, 1e-3, 1e6, "kN (the force map's red)") : 20.0) * 1e3;
}

}  // namespace nodes
