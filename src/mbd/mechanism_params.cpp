#include "mbd/mechanism_params.hpp"

#include "core/chamber_geometry_schema.hpp"
#include "core/run_config.hpp"
#include "mbd/mechanism_schema.hpp"

#include <cmath>
#include <functional>
#include <iomanip>
#include <tuple>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/units.hpp"

namespace mbd {

namespace u = core::units;

MechanismParams::MechanismParams() {
  // Table 1 masses; heights and inertias: see launch_free_configs/gyp1200_400rpm.yaml.
  fixed_cone = {24124.4, -0.70, {16000.0, 16000.0, 20000.0}};
  floating_cone = {4495.1, -0.55, {700.0, 700.0, 500.0}};
  vibrator = {784.5, -1.30, {25.0, 25.0, 30.0}};
  globe_bearing = {150.0, -1.15, {3.0, 3.0, 5.0}};
  connecting_shaft = {120.0, -1.775, {4.5, 4.5, 0.3}};
  drive_shaft = {100.0, -2.40, {3.0, 3.0, 0.5}};
  chamber.mantle.z = {-0.200, -0.715};
  chamber.mantle.r = {0.168, 0.600};
  chamber.concave.z = {-0.100, -0.760};
  chamber.concave.r = {0.194, 0.662};
}

namespace {

using P = MechanismParams;
using S = core::Schema<MechanismParams>;
template <class V>
using Ref = std::function<V&(P&)>;

// Plausible bands (core::Schema::plausible): a value inside a key's range but ~1000x off is a unit slip (issue 22:
// `com_z_mm: -0.7`, absorber stiffness x1000 passed). Points of the machine lie 10 mm to 10 m from O1 (or on it: 0).
constexpr double kPointLo_mm = 10, kPointHi_mm = 10000;
using core::kMetresForMm;

// mass_kg, com_z_mm (if com), inertia_kg_m2 of a body under `name`.
void body(S& k, const std::string& name, Ref<BodyParams> b, double mass_lo, double mass_hi, bool with_com,
          const std::string& what) {
  k.number(name + ".mass_kg", "kg", 1, mass_lo, mass_hi, [b](P& p) -> double& { return b(p).mass_kg; },
           what + ": mass", true);
  if (with_com)  // the cones: 50 kg (a laboratory crusher's) to 1000 t
    k.plausible(50, 1e6, "tonnes given for kg?", "grams given for kg?")
        .number(name + ".com_z_mm", "mm", u::mm, -10000, 10000, [b](P& p) -> double& { return b(p).com_z_m; },
                what + ": centre of mass height on the axis", true)
        .plausible(kPointLo_mm, kPointHi_mm, kMetresForMm, "");
}
void inertia(S& k, const std::string& name, Ref<BodyParams> b, const std::string& what) {
  k.vector3(name + ".inertia_kg_m2", "kg m^2", 1, 1e-6, 1e7, [b](P& p) -> Eigen::Vector3d& { return b(p).inertia_kg_m2; },
            what + ": principal inertias about the COM", true);
}

}  // namespace

const core::Schema<MechanismParams>& mechanism_schema() {
  static const S s = [] {
    S k;
    k.number("time_step_s", "s", 1, 1e-6, 5e-3, [](P& p) -> double& { return p.dt_s; },
             "integration step (bounded by the stiffest element and 0.05 rad of drive per step)", true)
        .number("gravity_m_s2", "m/s^2", 1, 0.0, 20.0, [](P& p) -> double& { return p.gravity_m_s2; }, "gravity",
                true)
        .number("drive.speed_rpm", "rpm", u::rpm, 1.0, 2000.0, [](P& p) -> double& { return p.drive_speed_rad_s; },
                "drive speed after the ramp", true)
        .number("drive.ramp_s", "s", 1, 0.0, 60.0, [](P& p) -> double& { return p.drive_ramp_s; },
                "start-up ramp from rest", true)
        .number("drive.max_torque_kNm", "kN m", 1e3, 0.1, 1e4, [](P& p) -> double& { return p.drive_max_torque_Nm; },
                "motor torque limit", true);
    body(k, "drive", [](P& p) -> BodyParams& { return p.drive_shaft; }, 0.1, 1e4, false, "B6 drive shaft");
    inertia(k, "drive", [](P& p) -> BodyParams& { return p.drive_shaft; }, "B6 drive shaft");
    k.number("drive.length_mm", "mm", u::mm, 10, 5000, [](P& p) -> double& { return p.drive_shaft_length_m; },
             "O7 hinge below O6 (shaft COM at its middle)", true);
    for (const auto& [name, what, ref] :
         {std::tuple<std::string, std::string, Ref<BodyParams>>{"fixed_cone", "B1 fixed cone",
                                                                [](P& p) -> BodyParams& { return p.fixed_cone; }},
          {"floating_cone", "B2 floating cone", [](P& p) -> BodyParams& { return p.floating_cone; }}}) {
      body(k, name, ref, 1.0, 1e6, true, what);
      inertia(k, name, ref, what);
    }
    body(k, "vibrator", [](P& p) -> BodyParams& { return p.vibrator; }, 1.0, 1e5, false, "B3 vibrator");
    inertia(k, "vibrator", [](P& p) -> BodyParams& { return p.vibrator; }, "B3 vibrator");
    k.number("vibrator.axis_z_mm", "mm", u::mm, -10000, 0, [](P& p) -> double& { return p.vibrator_axis_z_m; },
             "O3: vibrator centre on the floating-cone axis", true)
        .plausible(kPointLo_mm, kPointHi_mm, kMetresForMm, "")
        .number("vibrator.static_moment_kg_m", "kg m", 1, 0.0, 1e4,
                [](P& p) -> double& { return p.vibrator_static_moment_kg_m; },
                "mass x eccentricity (at most 0.5 m eccentricity)", true);
    body(k, "globe_bearing", [](P& p) -> BodyParams& { return p.globe_bearing; }, 0.1, 1e5, false, "B4 globe bearing");
    inertia(k, "globe_bearing", [](P& p) -> BodyParams& { return p.globe_bearing; }, "B4 globe bearing");
    k.number("globe_bearing.joint_z_mm", "mm", u::mm, -10000, 0, [](P& p) -> double& { return p.globe_bearing_z_m; },
             "O2, below O1 and above O3", true)
        .plausible(kPointLo_mm, kPointHi_mm, kMetresForMm, "");
    body(k, "connecting_shaft", [](P& p) -> BodyParams& { return p.connecting_shaft; }, 0.1, 1e5, false,
         "B5 connecting shaft");
    inertia(k, "connecting_shaft", [](P& p) -> BodyParams& { return p.connecting_shaft; }, "B5 connecting shaft");
    k.number("connecting_shaft.ball_pin_z_mm", "mm", u::mm, -10000, 0, [](P& p) -> double& { return p.ball_pin_z_m; },
             "O5 on the vibrator axis", true)
        .plausible(kPointLo_mm, kPointHi_mm, kMetresForMm, "")
        .number("connecting_shaft.universal_z_mm", "mm", u::mm, -10000, 0,
                [](P& p) -> double& { return p.universal_z_m; }, "O6 on the crusher axis", true)
        .plausible(kPointLo_mm, kPointHi_mm, kMetresForMm, "")
        .vector3("absorbers.stiffness_N_per_mm", "N/mm", u::N_per_mm, 1e-3, 1e7,
                 [](P& p) -> Eigen::Vector3d& { return p.absorber_k_N_per_m; }, "rubber absorbers, total k_x k_y k_z",
                 true)
        // Rubber isolators hold the frame's mode at ~0.5-5 Hz: k = m (2 pi f)^2 is 10 N/mm for 1 t at 0.5 Hz,
        // 1e5 N/mm for 100 t at 5 Hz (Table 1: 320-970 N/mm for 24 t, ~0.5 Hz).
        .plausible(10, 1e5, "kN/mm given for N/mm?", "N/m given for N/mm?")
        .vector3("absorbers.damping_Ns_per_mm", "N s/mm", u::Ns_per_mm, 0.0, 1e6,
                 [](P& p) -> Eigen::Vector3d& { return p.absorber_c_Ns_per_m; }, "rubber absorbers, total c_x c_y c_z",
                 true)
        .number("absorbers.ring_radius_mm", "mm", u::mm, 10, 10000, [](P& p) -> double& { return p.absorber_ring_radius_m; },
                "ring of the absorbers (tilt and twist stiffness)", true)
        .vector3("test_point_mm", "mm", u::mm, -10000, 10000, [](P& p) -> Eigen::Vector3d& { return p.test_point_m; },
                 "test point on the fixed cone (world, at rest)", true)
        .plausible(kPointLo_mm, kPointHi_mm, kMetresForMm, "")
        // Table 1 is in the kg-s-mm-N system: F[N] = k d[mm]^h1 + c |v[mm/s]|^h2 d[mm]^h3.
        .number_scaled("contact.stiffness_N_per_mm", "N/mm^h1",
                       [](const P& p) { return u::power_law_stiffness_to_si(1.0, p.contact.h1); }, 1.0, 1e9,
                       [](P& p) -> double& { return p.contact.k; }, "Eq. 11 stiffness k (SI: k 1000^h1)", true)
        .number("contact.stiffness_exponent", "", 1, 1.0, 3.0, [](P& p) -> double& { return p.contact.h1; },
                "Eq. 11 h1", true)
        .number_scaled("contact.damping_Ns_per_mm", "N s/mm (kg-s-mm units)",
                       [](const P& p) { return std::pow(1e3, p.contact.h2 + p.contact.h3); }, 0.0, 1e7,
                       [](P& p) -> double& { return p.contact.c; }, "Eq. 11 damping c (SI: c 1000^(h2+h3))", true)
        .number("contact.damping_exponent", "", 1, 0.5, 3.0, [](P& p) -> double& { return p.contact.h2; },
                "Eq. 11 h2", true)
        .number("contact.indentation_exponent", "", 1, 0.0, 3.0, [](P& p) -> double& { return p.contact.h3; },
                "Eq. 11 h3", true)
        .number("contact.mu_static", "", 1, 0.0, 2.0, [](P& p) -> double& { return p.contact.mu_s; },
                "Eq. 14 static threshold coefficient", true)
        .number("contact.mu_dynamic", "", 1, 0.0, 2.0, [](P& p) -> double& { return p.contact.mu_d; },
                "Eq. 14 dynamic threshold coefficient (<= mu_static)", true)
        .number("contact.v_static_mm_s", "mm/s", u::mm_per_s, 1e-3, 1e4, [](P& p) -> double& { return p.contact.v_s; },
                "Eq. 14 static threshold velocity", true)
        .number("contact.v_dynamic_mm_s", "mm/s", u::mm_per_s, 1e-3, 1e5, [](P& p) -> double& { return p.contact.v_d; },
                "Eq. 14 dynamic threshold velocity (> v_static)", true)
        .include<core::ChamberGeometry>("chamber", core::chamber_geometry_schema(),
                                        [](P& p) -> core::ChamberGeometry& { return p.chamber; })
        .integer("chamber.azimuth_samples", 8, 720, [](P& p) -> int& { return p.sampling.azimuth; },
                 "samples around the circumference (contact and bed)", true)
        .integer("chamber.generator_samples", 2, 100, [](P& p) -> int& { return p.sampling.generator; },
                 "samples along the mantle generator", true)
        .choice("bed.law", {"viscous", "hysteretic"},
                [](const P& p) { return std::string(p.bed.law == BedLaw::Hysteretic ? "hysteretic" : "viscous"); },
                [](P& p, const std::string& v) { p.bed.law = v == "hysteretic" ? BedLaw::Hysteretic : BedLaw::Viscous; },
                "equivalent bed law")
        .number("bed.rebound", "", 1, 0.01, 1.0, [](P& p) -> double& { return p.bed.rebound; },
                "hysteretic: recovered fraction of each compression", true)
        .applies_if([](const P& p) { return p.bed.law == BedLaw::Hysteretic; },
                    "law: hysteretic only (this bed is viscous)", "law hysteretic")
        .number("bed.modulus_MPa", "MPa", u::MPa, 0.0, 1e4, [](P& p) -> double& { return p.bed.modulus_Pa; },
                "p = E e^n: E", true)
        .number("bed.exponent", "", 1, 1.0, 4.0, [](P& p) -> double& { return p.bed.exponent; }, "p = E e^n: n", true)
        .number("bed.engage_ratio", "", 1, 0.1, 1.5, [](P& p) -> double& { return p.bed.engage_ratio; },
                "the bed fills this fraction of the rest gap", true)
        .number("bed.viscosity_kPa_s", "kPa s", 1e3, 0.0, 1e6, [](P& p) -> double& { return p.bed.viscosity_Pa_s; },
                "viscous bed: loss per unit strain rate", true)
        .number("bed.friction", "", 1, 0.0, 2.0, [](P& p) -> double& { return p.bed.friction; },
                "bed-on-mantle friction coefficient", true)
        .number("bed.v_static_mm_s", "mm/s", u::mm_per_s, 1e-2, 1e4, [](P& p) -> double& { return p.bed.v_s; },
                "bed friction: stick below", true)
        .number("bed.v_dynamic_mm_s", "mm/s", u::mm_per_s, 1e-2, 1e5, [](P& p) -> double& { return p.bed.v_d; },
                "bed friction: slip above (> v_static)", true)
        .boolean("effects.joint_friction.enabled", [](P& p) -> bool& { return p.effects.joint_friction.enabled; },
                 "friction torque in O1 and O3")
        .number("effects.joint_friction.coulomb_Nm", "N m", 1, 0.0, 1e5,
                [](P& p) -> double& { return p.effects.joint_friction.coulomb_Nm; }, "Coulomb torque")
        .number("effects.joint_friction.viscous_Nms", "N m s", 1, 0.0, 1e5,
                [](P& p) -> double& { return p.effects.joint_friction.viscous_Nms; }, "viscous torque per rad/s")
        .boolean("effects.absorber_nonlinearity.enabled",
                 [](P& p) -> bool& { return p.effects.absorber_nonlinearity.enabled; }, "F = k1 d + k3 d^3 (+ hysteresis)")
        .number("effects.absorber_nonlinearity.cubic_N_per_m3", "N/m^3", 1, -1e14, 1e14,
                [](P& p) -> double& { return p.effects.absorber_nonlinearity.cubic_N_per_m3; }, "k3")
        .number("effects.absorber_nonlinearity.hysteresis", "", 1, 0.0, 2.0,
                [](P& p) -> double& { return p.effects.absorber_nonlinearity.hysteresis; }, "loss factor eta")
        .boolean("effects.motor_droop.enabled", [](P& p) -> bool& { return p.effects.motor_droop.enabled; },
                 "drive speed = w0 - droop x torque")
        .number("effects.motor_droop.droop_rad_s_per_kNm", "rad/s per kN m", 1e-3, 0.0, 100.0,
                [](P& p) -> double& { return p.effects.motor_droop.droop_rad_s_per_Nm; }, "droop")
        .boolean("effects.cardan_misalignment.enabled",
                 [](P& p) -> bool& { return p.effects.cardan_misalignment.enabled; }, "drive shaft tilted about O6")
        .number("effects.cardan_misalignment.angle_deg", "deg", u::deg, 0.0, 40.0,
                [](P& p) -> double& { return p.effects.cardan_misalignment.angle_rad; }, "tilt angle")
        .boolean("effects.bearing_friction.enabled", [](P& p) -> bool& { return p.effects.bearing_friction.enabled; },
                 "Coulomb friction mu r |reaction| in the bushing O3 and the spherical support O1")
        .number("effects.bearing_friction.mu", "", 1, 0.0, 0.3,
                [](P& p) -> double& { return p.effects.bearing_friction.mu; },
                "friction coefficient (main parameter; oiled bronze on steel: hydrodynamic 0.001-0.005, mixed "
                "0.01-0.05, boundary 0.05-0.15)")
        .number("effects.bearing_friction.bushing_radius_mm", "mm", u::mm, 10.0, 500.0,
                [](P& p) -> double& { return p.effects.bearing_friction.bushing_radius_m; },
                "O3 bushing (pin) radius; estimated 100 mm: a 200 mm shaft in a ~300 mm half-disc vibrator")
        .number("effects.bearing_friction.sphere_radius_mm", "mm", u::mm, 0.0, 2000.0,
                [](P& p) -> double& { return p.effects.bearing_friction.sphere_radius_m; },
                "O1 spherical support radius (0: no friction in O1); estimated 400 mm")
        .number("effects.bearing_friction.regularisation_rad_s", "rad/s", 1, 1e-4, 10.0,
                [](P& p) -> double& { return p.effects.bearing_friction.regularisation_rad_s; },
                "Coulomb law smoothed as tanh(w_rel / w_eps)")
        .boolean("effects.drive_efficiency.enabled", [](P& p) -> bool& { return p.effects.drive_efficiency.enabled; },
                 "reported power = motor input: shaft power / efficiency + no-load loss")
        .number("effects.drive_efficiency.efficiency", "", 1, 0.3, 1.0,
                [](P& p) -> double& { return p.effects.drive_efficiency.efficiency; },
                "motor terminals to drive shaft (main parameter; motor 0.93-0.96 x belts 0.95-0.98)")
        .number("effects.drive_efficiency.no_load_kW", "kW", 1e3, 0.0, 1e3,
                [](P& p) -> double& { return p.effects.drive_efficiency.no_load_W; },
                "no-load loss (motor iron, windage, bearings) at reference_rpm")
        .number("effects.drive_efficiency.reference_rpm", "rpm", u::rpm, 1.0, 5000.0,
                [](P& p) -> double& { return p.effects.drive_efficiency.reference_speed_rad_s; },
                "drive speed at which no_load_kW holds")
        .number("effects.drive_efficiency.speed_exponent", "", 1, 0.0, 4.0,
                [](P& p) -> double& { return p.effects.drive_efficiency.speed_exponent; },
                "no-load loss ~ (speed / reference)^exponent");
    for (const char* e : {"joint_friction", "absorber_nonlinearity", "motor_droop", "cardan_misalignment",
                          "bearing_friction", "drive_efficiency"})
      k.flow_style(std::string("effects.") + e);
    return k;
  }();
  return s;
}

MechanismParams load_mechanism_params(const core::ConfigNode& m) {
  MechanismParams p;
  mechanism_schema().read(m, p);
  // Heights the joints fix (not keys of their own).
  p.vibrator.com_z_m = p.vibrator_axis_z_m;
  p.globe_bearing.com_z_m = p.globe_bearing_z_m;
  p.connecting_shaft.com_z_m = 0.5 * (p.ball_pin_z_m + p.universal_z_m);
  p.drive_shaft.com_z_m = p.universal_z_m - 0.5 * p.drive_shaft_length_m;
  validate(p, false);  // the bed's step bound is checked where the load is known (Mechanism, mbd_node)
  return p;
}

namespace {

[[noreturn]] void bad(const std::string& key, double value, const std::string& accepted) {
  std::ostringstream s;
  s << "mbd." << key << ": value " << value << " is not accepted; accepted " << accepted;
  throw std::invalid_argument(s.str());
}
void range(const std::string& key, double v, double lo, double hi, const std::string& unit = "") {
  if (!std::isfinite(v) || v < lo || v > hi) {
    std::ostringstream s;
    s << "[" << lo << ", " << hi << "]" << (unit.empty() ? "" : " " + unit);
    bad(key, v, s.str());
  }
}
void body_ok(const std::string& key, const BodyParams& b) {
  range(key + ".mass_kg", b.mass_kg, 1e-3, 1e7, "kg");
  for (int i = 0; i < 3; ++i) range(key + ".inertia_kg_m2", b.inertia_kg_m2[i], 1e-9, 1e8, "kg m^2");
  const auto& I = b.inertia_kg_m2;
  if (I[0] + I[1] < I[2] * (1 - 1e-9) || I[1] + I[2] < I[0] * (1 - 1e-9) || I[0] + I[2] < I[1] * (1 - 1e-9))
    bad(key + ".inertia_kg_m2", I.maxCoeff(), "principal inertias satisfying the triangle inequality");
}

}  // namespace

double stable_step_bound(const MechanismParams& p, std::string* element, bool with_bed) {
  double best = std::numeric_limits<double>::infinity();
  auto consider = [&](double m, double k, const std::string& name) {
    if (k <= 0) return;
    const double t = std::sqrt(m / k);
    if (t < best) {
      best = t;
      if (element) *element = name;
    }
  };
  const double mtot = p.fixed_cone.mass_kg + p.floating_cone.mass_kg + p.vibrator.mass_kg;
  consider(mtot, p.absorber_k_N_per_m.maxCoeff(), "absorbers (mbd.absorbers.stiffness_N_per_mm)");
  // Cone contact (Eq. 11) linearised where its force equals the vibrator's centrifugal force
  // m e w^2 (the largest steady force that presses the cones together):
  // F = k d^h1 -> dF/dd = h1 k^(1/h1) F^(1-1/h1).
  const double w = p.drive_speed_rad_s;
  const double F = std::max(1.0, p.vibrator_static_moment_kg_m * w * w +
                                     p.floating_cone.mass_kg * p.gravity_m_s2);
  const double h = p.contact.h1;
  const double kc = h * std::pow(p.contact.k, 1.0 / h) * std::pow(F, 1.0 - 1.0 / h);
  consider(p.floating_cone.mass_kg, kc, "cone contact Eq. 11 (mbd.contact.stiffness_N_per_mm)");
  if (!with_bed) return best;
  // Bed: all sample patches together at strain 0.5 (stiffness of the whole loaded bed).
  const auto& g = p.chamber;
  const double L = g.mantle.length();
  double kb = 0, cb = 0;
  const int ns = p.sampling.generator;
  for (int j = 0; j < ns; ++j) {
    const double s = (j + 0.5) * L / ns;
    Eigen::Vector2d t;
    const Eigen::Vector2d q = g.mantle.point_at(s, &t);
    Eigen::Vector2d n;
    const double grest = core::signed_distance_inside(g.concave, q, &n);
    if (grest <= 0) continue;
    const double area = 2.0 * 3.14159265358979 * q.y() * L / ns;
    const double gref = p.bed.engage_ratio * grest;
    // Hysteretic unloading is 1/rebound times stiffer than loading (chamber_forces.cpp).
    const double unload = p.bed.law == BedLaw::Hysteretic ? 1.0 / p.bed.rebound : 1.0;
    kb += unload * area * p.bed.modulus_Pa * p.bed.exponent * std::pow(0.5, p.bed.exponent - 1.0) / gref;
    cb += area * p.bed.viscosity_Pa_s / gref;
  }
  consider(p.floating_cone.mass_kg, 0.5 * kb, "material bed (mbd.bed.modulus_MPa)");
  // Explicit damping is stable for dt < 2 m / c; bound m / c (half of it), loaded half of the bed.
  if (cb > 0) {
    const double t = p.floating_cone.mass_kg / (0.5 * cb);
    if (t < best) {
      best = t;
      if (element) *element = "material bed damping m/c (mbd.bed.viscosity_kPa_s)";
    }
  }
  return best;
}

void validate(const MechanismParams& p, bool with_bed) {
  range("time_step_s", p.dt_s, 1e-6, 5e-3, "s");
  range("drive.speed_rpm", p.drive_speed_rad_s / u::rpm, 1.0, 2000.0, "rpm");
  range("drive.ramp_s", p.drive_ramp_s, 0.0, 60.0, "s");
  body_ok("fixed_cone", p.fixed_cone);
  body_ok("floating_cone", p.floating_cone);
  body_ok("vibrator", p.vibrator);
  body_ok("globe_bearing", p.globe_bearing);
  body_ok("connecting_shaft", p.connecting_shaft);
  body_ok("drive", p.drive_shaft);
  range("vibrator.static_moment_kg_m", p.vibrator_static_moment_kg_m, 0.0, 0.5 * p.vibrator.mass_kg,
        "kg m (eccentricity at most 0.5 m)");
  // Axial order along the shaft: O1 (0) > O2 > O3 > O5 > O6, and the chamber above O2.
  if (!(p.globe_bearing_z_m < 0)) bad("globe_bearing.joint_z_mm", p.globe_bearing_z_m * 1e3, "< 0 (below O1)");
  if (!(p.vibrator_axis_z_m < p.globe_bearing_z_m))
    bad("vibrator.axis_z_mm", p.vibrator_axis_z_m * 1e3, "< globe_bearing.joint_z_mm");
  if (!(p.ball_pin_z_m < p.vibrator_axis_z_m + 0.5))
    bad("connecting_shaft.ball_pin_z_mm", p.ball_pin_z_m * 1e3, "< vibrator.axis_z_mm + 500");
  if (!(p.universal_z_m < p.ball_pin_z_m - 0.05))
    bad("connecting_shaft.universal_z_mm", p.universal_z_m * 1e3, "< connecting_shaft.ball_pin_z_mm - 50");
  for (int i = 0; i < 3; ++i) {
    range("absorbers.stiffness_N_per_mm", p.absorber_k_N_per_m[i] / 1e3, 1e-3, 1e7, "N/mm");
    range("absorbers.damping_Ns_per_mm", p.absorber_c_Ns_per_m[i] / 1e3, 0.0, 1e6, "N s/mm");
  }
  range("contact.stiffness_exponent", p.contact.h1, 1.0, 3.0);
  range("contact.mu_static", p.contact.mu_s, 0.0, 2.0);
  range("contact.mu_dynamic", p.contact.mu_d, 0.0, p.contact.mu_s, "(<= mu_static)");
  range("contact.v_dynamic_mm_s", p.contact.v_d * 1e3, p.contact.v_s * 1e3 * (1 + 1e-9), 1e5,
        "mm/s (> v_static_mm_s)");
  range("bed.v_dynamic_mm_s", p.bed.v_d * 1e3, p.bed.v_s * 1e3 * (1 + 1e-9), 1e5, "mm/s (> v_static_mm_s)");
  range("bed.engage_ratio", p.bed.engage_ratio, 0.1, 1.5);
  if (p.bed.law == BedLaw::Hysteretic) range("bed.rebound", p.bed.rebound, 0.01, 1.0);
  if (p.sampling.azimuth < 8) bad("chamber.azimuth_samples", p.sampling.azimuth, "[8, 720]");
  if (p.sampling.generator < 2) bad("chamber.generator_samples", p.sampling.generator, "[2, 100]");
  try {
    core::validate_chamber_geometry(p.chamber);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("mbd.") + e.what());
  }
  // Accuracy: the vibrator turns by w dt per step; its off-axis COM makes the joints drift by
  // e (w dt)^2 / 2 per step, so keep w dt <= 0.05 rad (0.3 mm joint error at e = 0.16 m).
  if (p.drive_speed_rad_s * p.dt_s > 0.05 + 1e-12) {
    std::ostringstream s;
    s << "<= " << 0.05 / p.drive_speed_rad_s << " s at this drive speed (drive rotation per step <= 0.05 rad)";
    bad("time_step_s", p.dt_s, s.str());
  }
  if (p.effects.motor_droop.enabled && p.effects.motor_droop.droop_rad_s_per_Nm > 0) {
    // The droop line acts as an explicit damper 1/droop on the drive-line inertia I (vibrator spin
    // inertia + m e^2 + shafts): stable for dt < 2 droop I; accept dt <= droop I.
    const double I = p.vibrator.inertia_kg_m2.z() + p.vibrator.mass_kg * std::pow(p.vibrator_eccentricity_m(), 2) +
                     p.drive_shaft.inertia_kg_m2.z() + p.connecting_shaft.inertia_kg_m2.z();
    const double min_droop = p.dt_s / I;
    if (p.effects.motor_droop.droop_rad_s_per_Nm < min_droop) {
      std::ostringstream s;
      s << ">= " << min_droop * 1e3 << " rad/s per kN m at time_step_s " << p.dt_s
        << " (drive-line inertia " << I << " kg m^2), or 0 / enabled: false for a constant speed";
      bad("effects.motor_droop.droop_rad_s_per_kNm", p.effects.motor_droop.droop_rad_s_per_Nm * 1e3, s.str());
    }
  }
  if (p.effects.bearing_friction.enabled) {
    const auto& bf = p.effects.bearing_friction;
    range("effects.bearing_friction.mu", bf.mu, 0.0, 0.3);
    range("effects.bearing_friction.bushing_radius_mm", bf.bushing_radius_m * 1e3, 10.0, 500.0, "mm");
    range("effects.bearing_friction.sphere_radius_mm", bf.sphere_radius_m * 1e3, 0.0, 2000.0, "mm");
    range("effects.bearing_friction.regularisation_rad_s", bf.regularisation_rad_s, 1e-4, 10.0, "rad/s");
    // No step bound for the smoothing: the bushing slips at about the drive speed and O1 at the nutation rate, never
    // near zero for long; mu 0.3 with w_eps 0.005 rad/s runs stably at 400 and 600 rpm (bed, idle and flow).
  }
  if (p.effects.drive_efficiency.enabled) {
    const auto& de = p.effects.drive_efficiency;
    range("effects.drive_efficiency.efficiency", de.efficiency, 0.3, 1.0);
    range("effects.drive_efficiency.no_load_kW", de.no_load_W / 1e3, 0.0, 1e3, "kW");
    range("effects.drive_efficiency.reference_rpm", de.reference_speed_rad_s / u::rpm, 1.0, 5000.0, "rpm");
    range("effects.drive_efficiency.speed_exponent", de.speed_exponent, 0.0, 4.0);
  }
  std::string element;
  const double bound = stable_step_bound(p, &element, with_bed);
  if (p.dt_s > bound) {
    std::ostringstream s;
    s << "<= " << bound << " s = sqrt(m/k) of the stiffest element, " << element;
    bad("time_step_s", p.dt_s, s.str());
  }
}

std::string to_yaml(const MechanismParams& p) {
  YAML::Node root;
  root["mbd"] = mechanism_schema().write(p);
  // Effects added after the checkpoint format was fixed are written only when on, so that the fingerprint of a
  // config without them stays what older checkpoints hold (test ConfigSchema.MechanismFingerprintIsUnchanged).
  YAML::Node effects = root["mbd"]["effects"];
  if (!p.effects.bearing_friction.enabled) effects.remove("bearing_friction");
  if (!p.effects.drive_efficiency.enabled) effects.remove("drive_efficiency");
  YAML::Emitter e;
  e << root;
  return std::string(e.c_str()) + "\n";
}

MechanismParams load_mechanism_params_file(const std::string& path) {
  auto root = core::ConfigNode::load_file(path);
  auto p = load_mechanism_params(root.child("mbd"));
  if (root.has("run")) core::load_run_options(root.child("run"));
  core::load_coupling_options(root.child_or_empty("coupling"));
  root.ignore("dem");
  root.ignore("flow");  // the chamber flow model's section (chamber/flow_config.hpp)
  root.ignore("diagnosis");  // crusher diagnose's uncertain values (analysis/param_set.hpp)
  root.finish();
  return p;
}

}  // namespace mbd
