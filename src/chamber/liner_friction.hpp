#pragma once
// Friction of the pressed charge on the liners (flow.effects.liner_friction, a candidate of the diagnosis). A pressed
// cell's rock is held by the concave (the cells are fixed in its frame) and the mantle slides over it: Coulomb
// friction mu N against the mantle's tangential slip, N = p A the cell's normal force, mu rock on steel (Table 4:
// 0.7, the paper's DEM has it on every particle). Regularised as mu N tanh(|v_t| / v_reg) for the mechanism's
// explicit force-then-step coupling (on the GYP1200 at 1 ms, 20 mm/s chatters; 50 mm/s is within 2 % of 12.5 mm/s at
// a quarter of the step: src/chamber/README.md). The pair acts at the middle of the gap, on the mantle and (through
// the rock) on the concave: action and reaction, forces and torques. The mantle's spin is free (mbd O1), so the
// friction also turns it.
#include <Eigen/Core>
#include <cmath>

namespace chamber {

struct LinerFriction {
  bool enabled = false;
  double wall_friction = 0.7;         // rock on steel (Table 4)
  double regularisation_m_s = 0.05;   // config: regularisation_mm_s
};

// The liners' rigid motion: each body's centre-of-mass velocity and angular velocity (world).
struct LinerTwists {
  Eigen::Vector3d v_mantle = Eigen::Vector3d::Zero(), w_mantle = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_concave = Eigen::Vector3d::Zero(), w_concave = Eigen::Vector3d::Zero();
};

// Tangential slip of the mantle over the concave at x (world), n the unit normal there.
inline Eigen::Vector3d liner_slip(const LinerTwists& tw, const Eigen::Vector3d& x, const Eigen::Vector3d& n,
                                  const Eigen::Vector3d& com_mantle, const Eigen::Vector3d& com_concave) {
  const Eigen::Vector3d v = tw.v_mantle + tw.w_mantle.cross(x - com_mantle) -
                            (tw.v_concave + tw.w_concave.cross(x - com_concave));
  return v - n * n.dot(v);
}

// Friction force on the mantle for normal force N >= 0 and tangential slip v_t (the concave gets minus it).
inline Eigen::Vector3d liner_friction_force(const LinerFriction& f, double N, const Eigen::Vector3d& v_t) {
  const double s = v_t.norm();
  if (!(N > 0) || s < 1e-15) return Eigen::Vector3d::Zero();
  return -(f.wall_friction * N * std::tanh(s / f.regularisation_m_s) / s) * v_t;
}

}  // namespace chamber
