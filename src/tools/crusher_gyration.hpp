#pragma once
// The crusher benchmark case's liner motion (dem_bench and dem_mpi_bench --case crusher).
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "coupling/chamber_dem.hpp"

namespace tools {

// The mantle (floating cone) at nutation theta about O1 (the origin), its axis leaning towards azimuth
// phi = Omega t (the drive's speed: the vibrator carries the mantle round once per revolution), no spin of its own;
// the concave (fixed cone) at rest. Angular velocity from the orientation's rate, COM velocity w x com.
struct Gyration {
  double theta = 0, omega = 0, phi0 = 0, t0 = 0, mantle_com_z = 0, concave_com_z = 0;
  Eigen::Vector3d pivot = Eigen::Vector3d::Zero(), concave_origin = Eigen::Vector3d::Zero();
  Eigen::Quaterniond spin = Eigen::Quaterniond::Identity(), concave_q = Eigen::Quaterniond::Identity();
  Eigen::Quaterniond q(double t) const {
    const double phi = phi0 + omega * (t - t0);
    return Eigen::Quaterniond(Eigen::AngleAxisd(theta, Eigen::Vector3d(-std::sin(phi), std::cos(phi), 0))) * spin;
  }
  coupling::BodyMotion mantle(double t) const {
    coupling::BodyMotion b;
    const double h = 1e-6;
    b.orientation = q(t);
    const Eigen::AngleAxisd d(q(t + h) * q(t).inverse());
    b.angular_velocity = d.axis() * d.angle() / h;
    const Eigen::Vector3d arm = b.orientation * Eigen::Vector3d(0, 0, mantle_com_z);
    b.com = pivot + arm;
    b.velocity = b.angular_velocity.cross(arm);
    return b;
  }
  coupling::BodyMotion concave() const {
    coupling::BodyMotion b;
    b.orientation = concave_q;
    b.com = concave_origin + concave_q * Eigen::Vector3d(0, 0, concave_com_z);
    return b;
  }
  // Continues from the liners' poses in a loaded state: its nutation (unless given), azimuth and spin, the pivot
  // (O1) where the mantle's frame is, the concave where it is.
  void continue_from(const coupling::ChamberDem& dem, bool keep_theta) {
    const auto& pm = dem.mantle().mesh().pose();
    const Eigen::Vector3d axis = pm.orientation * Eigen::Vector3d::UnitZ();
    if (!keep_theta) theta = std::acos(std::min(1.0, axis.z()));
    phi0 = std::atan2(axis.y(), axis.x());
    t0 = dem.time();
    const Eigen::Quaterniond tilt(
        Eigen::AngleAxisd(std::acos(std::min(1.0, axis.z())), Eigen::Vector3d(-std::sin(phi0), std::cos(phi0), 0)));
    spin = tilt.inverse() * pm.orientation;  // the rotation about the mantle's own axis
    pivot = pm.position;
    concave_origin = dem.concave().mesh().pose().position;
    concave_q = dem.concave().mesh().pose().orientation;
  }
};

}  // namespace tools
