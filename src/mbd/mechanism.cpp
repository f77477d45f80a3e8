#include "mbd/mechanism.hpp"

#include <ode/ode.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <sstream>
#include <stdexcept>

#include "mbd/chamber_forces.hpp"
#include "mbd/drive_efficiency.hpp"
#include "mbd/mechanism_impl.hpp"

namespace mbd {

using mechanism_detail::mat;
using mechanism_detail::vec;

namespace {

// Error reduction of the joints. 0.5 (ODE default 0.2): the vibrator spins with its COM off the
// joint axis, so the first-order position update drifts the joint by e (w dt)^2 / 2 per step; the
// steady joint error is that drift / ERP (0.08 mm at 400 rpm, dt 0.5 ms, e 0.18 m).
constexpr double kErp = 0.5;
std::once_flag g_ode_once;
void init_ode() {
  std::call_once(g_ode_once, [] { dInitODE2(0); });
}

// Small-rotation vector of R relative to identity (exact axis-angle).
Eigen::Vector3d rotation_vector(const Eigen::Matrix3d& R) {
  Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

}  // namespace

const char* body_name(BodyId id) {
  switch (id) {
    case BodyId::FixedCone: return "fixed_cone";
    case BodyId::FloatingCone: return "floating_cone";
    case BodyId::Vibrator: return "vibrator";
    case BodyId::GlobeBearing: return "globe_bearing";
    case BodyId::ConnectingShaft: return "connecting_shaft";
    case BodyId::DriveShaft: return "drive_shaft";
  }
  return "?";
}

LoadModel load_model_from_string(const std::string& s) {
  if (s == "bed") return LoadModel::Bed;
  if (s == "none" || s == "dem") return LoadModel::None;
  throw std::invalid_argument("mbd: load '" + s + "' is not accepted; accepted: none, bed, dem");
}

void Mechanism::Impl::build() {
  init_ode();
  dAllocateODEDataForThread(dAllocateMaskAll);  // ODE needs per-thread data (callers may run in threads)
  world = dWorldCreate();
  // Each world steps with its own (self-threaded) implementation: ODE's shared default one is not safe
  // when two mechanisms step at the same time in different threads (the diagnosis fits in parallel).
  threading = dThreadingAllocateSelfThreadedImplementation();
  dWorldSetStepThreadingImplementation(world, dThreadingImplementationGetFunctions(threading), threading);
  dWorldSetGravity(world, 0, 0, -p.gravity_m_s2);
  dWorldSetERP(world, kErp);
  dWorldSetCFM(world, 1e-10);
  ecc = p.vibrator_eccentricity_m();
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  auto& B = body;
  B[0] = make_body(p.fixed_cone, {0, 0, p.fixed_cone.com_z_m}, I);
  B[1] = make_body(p.floating_cone, {0, 0, p.floating_cone.com_z_m}, I);
  // Vibrator: its COM sits at the eccentricity e off the shaft axis (static moment m e).
  B[2] = make_body(p.vibrator, {ecc, 0, p.vibrator_axis_z_m}, I);
  B[3] = make_body(p.globe_bearing, {0, 0, p.globe_bearing_z_m}, I);
  B[4] = make_body(p.connecting_shaft, {0, 0, p.connecting_shaft.com_z_m}, I);
  // Drive shaft: hangs from O6 along the drive axis (tilted by the cardan misalignment effect).
  const double beta = p.effects.cardan_misalignment.enabled ? p.effects.cardan_misalignment.angle_rad : 0.0;
  const Eigen::Matrix3d Rb = Eigen::AngleAxisd(beta, Eigen::Vector3d::UnitY()).toRotationMatrix();
  drive_axis = Rb * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d o6x(0, 0, p.universal_z_m);
  const Eigen::Vector3d b6x = o6x - 0.5 * p.drive_shaft_length_m * drive_axis;
  B[5] = make_body(p.drive_shaft, b6x, Rb);

  o1 = dJointCreateBall(world, nullptr);
  dJointAttach(o1, B[1], B[0]);
  dJointSetBallAnchor(o1, 0, 0, 0);

  o2 = dJointCreateBall(world, nullptr);
  dJointAttach(o2, B[3], B[1]);
  dJointSetBallAnchor(o2, 0, 0, p.globe_bearing_z_m);

  o3 = dJointCreatePiston(world, nullptr);
  dJointAttach(o3, B[2], B[1]);
  dJointSetPistonAnchor(o3, 0, 0, p.vibrator_axis_z_m);
  dJointSetPistonAxis(o3, 0, 0, 1);

  // O4 planar (normal = vibrator axis): 1 translational + 2 rotational constraints, written as
  //  - dJointDBall between the O2 centre on B4 and the vibrator axis point on B3 (both stay on the
  //    shaft axis through O2 and O3, so their distance is the normal distance of the plane), and
  //  - a user-mode dJointAMotor with two motor rows about B3's x and y axes (relative angular
  //    velocity zero, the misalignment fed back each step like ODE's ERP).
  o4_dist = dJointCreateDBall(world, nullptr);
  dJointAttach(o4_dist, B[3], B[2]);
  dJointSetDBallAnchor1(o4_dist, 0, 0, p.globe_bearing_z_m);
  dJointSetDBallAnchor2(o4_dist, 0, 0, p.vibrator_axis_z_m);
  o4_rot = dJointCreateAMotor(world, nullptr);
  dJointAttach(o4_rot, B[2], B[3]);
  dJointSetAMotorMode(o4_rot, dAMotorUser);
  dJointSetAMotorNumAxes(o4_rot, 2);
  dJointSetAMotorAxis(o4_rot, 0, 1, 1, 0, 0);
  dJointSetAMotorAxis(o4_rot, 1, 1, 0, 1, 0);
  dJointSetAMotorParam(o4_rot, dParamFMax, 1e9);
  dJointSetAMotorParam(o4_rot, dParamFMax2, 1e9);
  o4_normal_rest = p.globe_bearing_z_m - p.vibrator_axis_z_m;

  o5 = dJointCreatePU(world, nullptr);
  dJointAttach(o5, B[2], B[4]);
  dJointSetPUAnchor(o5, 0, 0, p.ball_pin_z_m);
  dJointSetPUAxisP(o5, 0, 0, 1);
  dJointSetPUAxis1(o5, 1, 0, 0);
  dJointSetPUAxis2(o5, 0, 1, 0);

  o6 = dJointCreateUniversal(world, nullptr);
  dJointAttach(o6, B[4], B[5]);
  dJointSetUniversalAnchor(o6, o6x[0], o6x[1], o6x[2]);
  dJointSetUniversalAxis1(o6, 1, 0, 0);
  const Eigen::Vector3d ax2 = Rb * Eigen::Vector3d::UnitY();
  dJointSetUniversalAxis2(o6, ax2[0], ax2[1], ax2[2]);

  o7 = dJointCreateHinge(world, nullptr);
  dJointAttach(o7, B[5], nullptr);
  dJointSetHingeAnchor(o7, b6x[0], b6x[1], b6x[2]);
  dJointSetHingeAxis(o7, drive_axis[0], drive_axis[1], drive_axis[2]);
  // Constant speed: a stiff velocity motor. With the motor-droop effect the drive is instead the
  // motor's linear speed-torque line T = (w_set - w) / droop, applied as a torque (see apply_and_step).
  droop = p.effects.motor_droop.enabled && p.effects.motor_droop.droop_rad_s_per_Nm > 0;
  dJointSetHingeParam(o7, dParamFMax, droop ? 0.0 : p.drive_max_torque_Nm);
  dJointSetHingeParam(o7, dParamVel, 0.0);
  dJointSetFeedback(o7, &o7_feedback);
  if (p.effects.bearing_friction.enabled) {  // the bearings' loads (output only: the dynamics do not change)
    dJointSetFeedback(o1, &o1_feedback);
    dJointSetFeedback(o3, &o3_feedback);
  }

  b1_rest = pos(0);
  tp_rest = p.test_point_m;
  tp_local = p.test_point_m - b1_rest;
  // The absorbers carry the weight of everything resting on the fixed cone at rest; the connecting
  // shaft hangs from the drive shaft (O6 holds it: the PU slides freely along the vibrator axis).
  absorber_preload = p.gravity_m_s2 * (p.fixed_cone.mass_kg + p.floating_cone.mass_kg + p.vibrator.mass_kg +
                                       p.globe_bearing.mass_kg);
  const double R = p.absorber_ring_radius_m;
  const auto& k = p.absorber_k_N_per_m;
  const auto& c = p.absorber_c_Ns_per_m;
  // Absorbers evenly on a ring of radius R: tilt stiffness kz R^2 / 2, twist (kx + ky) / 2 R^2.
  k_rot = {0.5 * k[2] * R * R, 0.5 * k[2] * R * R, 0.5 * (k[0] + k[1]) * R * R};
  c_rot = {0.5 * c[2] * R * R, 0.5 * c[2] * R * R, 0.5 * (c[0] + c[1]) * R * R};
  for (int i = 0; i < kBodyCount; ++i) ext_f[i].setZero(), ext_t[i].setZero();
  bed_state = chamber.initial_bed_state();
  bed_next = bed_state;
  double kin = 0, grav = 0, el = 0;
  mech_energy_parts(&kin, &grav, &el, &bed_stored_booked);
  audit.kinetic = kin;
  audit.gravity_potential = grav;
  audit.elastic_potential = el;
}

double Mechanism::Impl::mech_energy_parts(double* kin_sum, double* grav_out, double* el_out,
                                          double* bed_potential) const {
  double ke = 0, grav = 0;
  auto add = [&](dBodyID b) {
    dMass m;
    dBodyGetMass(b, &m);
    const Eigen::Vector3d v = vec(dBodyGetLinearVel(b)), w = vec(dBodyGetAngularVel(b));
    const Eigen::Matrix3d R = mat(dBodyGetRotation(b));
    Eigen::Matrix3d Ib;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Ib(i, j) = m.I[i * 4 + j];
    const Eigen::Vector3d wb = R.transpose() * w;
    ke += 0.5 * m.mass * v.squaredNorm() + 0.5 * wb.dot(Ib * wb);
    grav += m.mass * p.gravity_m_s2 * vec(dBodyGetPosition(b)).z();
  };
  for (int i = 0; i < kBodyCount; ++i) add(body[i]);
  // Absorbers: 1/2 d'K d - preload d_z, rotational 1/2 th'K th; cubic effect 1/4 k3 d^4.
  const Eigen::Vector3d d = pos(0) - b1_rest;
  const Eigen::Vector3d th = rotation_vector(rot(0));
  double el = 0;
  for (int i = 0; i < 3; ++i) el += 0.5 * p.absorber_k_N_per_m[i] * d[i] * d[i] + 0.5 * k_rot[i] * th[i] * th[i];
  el -= absorber_preload * d.z();
  if (p.effects.absorber_nonlinearity.enabled)
    for (int i = 0; i < 3; ++i) el += 0.25 * p.effects.absorber_nonlinearity.cubic_N_per_m3 * std::pow(d[i], 4);
  {  // potentials of the cone contact and the bed at the current configuration
    const RigidKinematics km = kin(1, p.floating_cone.com_z_m), kc = kin(0, p.fixed_cone.com_z_m);
    const ChamberForceResult cf = chamber.compute(km, kc, load == LoadModel::Bed, p.dt_s, &bed_state);
    el += cf.contact_potential + cf.bed_potential;
    if (bed_potential) *bed_potential = cf.bed_potential;
  }
  *kin_sum = ke;
  *grav_out = grav;
  *el_out = el;
  return ke + grav + el;
}

void Mechanism::Impl::apply_and_step() {
  const double dt = p.dt_s;
  // ---- velocities before the step (work is booked with the mean of old and new velocities) ----
  Eigen::Vector3d v0[kBodyCount], w0[kBodyCount];
  for (int i = 0; i < kBodyCount; ++i) v0[i] = lvel(i), w0[i] = avel(i);

  // Dissipative wrenches per category, per body (about COM).
  Eigen::Vector3d f_abs = Eigen::Vector3d::Zero(), t_abs = Eigen::Vector3d::Zero();
  // ---- absorbers (Table 1) at B1's COM ----
  const Eigen::Vector3d x1 = pos(0), v1 = lvel(0), w1 = avel(0);
  const Eigen::Vector3d d = x1 - b1_rest;
  const Eigen::Vector3d th = rotation_vector(rot(0));
  Eigen::Vector3d f_el = -p.absorber_k_N_per_m.cwiseProduct(d) + Eigen::Vector3d(0, 0, absorber_preload);
  f_abs = -p.absorber_c_Ns_per_m.cwiseProduct(v1);
  if (p.effects.absorber_nonlinearity.enabled) {
    const auto& an = p.effects.absorber_nonlinearity;
    f_el -= an.cubic_N_per_m3 * d.cwiseProduct(d).cwiseProduct(d);
    const double wref = std::max(1.0, p.drive_speed_rad_s);
    f_abs -= an.hysteresis / wref * p.absorber_k_N_per_m.cwiseProduct(v1);
  }
  const Eigen::Vector3d t_el = -k_rot.cwiseProduct(th);
  t_abs = -c_rot.cwiseProduct(w1);
  dBodyAddForce(body[0], f_el.x() + f_abs.x(), f_el.y() + f_abs.y(), f_el.z() + f_abs.z());
  dBodyAddTorque(body[0], t_el.x() + t_abs.x(), t_el.y() + t_abs.y(), t_el.z() + t_abs.z());

  // ---- cone contact and material bed ----
  const RigidKinematics km = kin(1, p.floating_cone.com_z_m), kc = kin(0, p.fixed_cone.com_z_m);
  const ChamberForceResult cf = chamber.compute(km, kc, load == LoadModel::Bed, dt, &bed_state, &bed_next);
  bed_state.swap(bed_next);
  auto apply = [&](int i, const Wrench& w) {
    const Eigen::Vector3d f = w.f_cons + w.f_diss, tq = w.t_cons + w.t_diss;
    dBodyAddForce(body[i], f.x(), f.y(), f.z());
    dBodyAddTorque(body[i], tq.x(), tq.y(), tq.z());
  };
  apply(1, cf.on_mantle);
  apply(0, cf.on_concave);
  min_gap = cf.min_gap;
  bed_force = cf.bed_normal_force;
  contact_force = cf.contact_normal_force;

  // ---- joint friction effect: O1 (B2 vs B1) and O3 (vibrator bearing, B3 vs B2 about the axis) ----
  Eigen::Vector3d t_jf1 = Eigen::Vector3d::Zero(), t_jf3 = Eigen::Vector3d::Zero();
  if (p.effects.joint_friction.enabled) {
    const auto& jf = p.effects.joint_friction;
    auto law = [&](const Eigen::Vector3d& wrel) -> Eigen::Vector3d {
      const double n = wrel.norm();
      if (n < 1e-15) return Eigen::Vector3d::Zero();
      return -(jf.coulomb_Nm * std::tanh(n / jf.regularisation_rad_s) / n + jf.viscous_Nms) * wrel;
    };
    t_jf1 = law(avel(1) - avel(0));
    const Eigen::Vector3d ax = rot(1).col(2);
    t_jf3 = law(ax * ax.dot(avel(2) - avel(1)));
    dBodyAddTorque(body[1], t_jf1.x() - t_jf3.x(), t_jf1.y() - t_jf3.y(), t_jf1.z() - t_jf3.z());
    dBodyAddTorque(body[0], -t_jf1.x(), -t_jf1.y(), -t_jf1.z());
    dBodyAddTorque(body[2], t_jf3.x(), t_jf3.y(), t_jf3.z());
  }

  // ---- bearing friction effect: mu r |reaction| in O3 (about the axis) and O1 (all axes) ----
  // The reaction is the previous step's constraint force (dJointFeedback is written by dWorldStep): the explicit
  // force-then-step order of the other loads. O3's force is radial (the piston joint leaves the axis free); its
  // tilting moment is not counted (the vibrator's force acts at the bushing's centre).
  Eigen::Vector3d t_bf1 = Eigen::Vector3d::Zero(), t_bf3 = Eigen::Vector3d::Zero();
  if (p.effects.bearing_friction.enabled) {
    const auto& bf = p.effects.bearing_friction;
    auto coulomb = [&](const Eigen::Vector3d& wrel, double t_max) -> Eigen::Vector3d {
      const double n = wrel.norm();
      if (n < 1e-15 || t_max <= 0) return Eigen::Vector3d::Zero();
      return -t_max * std::tanh(n / bf.regularisation_rad_s) / n * wrel;
    };
    const Eigen::Vector3d ax = rot(1).col(2);
    t_bf3 = coulomb(ax * ax.dot(avel(2) - avel(1)), bf.mu * bf.bushing_radius_m * vec(o3_feedback.f1).norm());
    t_bf1 = coulomb(avel(1) - avel(0), bf.mu * bf.sphere_radius_m * vec(o1_feedback.f1).norm());
    dBodyAddTorque(body[1], t_bf1.x() - t_bf3.x(), t_bf1.y() - t_bf3.y(), t_bf1.z() - t_bf3.z());
    dBodyAddTorque(body[0], -t_bf1.x(), -t_bf1.y(), -t_bf1.z());
    dBodyAddTorque(body[2], t_bf3.x(), t_bf3.y(), t_bf3.z());
  }

  // ---- external (particle) wrenches ----
  for (int i = 0; i < kBodyCount; ++i) {
    dBodyAddForce(body[i], ext_f[i].x(), ext_f[i].y(), ext_f[i].z());
    dBodyAddTorque(body[i], ext_t[i].x(), ext_t[i].y(), ext_t[i].z());
  }

  // ---- drive: ramp to the set speed, optional droop with the last torque ----
  const double ramp = p.drive_ramp_s > 0 ? std::min(1.0, (t_before + t + dt) / p.drive_ramp_s) : 1.0;
  const double smooth = ramp * ramp * (3.0 - 2.0 * ramp);
  double w_cmd = p.drive_speed_rad_s * smooth;
  double droop_torque = 0;
  if (droop) {
    const double w = dJointGetHingeAngleRate(o7);
    droop_torque = std::clamp((w_cmd - w) / p.effects.motor_droop.droop_rad_s_per_Nm, -p.drive_max_torque_Nm,
                              p.drive_max_torque_Nm);
    dJointAddHingeTorque(o7, droop_torque);
  } else {
    dJointSetHingeParam(o7, dParamVel, w_cmd);
  }
  {  // O4 planar: rotational rows driven by the misalignment of the globe bearing to the vibrator
    const Eigen::Matrix3d R3 = rot(2);
    const Eigen::Vector3d mis = R3.col(2).cross(rot(3).col(2));
    const double k = kErp / dt;  // same error reduction as the ODE joints
    dJointSetAMotorParam(o4_rot, dParamVel, k * mis.dot(R3.col(0)));
    dJointSetAMotorParam(o4_rot, dParamVel2, k * mis.dot(R3.col(1)));
  }

  dWorldStep(world, dt);
  t += dt;
  ++steps;

  // ---- bookkeeping ----
  Eigen::Vector3d vm[kBodyCount], wm[kBodyCount];
  for (int i = 0; i < kBodyCount; ++i) vm[i] = 0.5 * (v0[i] + lvel(i)), wm[i] = 0.5 * (w0[i] + avel(i));
  torque = droop ? droop_torque : vec(o7_feedback.t1).dot(drive_axis);
  const double w_drive = wm[5].dot(drive_axis);
  audit.drive_work += torque * w_drive * dt;
  audit.motor_input_work += motor_input_power(p.effects.drive_efficiency, torque * w_drive, w_drive) * dt;
  audit.absorber_dissipation -= (f_abs.dot(vm[0]) + t_abs.dot(wm[0])) * dt;
  auto diss = [&](int i, const Wrench& w) { return -(w.f_diss.dot(vm[i]) + w.t_diss.dot(wm[i])) * dt; };
  audit.contact_dissipation += diss(1, cf.contact_on_mantle) + diss(0, cf.contact_on_concave);
  audit.bed_dissipation += diss(1, cf.bed_on_mantle) + diss(0, cf.bed_on_concave);
  if (hysteretic_bed()) {  // the force's work minus what the bed stores is lost (stored: at the step start)
    audit.bed_dissipation -= cf.bed_potential - bed_stored_booked;
    bed_stored_booked = cf.bed_potential;
  }
  audit.joint_friction_dissipation -=
      (t_jf1.dot(wm[1] - wm[0]) + t_jf3.dot(wm[2] - wm[1])) * dt;
  audit.bushing_friction_dissipation -= t_bf3.dot(wm[2] - wm[1]) * dt;
  audit.sphere_friction_dissipation -= t_bf1.dot(wm[1] - wm[0]) * dt;
  for (int i = 0; i < kBodyCount; ++i) audit.external_work += (ext_f[i].dot(vm[i]) + ext_t[i].dot(wm[i])) * dt;
  // Test point kinematics
  const Eigen::Matrix3d R1 = rot(0);
  const Eigen::Vector3d tv = lvel(0) + avel(0).cross(R1 * tp_local);
  tp_acc = (tv - tp_vel_prev) / dt;
  tp_vel_prev = tv;
  for (int i = 0; i < kBodyCount; ++i) {
    const Eigen::Vector3d x = pos(i);
    if (!x.allFinite() || x.norm() > 100.0) {
      std::ostringstream s;
      s << "mbd: numerical blow-up at step " << steps << " (t = " << t << " s): body " << body_name(BodyId(i))
        << " at [" << x.transpose() << "] m; state dump: drive torque " << torque << " N m, min gap "
        << min_gap * 1e3 << " mm, bed force " << bed_force << " N, contact force " << contact_force
        << " N. Reduce mbd.time_step_s or check the bed/contact parameters.";
      throw std::runtime_error(s.str());
    }
  }
}

double Mechanism::Impl::constraint_error() const {
  double e = 0;
  auto pt = [&](void (*f1)(dJointID, dVector3), void (*f2)(dJointID, dVector3), dJointID j) {
    dVector3 a, b;
    f1(j, a);
    f2(j, b);
    e = std::max(e, (vec(a) - vec(b)).norm());
  };
  pt(dJointGetBallAnchor, dJointGetBallAnchor2, o1);
  pt(dJointGetBallAnchor, dJointGetBallAnchor2, o2);
  pt(dJointGetUniversalAnchor, dJointGetUniversalAnchor2, o6);
  pt(dJointGetHingeAnchor, dJointGetHingeAnchor2, o7);
  {
    dVector3 a1, a2;
    dJointGetUniversalAxis1(o6, a1);
    dJointGetUniversalAxis2(o6, a2);
    e = std::max(e, std::abs(vec(a1).dot(vec(a2))));
  }
  const Eigen::Matrix3d R2 = rot(1), R3 = rot(2), R4 = rot(3), R5 = rot(4), R6 = rot(5);
  const Eigen::Vector3d z2 = R2.col(2), z3 = R3.col(2), z4 = R4.col(2);
  // O3 cylindrical: axes parallel, vibrator axis point on the floating-cone axis line.
  const Eigen::Vector3d a3 = pos(2) + R3 * Eigen::Vector3d(-ecc, 0, 0);
  const Eigen::Vector3d r = a3 - pos(1);
  e = std::max(e, z2.cross(z3).norm());
  e = std::max(e, (r - r.dot(z2) * z2).norm());
  // O4 planar: B4 and B3 axes parallel, normal distance constant.
  e = std::max(e, z4.cross(z3).norm());
  e = std::max(e, std::abs((pos(3) - a3).dot(z3) - o4_normal_rest));
  // O5 ball-pin: pin point of B5 on the vibrator axis; B5's y axis perpendicular to B3's x axis.
  const Eigen::Vector3d pin = pos(4) + R5 * Eigen::Vector3d(0, 0, p.ball_pin_z_m - p.connecting_shaft.com_z_m);
  const Eigen::Vector3d rp = pin - a3;
  e = std::max(e, (rp - rp.dot(z3) * z3).norm());
  e = std::max(e, std::abs(R3.col(0).dot(R5.col(1))));
  // O7: drive shaft axis along the hinge axis.
  e = std::max(e, R6.col(2).cross(drive_axis).norm());
  return e;
}

Mechanism::Mechanism(const MechanismParams& params, LoadModel load) : impl_(new Impl(params, load)) {
  validate(params, load == LoadModel::Bed);
  impl_->build();
}
Mechanism::~Mechanism() = default;

void Mechanism::step() { impl_->apply_and_step(); }
void Mechanism::advance(double s) {
  const long n = std::lround(s / impl_->p.dt_s);
  for (long i = 0; i < n; ++i) impl_->apply_and_step();
}
void Mechanism::warm_start(double s, LoadModel during) {
  const LoadModel keep = impl_->load;
  impl_->load = during;
  advance(s);
  impl_->load = keep;
  impl_->t_before += impl_->t;
  impl_->t = 0;
}
double Mechanism::time() const { return impl_->t; }
double Mechanism::dt() const { return impl_->p.dt_s; }
const MechanismParams& Mechanism::params() const { return impl_->p; }

BodyState Mechanism::body(BodyId id) const {
  const int i = static_cast<int>(id);
  BodyState s;
  s.position = impl_->pos(i);
  const dReal* q = dBodyGetQuaternion(impl_->body[i]);
  s.orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
  s.linear_velocity = impl_->lvel(i);
  s.angular_velocity = impl_->avel(i);
  return s;
}

Eigen::Isometry3d Mechanism::liner_pose(BodyId id) const {
  if (id != BodyId::FloatingCone && id != BodyId::FixedCone)
    throw std::invalid_argument(std::string("mbd: no liner on ") + body_name(id));
  const int i = static_cast<int>(id);
  const double com_z = id == BodyId::FixedCone ? impl_->p.fixed_cone.com_z_m : impl_->p.floating_cone.com_z_m;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = impl_->rot(i);
  T.translation() = impl_->pos(i) + impl_->rot(i) * Eigen::Vector3d(0, 0, -com_z);
  return T;
}

Eigen::Vector3d Mechanism::test_point_offset() const { return impl_->tp_local; }

TestPointState Mechanism::test_point() const {
  TestPointState s;
  const Eigen::Matrix3d R1 = impl_->rot(0);
  const Eigen::Vector3d arm = R1 * impl_->tp_local;
  s.displacement = impl_->pos(0) + arm - impl_->tp_rest;
  s.velocity = impl_->lvel(0) + impl_->avel(0).cross(arm);
  s.acceleration = impl_->tp_acc;
  return s;
}

DriveState Mechanism::drive() const {
  DriveState d;
  d.speed = dJointGetHingeAngleRate(impl_->o7);
  d.torque = impl_->torque;
  d.power = d.torque * d.speed;
  d.input_power = motor_input_power(impl_->p.effects.drive_efficiency, d.power, d.speed);
  return d;
}

double Mechanism::nutation_angle() const {
  const Eigen::Vector3d z1 = impl_->rot(0).col(2), z2 = impl_->rot(1).col(2);
  return std::atan2(z1.cross(z2).norm(), z1.dot(z2));
}

double Mechanism::mantle_spin() const {
  const Eigen::Vector3d z2 = impl_->rot(1).col(2);
  return z2.dot(impl_->avel(1) - impl_->avel(0));
}

double Mechanism::min_gap() const { return impl_->min_gap; }
double Mechanism::constraint_error() const { return impl_->constraint_error(); }
double Mechanism::bed_force() const { return impl_->bed_force; }
double Mechanism::contact_force() const { return impl_->contact_force; }

void Mechanism::set_particle_wrench(BodyId id, const Eigen::Vector3d& force, const Eigen::Vector3d& torque) {
  if (!force.allFinite() || !torque.allFinite())
    throw std::invalid_argument(std::string("mbd: particle wrench on ") + body_name(id) + " is not finite");
  impl_->ext_f[static_cast<int>(id)] = force;
  impl_->ext_t[static_cast<int>(id)] = torque;
}

void Mechanism::set_load_model(LoadModel load) { impl_->load = load; }

EnergyAudit Mechanism::flows() const { return impl_->audit; }

EnergyAudit Mechanism::energy() const {
  EnergyAudit a = impl_->audit;
  double stored = 0;
  impl_->mech_energy_parts(&a.kinetic, &a.gravity_potential, &a.elastic_potential, &stored);
  if (impl_->hysteretic_bed()) a.bed_dissipation -= stored - impl_->bed_stored_booked;  // the last step's share
  return a;
}

}  // namespace mbd
