#pragma once
// The inertia cone crusher mechanism (paper section 2, Figure 2) on ODE (double precision, dWorldStep).
//
// Bodies: B1 fixed cone (6 DOF on the rubber absorbers), B2 floating cone, B3 eccentric vibrator,
// B4 globe bearing, B5 connecting shaft, B6 drive shaft. Joint mapping to ODE:
//   O1 spherical B2-B1            dJointBall
//   O2 spherical B4-B2            dJointBall
//   O3 cylindrical B3-B2          dJointPiston (axis = floating-cone axis)
//   O4 planar B3-B4 (normal = axis; frees the two in-plane translations and the spin): 3 rows written
//                                 as dJointDBall (distance between the O2 centre and the vibrator axis
//                                 point: the normal distance, since both stay on the shaft axis) plus a
//                                 user-mode dJointAMotor with 2 rows about B3's x, y axes (relative
//                                 angular velocity zero, misalignment fed back with the joints ERP each step)
//   O5 ball-pin B3-B5 (fixes x, y translation and Rz)   dJointPU (prismatic along the vibrator axis,
//                                 universal with axes x of B3 and y of B5: transmits the torque about z)
//   O6 universal B5-B6            dJointUniversal
//   O7 revolute B6-ground         dJointHinge with a velocity motor (dParamVel, dParamFMax) and
//                                 dJointFeedback: drive torque = feedback torque on B6 along the axis.
// Forces computed by our code and applied with dBodyAddForce: absorbers (linear 6-DOF spring-damper at
// B1's COM), the cone contact (Eq. 11, 13-15) at the closest approach of mantle and concave, the
// equivalent material bed (chamber_forces.hpp), external particle wrenches, and the enabled effects.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <string>

#include "mbd/mechanism_params.hpp"

namespace core {
class BinaryWriter;
class BinaryReader;
}  // namespace core

namespace mbd {

enum class BodyId { FixedCone, FloatingCone, Vibrator, GlobeBearing, ConnectingShaft, DriveShaft };
constexpr int kBodyCount = 6;
const char* body_name(BodyId id);  // "fixed_cone", ...

struct BodyState {
  Eigen::Vector3d position;  // centre of mass, world
  Eigen::Quaterniond orientation;
  Eigen::Vector3d linear_velocity, angular_velocity;  // world
};

// Test point on the fixed cone: displacement from its rest (equilibrium) position, velocity and
// acceleration, world frame.
struct TestPointState {
  Eigen::Vector3d displacement, velocity, acceleration;
};

struct DriveState {
  double speed;   // rad/s, drive shaft about its axis
  double torque;  // N m, applied by the motor to the drive shaft
  double power;   // W = torque x speed (the drive shaft's power)
  double input_power;  // W, the motor's input power as a plant logs it (effects.drive_efficiency; = power when off)
};

// Cumulative energy audit since construction (J) and the current mechanical energy.
struct EnergyAudit {
  double drive_work = 0;             // integral of drive torque x speed
  double absorber_dissipation = 0;   // absorber dampers (+ hysteresis effect)
  double contact_dissipation = 0;    // Eq. 11 damping + Eq. 13-15 friction
  double bed_dissipation = 0;        // bed viscosity + bed friction
  double joint_friction_dissipation = 0;
  double bushing_friction_dissipation = 0;    // effects.bearing_friction in O3
  double sphere_friction_dissipation = 0;     // effects.bearing_friction in O1
  double external_work = 0;          // work of set_particle_wrench loads
  double motor_input_work = 0;       // integral of the motor's input power (effects.drive_efficiency; = drive_work when off)
  double kinetic = 0, gravity_potential = 0, elastic_potential = 0;  // current
  double mechanical_energy() const { return kinetic + gravity_potential + elastic_potential; }
  double dissipation() const {
    return absorber_dissipation + contact_dissipation + bed_dissipation + joint_friction_dissipation +
           bushing_friction_dissipation + sphere_friction_dissipation;
  }
};

enum class LoadModel { None, Bed };  // None also for a DEM-coupled run (loads via set_particle_wrench)
// "none" | "bed" (also "dem" -> None: the particles load the liners). Throws std::invalid_argument.
LoadModel load_model_from_string(const std::string& s);

class Mechanism {
 public:
  explicit Mechanism(const MechanismParams& params, LoadModel load = LoadModel::Bed);
  ~Mechanism();
  Mechanism(const Mechanism&) = delete;
  Mechanism& operator=(const Mechanism&) = delete;

