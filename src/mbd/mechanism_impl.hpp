#pragma once
// Private to src/mbd: the state of mbd::Mechanism (mechanism.cpp: construction and stepping;
// mechanism_checkpoint.cpp: save_state / load_state). Not installed, not for other libraries.
#include <ode/ode.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "mbd/chamber_forces.hpp"
#include "mbd/mechanism.hpp"

namespace mbd {

namespace mechanism_detail {
inline Eigen::Vector3d vec(const dReal* v) { return {v[0], v[1], v[2]}; }
inline Eigen::Matrix3d mat(const dReal* R) {  // ODE: 3x4 row-major
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = R[i * 4 + j];
  return m;
}
inline void set_rot(dBodyID b, const Eigen::Matrix3d& m) {
  dMatrix3 R;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) R[i * 4 + j] = m(i, j);
    R[i * 4 + 3] = 0;
  }
  dBodySetRotation(b, R);
}
}  // namespace mechanism_detail

struct Mechanism::Impl {
  MechanismParams p;
  LoadModel load;
  ChamberForces chamber;
  dWorldID world = nullptr;
  dThreadingImplementationID threading = nullptr;
  dBodyID body[kBodyCount] = {};
  dJointID o1 = nullptr, o2 = nullptr, o3 = nullptr, o4_dist = nullptr, o4_rot = nullptr, o5 = nullptr,
           o6 = nullptr, o7 = nullptr;
  dJointFeedback o7_feedback{};
  dJointFeedback o1_feedback{}, o3_feedback{};  // bearing-friction effect: the joints' reactions of the last step
  double t = 0;
  double t_before = 0;  // time run before the clock was set back to 0 (warm start)
  long steps = 0;
  // rest references
  Eigen::Vector3d b1_rest;            // fixed cone COM at rest
  Eigen::Vector3d tp_local;           // test point in B1 body frame
  Eigen::Vector3d tp_rest;            // test point world at rest
  Eigen::Vector3d tp_vel_prev = Eigen::Vector3d::Zero(), tp_acc = Eigen::Vector3d::Zero();
  double absorber_preload = 0;        // N, carries the weight (static equilibrium at rest)
  Eigen::Vector3d k_rot, c_rot;       // absorber tilt/twist stiffness and damping
  Eigen::Vector3d drive_axis{0, 0, 1};
  double o4_normal_rest = 0;          // (B4 point - B3 axis point) . axis at rest
  double ecc = 0;                     // vibrator eccentricity
  double torque = 0;                  // drive torque (last step)
  bool droop = false;                 // motor-droop effect: drive torque from the speed-torque line
  double min_gap = 0, bed_force = 0, contact_force = 0;
  Eigen::Vector3d ext_f[kBodyCount], ext_t[kBodyCount];
  EnergyAudit audit;
  BedState bed_state, bed_next;       // hysteretic bed memory (chamber_forces.hpp)
  double bed_stored_booked = 0;       // hysteretic bed: stored energy already taken off bed_dissipation
  bool hysteretic_bed() const { return load == LoadModel::Bed && p.bed.law == BedLaw::Hysteretic; }

  explicit Impl(const MechanismParams& params, LoadModel l) : p(params), load(l), chamber(params) {}
  ~Impl() {
    if (world) {
      dWorldSetStepThreadingImplementation(world, nullptr, nullptr);
      dWorldDestroy(world);
    }
    if (threading) dThreadingFreeImplementation(threading);
  }

  Eigen::Vector3d pos(int i) const { return mechanism_detail::vec(dBodyGetPosition(body[i])); }
  Eigen::Matrix3d rot(int i) const { return mechanism_detail::mat(dBodyGetRotation(body[i])); }
  Eigen::Vector3d lvel(int i) const { return mechanism_detail::vec(dBodyGetLinearVel(body[i])); }
  Eigen::Vector3d avel(int i) const { return mechanism_detail::vec(dBodyGetAngularVel(body[i])); }

  dBodyID make_body(const BodyParams& bp, const Eigen::Vector3d& x, const Eigen::Matrix3d& R) {
    dBodyID b = dBodyCreate(world);
    dMass m;
    dMassSetParameters(&m, bp.mass_kg, 0, 0, 0, bp.inertia_kg_m2[0], bp.inertia_kg_m2[1], bp.inertia_kg_m2[2], 0,
                       0, 0);
    dBodySetMass(b, &m);
    dBodySetPosition(b, x[0], x[1], x[2]);
    mechanism_detail::set_rot(b, R);
    dBodySetGyroscopicMode(b, 1);
    return b;
  }

  RigidKinematics kin(int i, double liner_z) const {
    RigidKinematics k;
    k.x = pos(i);
    k.R = rot(i);
    k.v = lvel(i);
    k.w = avel(i);
    k.liner_origin = Eigen::Vector3d(0, 0, -liner_z);
    const auto& bp = i == 0 ? p.fixed_cone : p.floating_cone;
    k.inv_mass = 1.0 / bp.mass_kg;
    k.inv_inertia_world = k.R * bp.inertia_kg_m2.cwiseInverse().asDiagonal() * k.R.transpose();
    return k;
  }

  void build();
  void apply_and_step();
  double constraint_error() const;
  double mech_energy_parts(double* kin, double* grav, double* elast, double* bed_potential = nullptr) const;
};

}  // namespace mbd
