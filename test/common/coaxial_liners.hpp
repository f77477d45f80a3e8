#pragma once
// Test geometry shared by the continuum-bed tests (chamber flow model, retained fines): coaxial cylindrical liners
// and poses shifted from rest.
#include <Eigen/Geometry>
#include <cmath>

#include "core/chamber_geometry.hpp"

namespace test_liners {

// A cylinder of radius r from z0 to z1 (m), as a liner profile.
inline core::Profile cylinder(double r, double z0 = -0.9, double z1 = -0.1) {
  core::Profile p;
  p.z = {z0, z1};
  p.r = {r, r};
  return p;
}

// GYP1200-like liners (the mantle r 600 -> 168 mm over z -715 -> -200 mm, the concave 662 -> 194 mm over -760 -> -100)
// for the long flow-model runs, and the mantle's nutation there: 0.014 rad about an axis turning at 7 Hz.
inline core::Profile gyp_mantle() {
  core::Profile p;
  p.z = {-0.715, -0.2};
  p.r = {0.600, 0.168};
  return p;
}
inline core::Profile gyp_concave() {
  core::Profile p;
  p.z = {-0.760, -0.1};
  p.r = {0.662, 0.194};
  return p;
}
inline Eigen::Isometry3d nutating(double t) {
  const double w = 2 * M_PI * 7;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.014, Eigen::Vector3d(-std::sin(w * t), std::cos(w * t), 0)).toRotationMatrix();
  return T;
}

// The rest pose translated by d (m).
inline Eigen::Isometry3d shifted(const Eigen::Vector3d& d) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = d;
  return T;
}

}  // namespace test_liners
