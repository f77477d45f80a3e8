#pragma once
// Where the drive's power goes between two audits of a Mechanism's energy flows (Mechanism::flows; mean powers over
// the span, W).

#include <string>

#include "mbd/mechanism.hpp"

namespace mbd {

struct PowerPartition {
  double span_s = 0;
  double drive = 0;             // into the drive shaft by the motor
  double load = 0;              // into the load (the DEM rock) by set_particle_wrench: minus its work on the bodies
  double absorbers = 0;         // rubber absorbers' dampers (frame vibration)
  double cone_contact = 0;      // mantle-concave contact, Eq. 11 and 13-15
  double bed = 0;               // equivalent material bed (bed runs)
  double joint_friction = 0;    // effects.joint_friction
  double bearing_friction = 0;  // effects.bearing_friction: bushing O3 + spherical support O1
  double motor_input = 0;       // the motor's input power (effects.drive_efficiency; = drive when off): drive + losses
  // drive - (the rest): the rise of the mechanism's kinetic, potential and elastic energy (about 0 over whole
  // cycles at a steady state) and what the integrator gained or lost
  double residual() const { return drive - load - absorbers - cone_contact - bed - joint_friction - bearing_friction; }
};

// Mean powers from flows `a` (at time ta) to flows `b` (at tb > ta). Throws std::invalid_argument if tb <= ta.
PowerPartition power_partition(const EnergyAudit& a, double ta, const EnergyAudit& b, double tb);

// One line in kW, e.g. "drive 45.10 kW = load 35.00 + absorbers 8.60 + ... (over 0.300 s)".
std::string describe(const PowerPartition& p);

}  // namespace mbd
