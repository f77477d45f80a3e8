// Checkpoint / restart of the mechanism: Mechanism::save_state and Mechanism::load_state (mechanism.hpp).
//
// File layout (core/binary_io.hpp: raw little-endian values, each block opened by a 4-character tag):
//   MECH  format version, body count, load model, time step (bits), parameters (to_yaml) as a fingerprint
//   CLCK  t, t_before (warm start), step count
//   BODY  x kBodyCount: index, position, quaternion, rotation matrix (3x4 as ODE stores it), linear and
//         angular velocity
//   JNTS  hinge motor velocity target (O7), planar-joint AMotor velocity targets (O4), O7 feedback
//   TPNT  test-point velocity of the last step and acceleration (finite-difference filter)
//   OUTP  last step's drive torque, min gap, bed force, contact force
//   EXTW  held particle wrenches (force, torque) per body
//   ENRG  energy audit
//   BEDS  hysteretic bed: stored energy booked, memory (both buffers: they alternate every step)
//   SRCH  contact search: last closest azimuth sample per mantle profile vertex
//   EFX2  only with effects.bearing_friction or effects.drive_efficiency on (the parameters say which, so files of
//         configs without them keep the version-1 layout): O1 and O3 joint feedback (the bearings' lagged loads),
//         the bushing and sphere friction dissipation, the motor input work
//   MEND
//
// Orientation, bit for bit: ODE integrates q, normalises it (dNormalize4) and sets R = dQtoR(q). Its setters
// cannot put those bits back: dBodySetQuaternion normalises again, and dNormalize4 is not idempotent (it
// multiplies by 1/sqrt(|q|^2), which is 1 +- 1 ulp for about 38 % of unit quaternions, changing their last
// bit), while dBodySetRotation re-orthogonalises R and derives q from it. load_state therefore calls
// dBodySetQuaternion (ODE's own bookkeeping) and then writes the saved q and R bits into the body's storage
// that dBodyGetQuaternion / dBodyGetRotation return (documented as pointers to the body's internal data;
// the body object itself is not const). The joints hold no evolving state beyond the velocity targets
// saved above: their reference frames come from the construction pose (rebuilt identically), limits are
// re-evaluated every step, dWorldStep keeps no solver warm start, and dJointFeedback is output only
// (saved so that it reads the same before the first step).
#include <ode/ode.h>

#include <cstdint>
#include <cstring>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/binary_io.hpp"
#include "mbd/mechanism.hpp"
#include "mbd/mechanism_impl.hpp"