  void step();              // one time step dt
  void advance(double s);   // whole steps covering s seconds
  // Runs s seconds with the load `during`, then sets the clock back to 0 (the drive stays at speed, the ramp
  // is not repeated): the same trajectory as a run from rest, s seconds later. Keeps the load model.
  void warm_start(double s, LoadModel during);
  double time() const;
  double dt() const;
  const MechanismParams& params() const;

  BodyState body(BodyId id) const;
  // Pose of a liner frame in the world (core/chamber_geometry.hpp: origin at O1 of the untilted
  // assembly, z along the body axis): FloatingCone -> mantle profile frame, FixedCone -> concave.
  // Liner meshes built from the (z, r) profiles are placed with this transform.
  Eigen::Isometry3d liner_pose(BodyId id) const;
  TestPointState test_point() const;
  Eigen::Vector3d test_point_offset() const;  // m, the test point in the fixed cone's body frame (from its origin)
  DriveState drive() const;
  double nutation_angle() const;  // rad, angle between the floating-cone axis and the fixed-cone axis
  double mantle_spin() const;     // rad/s, floating cone about its own axis relative to the fixed cone
  double min_gap() const;  // m, closest approach of mantle and concave (negative = indentation); while the
                           // cones are certainly apart this is a cheap lower bound (no search is run)
  double constraint_error() const;  // m: max joint anchor mismatch (angles x 1 m), see mechanism.cpp
  double bed_force() const;       // N, total normal force of the bed on the mantle (last step)
  double contact_force() const;   // N, normal force of the cone contact (last step)

  // External (particle) wrench on a body, about its centre of mass, world frame. Held until changed.
  void set_particle_wrench(BodyId id, const Eigen::Vector3d& force, const Eigen::Vector3d& torque_about_com);
  void set_load_model(LoadModel load);

  EnergyAudit energy() const;  // cumulative works + current energy
  // The cumulative works and dissipations alone (current energies left 0; a hysteretic bed's last-step share not
  // booked), without the contact search energy() runs, so calling it leaves every later step bit for bit the same.
  EnergyAudit flows() const;

  // Checkpoint / restart (core/binary_io.hpp; mechanism_checkpoint.cpp). save_state writes the complete
  // evolving state, nothing that the parameters determine: every body's position, quaternion, rotation
  // matrix and velocities (bits as ODE holds them); the clock (t, warm-start t_before, step count); the
  // motor and planar-joint velocity targets and the drive feedback; the test-point filter; the last
  // step's outputs (torque, min gap, bed and contact force); the held particle wrenches; the energy
  // audit; the hysteretic bed memory (both buffers) and its stored-energy booking; the contact search's
  // last closest samples; and the load model, with the parameters (to_yaml) as a fingerprint. The enabled
  // effects keep no state of their own (absorber loss and droop act on the current velocities; the
  // droop's torque is the last drive torque). save_state changes nothing. load_state restores it into a
  // Mechanism constructed with the same parameters and load model, the joints keeping their frames from the construction pose as in the original run: the
  // continuation is bit for bit the uninterrupted run. Throws std::runtime_error naming what does not
  // match (block tag, format version, load model, body count, parameters, array size, truncated file)
  // and then leaves this Mechanism unchanged. 6.7 kB with the shipped sampling (3.1 kB bed memory, 1.6 kB
  // parameter listing).
  void save_state(core::BinaryWriter& w) const;
  void load_state(core::BinaryReader& r);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mbd
