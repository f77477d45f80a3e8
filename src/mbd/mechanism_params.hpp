#pragma once
// Parameters of the crusher mechanism (paper section 2, Figure 2, Table 1), SI units throughout.
// Defaults are the GYP1200 at 400 rpm as in launch_free_configs/gyp1200_400rpm.yaml; every value the
// paper does not give is documented there with its source or reasoning.
//
// Geometry convention: world z up, origin at the centre of the spherical joint O1 in the assembled
// untilted crusher at rest; all bodies start on the crusher axis l0 (z). Heights *_z are along z.
#include <Eigen/Core>
#include <string>

#include "core/chamber_geometry.hpp"
#include "core/config.hpp"

namespace mbd {

struct BodyParams {
  double mass_kg = 1.0;
  double com_z_m = 0.0;                                    // centre of mass height (on the axis)
  Eigen::Vector3d inertia_kg_m2 = Eigen::Vector3d::Ones();  // principal, about the COM, body axes
};

// Eq. 11 and Eq. 13-15 (Table 1), converted to SI at load.
struct ContactParams {
  double k = 1e5 * 3.1622776601683795e4;  // N/m^h1 (Table 1: 1e5 N/mm^1.5 -> k*1000^h1)
  double h1 = 1.5;                         // stiffness exponent
  double c = 50.0 * 1e9;                   // N (s/m)^h2 / m^h3 (Table 1: 50 -> c*1000^(h2+h3))
  double h2 = 1.0;                         // damping exponent
  double h3 = 2.0;                         // indentation exponent
  double mu_s = 0.3, mu_d = 0.25;          // static / dynamic threshold coefficients
  double v_s = 1e-3, v_d = 10e-3;          // m/s (Table 1: 1 and 10 mm/s)
};

// Equivalent material-bed load (computed in chamber_forces.cpp): pressure on the mantle where the local gap g is
// smaller than engage_ratio * g_rest (g_rest: gap of the untilted assembly at that height):
//   strain e = 1 - g / (engage_ratio g_rest),  p = modulus e^exponent + viscosity * e_dot (closing only,
//   faded in over the first 5 % strain), force p x patch area along the local concave normal, reacted
//   on the concave; tangential bed friction by the Eq. 14 law with bed velocities. Calibrated at 400 rpm.
//   Known limit: the crushing force grows ~ w^2, so the viscous bed's power grows ~ w^4: 600 rpm is
//   over-predicted (~415 kW vs 146 kW measured, Table 5) while the amplitude validates (5.89 vs 5.74 mm).
// Bed laws: viscous (elastic p = E e^n plus a loss proportional to the closing rate) or hysteretic
// (rate-independent: virgin loading p = E (e - e0)^n, elastic unloading that recovers the fraction
// `rebound` of the compression, refill when the gap reopens; chamber_forces.hpp).
enum class BedLaw { Viscous, Hysteretic };

struct BedParams {
  BedLaw law = BedLaw::Viscous;
  double rebound = 1.0;            // hysteretic: recovered fraction of each compression (1: elastic)
  double modulus_Pa = 8e6;
  double exponent = 1.5;
  double engage_ratio = 0.9;
  double viscosity_Pa_s = 1.9e5;   // Pa per unit strain rate (1/s)
  double friction = 0.5;           // bed-on-mantle friction coefficient (Eq. 14 law, bed velocities)
  double v_s = 5e-3, v_d = 20e-3;  // m/s, stick/slip thresholds of the bed friction law
};

struct Sampling {
  int azimuth = 24;    // samples around the circumference (cone contact and bed)
  int generator = 4;   // samples along the mantle generator
};

// Omitted-physics modules (all off by default; YAML mbd.effects.<name>).
struct JointFriction {  // torque in O1 (floating/fixed cone) and O3 (vibrator bearing on the shaft)
  bool enabled = false;
  double coulomb_Nm = 0.0;
  double viscous_Nms = 0.0;
  double regularisation_rad_s = 0.05;  // Coulomb law smoothed as tanh(w / w_eps)
};
struct AbsorberNonlinearity {  // F = k1 d + k3 d^3 (+ hysteresis eta k1 d_dot / w_drive), per axis
  bool enabled = false;
  double cubic_N_per_m3 = 0.0;
  double hysteresis = 0.0;  // loss factor eta
};
struct MotorDroop {  // drive speed = w0 - droop * torque
  bool enabled = false;
  double droop_rad_s_per_Nm = 0.0;  // config: droop_rad_s_per_kNm
};
struct CardanMisalignment {  // drive shaft axis tilted by angle about the universal joint O6
  bool enabled = false;
  double angle_rad = 0.0;  // config: angle_deg
};
// Load-proportional (Coulomb) friction of the plain bearings, the joint friction of RecurDyn / Adams: torque
// mu x r x |joint reaction force| against the relative rotation (tanh-smoothed), in the vibrator's bushing O3
// (r = bushing radius, about the axis) and the spherical support O1 (r = sphere radius, all three axes). The reaction
// is the previous step's constraint force (dJointFeedback). Main parameter: mu (only mu x r enters; the radii are
// fixed estimates, src/mbd/README.md). Its power grows as w^3 (bushing load ~ m e w^2, sliding speed ~ w).
struct BearingFriction {
  bool enabled = false;
  double mu = 0.0;
  double bushing_radius_m = 0.10;   // config: bushing_radius_mm (O3)
  double sphere_radius_m = 0.40;    // config: sphere_radius_mm (O1; 0: no friction in O1)
  double regularisation_rad_s = 0.05;
};
// The drive between the motor's terminals and the drive shaft (mbd/drive_efficiency.hpp): the plant logs the motor's
// input power = shaft power / efficiency + a no-load loss P0 (w / w_ref)^k (with regeneration, shaft power x
// efficiency). A measurement transform: the motion is unchanged; DriveState::input_power and the recordings follow it.
struct DriveEfficiency {
  bool enabled = false;
  double efficiency = 1.0;
  double no_load_W = 0.0;                                             // config: no_load_kW, at the reference speed
  double reference_speed_rad_s = 400.0 * 2.0 * 3.14159265358979323846 / 60.0;  // config: reference_rpm
  double speed_exponent = 2.0;
};
struct Effects {
  JointFriction joint_friction;
  AbsorberNonlinearity absorber_nonlinearity;
  MotorDroop motor_droop;
  CardanMisalignment cardan_misalignment;
  BearingFriction bearing_friction;
  DriveEfficiency drive_efficiency;
};

struct MechanismParams {
  // Integration
  double dt_s = 1e-3;
  double gravity_m_s2 = 9.81;
  // Drive (O7): constant speed after a ramp from rest
  double drive_speed_rad_s = 400.0 * 2.0 * 3.14159265358979323846 / 60.0;
  double drive_ramp_s = 1.0;
  double drive_max_torque_Nm = 2e5;
  // Bodies B1..B6 (Table 1 masses; positions, inertias: config reasoning)
  BodyParams fixed_cone, floating_cone, vibrator, globe_bearing, connecting_shaft, drive_shaft;
  double vibrator_static_moment_kg_m = 119.0;  // mass x eccentricity (calibrated at 400 rpm)
  double vibrator_axis_z_m = -1.3;            // O3: vibrator centre on the floating-cone axis
  double globe_bearing_z_m = -1.15;           // O2 (and the plane of O4)
  double ball_pin_z_m = -1.45;                // O5 on the vibrator axis
  double universal_z_m = -2.1;                // O6 on the crusher axis
  double drive_shaft_length_m = 0.6;          // O7 hinge below O6 (drive shaft COM at its middle)
  // Rubber absorbers (Table 1, totals of all absorbers), acting at the fixed cone's COM
  Eigen::Vector3d absorber_k_N_per_m{320e3, 320e3, 970e3};
  Eigen::Vector3d absorber_c_Ns_per_m{100e3, 100e3, 100e3};
  double absorber_ring_radius_m = 1.0;  // gives tilt/twist stiffness and damping
  // Test point on the fixed cone (world position at rest)
  Eigen::Vector3d test_point_m{1.0, 0.0, -0.6};
  ContactParams contact;
  BedParams bed;
  Sampling sampling;
  core::ChamberGeometry chamber;  // mantle / concave profiles
  Effects effects;

