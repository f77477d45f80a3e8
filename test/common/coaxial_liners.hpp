#pragma once
// Test geometry shared by the continuum-bed tests (chamber flow model, retained fines): coaxial cylindrical liners
// and poses shifted from rest.
#include <Eigen/Geometry>

#include "core/chamber_geometry.hpp"

namespace test_liners {

// A cylinder of radius r from z0 to z1 (m), as a liner profile.
inline core::Profile cylinder(double r, double z0 = -0.9, double z1 = -0.1) {
  core::Profile p;
  p.z = {z0, z1};
  p.r = {r, r};
  return p;
}

// The rest pose translated by d (m).
inline Eigen::Isometry3d shifted(const Eigen::Vector3d& d) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = d;
  return T;
}

}  // namespace test_liners
