#include "nodes/mbd_node_flow.hpp"

#include <inertia_crusher/ConcaveForceMap.h>
#include <inertia_crusher/ProductStream.h>
#include <visualization_msgs/MarkerArray.h>

#include <algorithm>
#include <numeric>

#include "dem/revolution.hpp"
#include "nodes/ros_common_force_map.hpp"

namespace nodes {
namespace {

std::vector<Eigen::Vector3d> triangle_list(const core::Profile& p, dem::NormalSide side) {
  const auto mesh = dem::revolve_profile(dem::profile_points(p), 48, side);
  std::vector<Eigen::Vector3d> v;
  for (const auto& t : mesh.triangles())
    for (int k : t) v.push_back(mesh.vertex(k));
  return v;
}

geometry_msgs::Pose pose_of(const Eigen::Isometry3d& T) {
  return to_pose(T.translation(), Eigen::Quaterniond(T.linear()));
}

// A liner's marker in its liner frame (stamp and pose set per message).
visualization_msgs::Marker liner(const std::string& ns, int id, const std::vector<Eigen::Vector3d>& tris, bool moving) {
  visualization_msgs::Marker m;
  m.header.frame_id = "world";
  m.ns = ns;
  m.id = id;
  m.type = visualization_msgs::Marker::TRIANGLE_LIST;
  m.scale.x = m.scale.y = m.scale.z = 1;
  m.color.r = moving ? 0.75 : 0.55;
  m.color.g = moving ? 0.55 : 0.6;
  m.color.b = moving ? 0.3 : 0.7;
  m.color.a = moving ? 1.0 : 0.35;
  m.points.reserve(tris.size());
  for (const auto& v : tris) m.points.push_back(to_point(v));
  return m;
}

}  // namespace

FlowOutputs::FlowOutputs(ros::NodeHandle& nh, const mbd::MechanismParams& p, double window_s)
    : window_s_(window_s) {
  liners_.markers.push_back(liner("mantle", 0, triangle_list(p.chamber.mantle, dem::NormalSide::Outward), true));
  liners_.markers.push_back(liner("concave", 1, triangle_list(p.chamber.concave, dem::NormalSide::Inward), false));
  concave_ = p.chamber.concave;
  ros::NodeHandle pnh("~");
  force_scale_N_ = force_scale_N(pnh);
  pub_product_ = nh.advertise<inertia_crusher::ProductStream>("/crusher/product", 100);
  pub_liners_ = nh.advertise<visualization_msgs::MarkerArray>("/crusher/liners", 2, true);
  pub_cells_ = nh.advertise<visualization_msgs::MarkerArray>("/crusher/chamber", 2, true);
  pub_map_ = nh.advertise<inertia_crusher::ConcaveForceMap>("/crusher/concave_forces", 100, true);
  pub_map_markers_ = nh.advertise<visualization_msgs::MarkerArray>("/crusher/concave_force_markers", 2, true);
}

analysis::ProductSummary flow_product(const chamber::FlowModel& f, const std::vector<double>& by_class, double tph) {
  analysis::ProductSummary s;
  s.throughput_tph = tph;
  s.mass_discharged_kg = std::accumulate(by_class.begin(), by_class.end(), 0.0);
  const auto pass = f.passing(by_class);
  for (std::size_t k = 0; k < pass.size(); ++k) {
    s.sieve_mm.push_back(f.params().sieves_m[k] * 1e3);
    s.passing_pct.push_back(100 * pass[k]);
  }
  return s;
}

void FlowOutputs::publish(const ros::Time& stamp, const mbd::Mechanism& m, const chamber::FlowModel& f,
                          BagRecorder& bag) {
  const double t = stamp.toSec(), out = f.discharged_kg();
  // The latched displays (liners, cells, force map) are serialised for ROS only while someone listens, and once a
  // simulated second otherwise, so that a viewer that joins late finds a recent one (the bag records every one).
  const bool refresh_latch = t >= next_latch_t_;
  if (refresh_latch) next_latch_t_ = t + kLatchRefresh_s;
  auto latched = [&](ros::Publisher& pub, const auto& msg) {
    if (refresh_latch || pub.getNumSubscribers() > 0) pub.publish(msg);
  };
  discharged_.emplace_back(t, out);
  while (discharged_.size() > 2 && discharged_[1].first <= t - window_s_) discharged_.pop_front();
  const auto& [t0, kg0] = discharged_.front();
  const auto s = flow_product(f, f.discharged_by_class(), t > t0 ? (out - kg0) / (t - t0) * 3.6 : 0.0);
  inertia_crusher::ProductStream p;
  p.header.stamp = stamp;
  p.header.frame_id = "world";
  p.sieve_mm = s.sieve_mm;
  p.passing_pct = s.passing_pct;
  p.throughput_tph = s.throughput_tph;
  p.mass_discharged_kg = out;
  p.mass_fed_kg = f.fed_kg();
  p.mass_in_chamber_kg = f.mass_kg();
  p.mass_crushed_kg = 0;  // the flow model's rock is one continuum: none is "crushed to fines" apart from it
  p.mass_fines_bed_kg = 0;
  p.mass_lost_kg = 0;
  pub_product_.publish(p);
  bag.write("/crusher/product", stamp, p);

  for (auto& mk : liners_.markers) mk.header.stamp = stamp;
  liners_.markers[0].pose = pose_of(m.liner_pose(mbd::BodyId::FloatingCone));
  liners_.markers[1].pose = pose_of(m.liner_pose(mbd::BodyId::FixedCone));
  latched(pub_liners_, liners_);
  bag.write("/crusher/liners", stamp, liners_);

  // Cells holding rock at their concave point, coloured by pressure on a fixed 0-10 MPa scale (blue to red).
  visualization_msgs::Marker c;
  c.header = p.header;
  c.ns = "chamber_cells";
  c.type = visualization_msgs::Marker::SPHERE_LIST;
  c.pose = pose_of(m.liner_pose(mbd::BodyId::FixedCone));
  c.scale.x = c.scale.y = c.scale.z = 0.015;
  for (std::size_t k = 0; k < f.cells(); ++k) {
    if (f.cell_mass(k) <= 0) continue;
    c.points.push_back(to_point(f.cell_point(k)));
    std_msgs::ColorRGBA col;
    const double u = std::min(1.0, f.cell_pressure(k) / 10e6);
    col.r = u, col.g = 0.3 * (1 - u), col.b = 1 - u, col.a = 1;
    c.colors.push_back(col);
  }
  visualization_msgs::MarkerArray cells;
  cells.markers.push_back(c);
  latched(pub_cells_, cells);
  bag.write("/crusher/chamber", stamp, cells);

  // The mean normal force on each concave area since the last map: the cells' impulse gained over the time passed.
  if (!map_) map_ = std::make_unique<chamber::ConcaveForceMap>(f, concave_);
  const auto& J = f.normal_impulse();
  if (!last_impulse_.empty() && t > last_map_t_) {
    std::vector<double> mean(J.size());
    for (std::size_t k = 0; k < J.size(); ++k) mean[k] = (J[k] - last_impulse_[k]) / (t - last_map_t_);
    inertia_crusher::ConcaveForceMap fm;
    fm.header = p.header;
    fm.rings = map_->rings();
    fm.sectors = map_->sectors();
    fm.window_s = t - last_map_t_;
    fm.mean_normal_force = map_->map(mean);
    latched(pub_map_, fm);
    bag.write("/crusher/concave_forces", stamp, fm);
    const Eigen::Isometry3d T = m.liner_pose(mbd::BodyId::FixedCone);
    std::vector<Eigen::Vector3d> at;
    for (int a = 0; a < map_->rings() * map_->sectors(); ++a) at.push_back(T * map_->area_centre(a));
    const auto markers = force_map_markers(stamp, at, fm.mean_normal_force, force_scale_N_);
    latched(pub_map_markers_, markers);
    bag.write("/crusher/concave_force_markers", stamp, markers);
  }
  last_impulse_ = J;
  last_map_t_ = t;
}

void FlowOutputs::save_state(core::BinaryWriter& w) const {
  w.tag("FOUT");
  std::vector<double> history;  // (t, kg) pairs
  for (const auto& [t, kg] : discharged_) history.insert(history.end(), {t, kg});
  w.put_vec(history);
  w.put_vec(last_impulse_);
  w.put(last_map_t_);
}

void FlowOutputs::load_state(core::BinaryReader& r) {
  r.expect("FOUT");
  std::vector<double> history;
  r.get_vec(history);
  if (history.size() % 2) r.fail("flow outputs: the throughput history is corrupt");
  discharged_.clear();
  for (std::size_t k = 0; k < history.size(); k += 2) discharged_.emplace_back(history[k], history[k + 1]);
  r.get_vec(last_impulse_);
  r.get(last_map_t_);
}

}  // namespace nodes