  MechanismParams();  // fills the GYP1200 400 rpm defaults (bodies, chamber)
  double vibrator_eccentricity_m() const { return vibrator_static_moment_kg_m / vibrator.mass_kg; }
};

// Reads the `mbd:` mapping of a run config (the caller calls finish() on the root).
MechanismParams load_mechanism_params(const core::ConfigNode& mbd_section);
// Loads the `mbd:` section of a run configuration file and checks the rest of the file the way the
// nodes read it (run:, coupling:; the dem: section belongs to dem_node): for tools that need only the
// mechanism (benchmarks, diagnosis, recording generator).
MechanismParams load_mechanism_params_file(const std::string& path);
// Whole-parameter checks (ranges, geometry order, time step vs the stiffest element).
// Throws std::invalid_argument naming the key (mbd.<...>), the value and the accepted range. with_bed false: the
// equivalent bed is not the load (idle, flow and coupled runs), its stiffness does not bound the step.
void validate(const MechanismParams& p, bool with_bed = true);
// The stable-step bound used by validate(): min over elements of sqrt(m/k) (s), and which element.
double stable_step_bound(const MechanismParams& p, std::string* element = nullptr, bool with_bed = true);
// Writes an `mbd:` section (with the top-level key) that load_mechanism_params reads back.
std::string to_yaml(const MechanismParams& p);

}  // namespace mbd