namespace mbd {

namespace {

static_assert(sizeof(dReal) == sizeof(double), "checkpoints are written for double-precision ODE");
constexpr uint32_t kFormatVersion = 1;

const char* load_name(LoadModel l) { return l == LoadModel::Bed ? "bed" : "none"; }


// First line where two parameter listings differ, with the section it belongs to.
std::string first_difference(const std::string& a, const std::string& b) {
  std::istringstream sa(a), sb(b);
  std::string la, lb, section;
  while (true) {
    const bool ga = static_cast<bool>(std::getline(sa, la)), gb = static_cast<bool>(std::getline(sb, lb));
    if (!ga && !gb) return "";
    if (!ga) la = "(end)";
    if (!gb) lb = "(end)";
    if (la != lb) return "under '" + section + "': file has '" + la + "', this mechanism has '" + lb + "'";
    if (la.size() > 2 && la[0] == ' ' && la[1] == ' ' && la[2] != ' ') section = la.substr(2);
  }
}

struct SavedBody {
  dReal pos[3], q[4], R[12], lvel[3], avel[3];
};

// Everything load_state reads, applied only once the whole file has been read and checked.
struct Staged {
  double t = 0, t_before = 0;
  int64_t steps = 0;
  SavedBody body[kBodyCount];
  double hinge_vel = 0, amotor_vel = 0, amotor_vel2 = 0;
  dJointFeedback feedback{};
  Eigen::Vector3d tp_vel_prev, tp_acc;
  double torque = 0, min_gap = 0, bed_force = 0, contact_force = 0;
  Eigen::Vector3d ext_f[kBodyCount], ext_t[kBodyCount];
  EnergyAudit audit;
  double bed_stored_booked = 0;
  BedState bed_state, bed_next;
  std::vector<int32_t> search;
  dJointFeedback o1_feedback{}, o3_feedback{};
};

bool has_effects_block(const MechanismParams& p) {
  return p.effects.bearing_friction.enabled || p.effects.drive_efficiency.enabled;
}
void put_feedback(core::BinaryWriter& w, const dJointFeedback& f) {
  w.put_doubles(f.f1, 3);
  w.put_doubles(f.t1, 3);
  w.put_doubles(f.f2, 3);
  w.put_doubles(f.t2, 3);
}
void get_feedback(core::BinaryReader& r, dJointFeedback& f) {
  r.get_doubles(f.f1, 3);
  r.get_doubles(f.t1, 3);
  r.get_doubles(f.f2, 3);
  r.get_doubles(f.t2, 3);
}

void put_audit(core::BinaryWriter& w, const EnergyAudit& a) {
  for (double v : {a.drive_work, a.absorber_dissipation, a.contact_dissipation, a.bed_dissipation,
                   a.joint_friction_dissipation, a.external_work, a.kinetic, a.gravity_potential,
                   a.elastic_potential})
    w.put<double>(v);
}
EnergyAudit get_audit(core::BinaryReader& r) {
  EnergyAudit a;
  for (double* v : {&a.drive_work, &a.absorber_dissipation, &a.contact_dissipation, &a.bed_dissipation,
                    &a.joint_friction_dissipation, &a.external_work, &a.kinetic, &a.gravity_potential,
                    &a.elastic_potential})
    *v = r.get<double>();
  return a;
}

}  // namespace

void Mechanism::save_state(core::BinaryWriter& w) const {
  const Impl& m = *impl_;
  w.tag("MECH");
  w.put<uint32_t>(kFormatVersion);
  w.put<uint32_t>(kBodyCount);
  w.put<int32_t>(static_cast<int32_t>(m.load));
  w.put<double>(m.p.dt_s);
  w.put_string(to_yaml(m.p));

  w.tag("CLCK");
  w.put<double>(m.t);
  w.put<double>(m.t_before);
  w.put<int64_t>(m.steps);

  for (int i = 0; i < kBodyCount; ++i) {
    w.tag("BODY");
    w.put<int32_t>(i);
    const dBodyID b = m.body[i];
    w.put_doubles(dBodyGetPosition(b), 3);
    w.put_doubles(dBodyGetQuaternion(b), 4);
    w.put_doubles(dBodyGetRotation(b), 12);
    w.put_doubles(dBodyGetLinearVel(b), 3);
    w.put_doubles(dBodyGetAngularVel(b), 3);
  }

  w.tag("JNTS");
  w.put<double>(dJointGetHingeParam(m.o7, dParamVel));
  w.put<double>(dJointGetAMotorParam(m.o4_rot, dParamVel));
  w.put<double>(dJointGetAMotorParam(m.o4_rot, dParamVel2));
  w.put_doubles(m.o7_feedback.f1, 3);
  w.put_doubles(m.o7_feedback.t1, 3);
  w.put_doubles(m.o7_feedback.f2, 3);
  w.put_doubles(m.o7_feedback.t2, 3);

  w.tag("TPNT");
  w.put_xyz(m.tp_vel_prev);
  w.put_xyz(m.tp_acc);

  w.tag("OUTP");
  w.put<double>(m.torque);
  w.put<double>(m.min_gap);
  w.put<double>(m.bed_force);
  w.put<double>(m.contact_force);

  w.tag("EXTW");
  for (int i = 0; i < kBodyCount; ++i) w.put_xyz(m.ext_f[i]), w.put_xyz(m.ext_t[i]);

  w.tag("ENRG");
  put_audit(w, m.audit);

  w.tag("BEDS");
  w.put<double>(m.bed_stored_booked);
  w.put_vec(m.bed_state);
  w.put_vec(m.bed_next);

  w.tag("SRCH");
  const std::vector<int>& k = m.chamber.contact_search_state();
  w.put_vec(std::vector<int32_t>(k.begin(), k.end()));

  if (has_effects_block(m.p)) {
    w.tag("EFX2");
    put_feedback(w, m.o1_feedback);
    put_feedback(w, m.o3_feedback);
    w.put<double>(m.audit.bushing_friction_dissipation);
    w.put<double>(m.audit.sphere_friction_dissipation);
    w.put<double>(m.audit.motor_input_work);
  }

  w.tag("MEND");
}

void Mechanism::load_state(core::BinaryReader& r) {
  Impl& m = *impl_;
  Staged s;

  r.expect("MECH");
  const uint32_t version = r.get<uint32_t>();
  if (version != kFormatVersion)
    r.fail("format version " + std::to_string(version) + ", this build reads version " +
           std::to_string(kFormatVersion));
  const uint32_t bodies = r.get<uint32_t>();
  if (bodies != uint32_t(kBodyCount))
    r.fail("body count " + std::to_string(bodies) + ", this mechanism has " + std::to_string(kBodyCount));
  const int32_t load = r.get<int32_t>();
  if (load != int32_t(LoadModel::None) && load != int32_t(LoadModel::Bed))
    r.fail("unknown load model " + std::to_string(load));
  if (LoadModel(load) != m.load)
    r.fail(std::string("saved with load model '") + load_name(LoadModel(load)) + "', this mechanism has '" +
           load_name(m.load) + "'");
  const double dt = r.get<double>();
  if (std::memcmp(&dt, &m.p.dt_s, sizeof dt) != 0)
    r.fail("saved with time step " + std::to_string(dt) + " s, this mechanism has " + std::to_string(m.p.dt_s) +
           " s");
  const std::string yaml = r.get_string();
  const std::string mine = to_yaml(m.p);
  if (yaml != mine) r.fail("saved with other mechanism parameters (" + first_difference(yaml, mine) + ")");

  r.expect("CLCK");
  s.t = r.get<double>();
  s.t_before = r.get<double>();
  s.steps = r.get<int64_t>();

  for (int i = 0; i < kBodyCount; ++i) {
    r.expect("BODY");
    const int32_t idx = r.get<int32_t>();
    if (idx != i) r.fail("body block " + std::to_string(idx) + " where body " + std::to_string(i) + " belongs");
    SavedBody& b = s.body[i];
    r.get_doubles(b.pos, 3);
    r.get_doubles(b.q, 4);
    r.get_doubles(b.R, 12);
    r.get_doubles(b.lvel, 3);
    r.get_doubles(b.avel, 3);
  }

  r.expect("JNTS");
  s.hinge_vel = r.get<double>();
  s.amotor_vel = r.get<double>();
  s.amotor_vel2 = r.get<double>();
  r.get_doubles(s.feedback.f1, 3);
  r.get_doubles(s.feedback.t1, 3);
  r.get_doubles(s.feedback.f2, 3);
  r.get_doubles(s.feedback.t2, 3);

  r.expect("TPNT");
  s.tp_vel_prev = r.get_xyz<Eigen::Vector3d>();
  s.tp_acc = r.get_xyz<Eigen::Vector3d>();

  r.expect("OUTP");
  s.torque = r.get<double>();
  s.min_gap = r.get<double>();
  s.bed_force = r.get<double>();
  s.contact_force = r.get<double>();

  r.expect("EXTW");
  for (int i = 0; i < kBodyCount; ++i) s.ext_f[i] = r.get_xyz<Eigen::Vector3d>(), s.ext_t[i] = r.get_xyz<Eigen::Vector3d>();

  r.expect("ENRG");
  s.audit = get_audit(r);

  r.expect("BEDS");
  s.bed_stored_booked = r.get<double>();
  const std::size_t cells = m.chamber.initial_bed_state().size();
  r.get_vec(s.bed_state, cells);
  r.get_vec(s.bed_next, cells);
  if (s.bed_state.size() != cells || s.bed_next.size() != cells)
    r.fail("bed memory has " + std::to_string(s.bed_state.size()) + "/" + std::to_string(s.bed_next.size()) +
           " cells, this mechanism " + std::to_string(cells));

  r.expect("SRCH");
  const std::size_t vertices = m.chamber.contact_search_state().size();
  r.get_vec(s.search, vertices);
  if (s.search.size() != vertices)
    r.fail("contact search state has " + std::to_string(s.search.size()) + " vertices, this mechanism " +
           std::to_string(vertices));
  for (int32_t k : s.search)
    if (k < 0 || k >= m.p.sampling.azimuth) r.fail("contact search sample " + std::to_string(k) + " out of range");

  if (has_effects_block(m.p)) {
    r.expect("EFX2");
    get_feedback(r, s.o1_feedback);
    get_feedback(r, s.o3_feedback);
    s.audit.bushing_friction_dissipation = r.get<double>();
    s.audit.sphere_friction_dissipation = r.get<double>();
    s.audit.motor_input_work = r.get<double>();
  } else {
    s.audit.motor_input_work = s.audit.drive_work;  // no drive losses: the motor's input is the shaft's work
  }

  r.expect("MEND");

  // ---- everything read and checked: apply ----
  m.chamber.set_contact_search_state(std::vector<int>(s.search.begin(), s.search.end()));
  for (int i = 0; i < kBodyCount; ++i) {
    const dBodyID b = m.body[i];
    const SavedBody& sb = s.body[i];
    dBodySetPosition(b, sb.pos[0], sb.pos[1], sb.pos[2]);
    dBodySetQuaternion(b, sb.q);  // ODE's own path (normalises q, recomputes R, moves geoms) ...
    // ... then the exact bits (see the top of this file: dNormalize4 is not idempotent).
    std::memcpy(const_cast<dReal*>(dBodyGetQuaternion(b)), sb.q, sizeof sb.q);
    std::memcpy(const_cast<dReal*>(dBodyGetRotation(b)), sb.R, sizeof sb.R);
    dBodySetLinearVel(b, sb.lvel[0], sb.lvel[1], sb.lvel[2]);
    dBodySetAngularVel(b, sb.avel[0], sb.avel[1], sb.avel[2]);
  }
  dJointSetHingeParam(m.o7, dParamVel, s.hinge_vel);
  dJointSetAMotorParam(m.o4_rot, dParamVel, s.amotor_vel);
  dJointSetAMotorParam(m.o4_rot, dParamVel2, s.amotor_vel2);
  m.o7_feedback = s.feedback;
  m.o1_feedback = s.o1_feedback;
  m.o3_feedback = s.o3_feedback;
  m.t = s.t;
  m.t_before = s.t_before;
  m.steps = static_cast<long>(s.steps);
  m.tp_vel_prev = s.tp_vel_prev;
  m.tp_acc = s.tp_acc;
  m.torque = s.torque;
  m.min_gap = s.min_gap;
  m.bed_force = s.bed_force;
  m.contact_force = s.contact_force;
  for (int i = 0; i < kBodyCount; ++i) m.ext_f[i] = s.ext_f[i], m.ext_t[i] = s.ext_t[i];
  m.audit = s.audit;
  m.bed_stored_booked = s.bed_stored_booked;
  m.bed_state = std::move(s.bed_state);
  m.bed_next = std::move(s.bed_next);
}

}  // namespace mbd
