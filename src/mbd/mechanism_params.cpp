#include "mbd/mechanism_params.hpp"

#include "core/run_config.hpp"

#include <cmath>
#include <iomanip>
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

BodyParams load_body(const core::ConfigNode& n, double mass_lo, double mass_hi, bool with_com) {
  BodyParams b;
  b.mass_kg = n.number("mass_kg", mass_lo, mass_hi, "kg");
  if (with_com) b.com_z_m = n.number("com_z_mm", -10000, 10000, "mm", u::mm);
  b.inertia_kg_m2 = n.vector3("inertia_kg_m2", 1e-6, 1e7, "kg m^2");
  return b;
}

}  // namespace

MechanismParams load_mechanism_params(const core::ConfigNode& m) {
  MechanismParams p;
  p.dt_s = m.number("time_step_s", 1e-6, 5e-3, "s");
  p.gravity_m_s2 = m.number("gravity_m_s2", 0.0, 20.0, "m/s^2");

  const auto drive = m.child("drive");
  p.drive_speed_rad_s = drive.number("speed_rpm", 1.0, 2000.0, "rpm", u::rpm);
  p.drive_ramp_s = drive.number("ramp_s", 0.0, 60.0, "s");
  p.drive_max_torque_Nm = drive.number("max_torque_kNm", 0.1, 1e4, "kN m", 1e3);
  p.drive_shaft = load_body(drive, 0.1, 1e4, false);
  p.drive_shaft_length_m = drive.number("length_mm", 10, 5000, "mm", u::mm);

  p.fixed_cone = load_body(m.child("fixed_cone"), 1.0, 1e6, true);
  p.floating_cone = load_body(m.child("floating_cone"), 1.0, 1e6, true);

  const auto vib = m.child("vibrator");
  p.vibrator.mass_kg = vib.number("mass_kg", 1.0, 1e5, "kg");
  p.vibrator.inertia_kg_m2 = vib.vector3("inertia_kg_m2", 1e-6, 1e7, "kg m^2");
  p.vibrator_axis_z_m = vib.number("axis_z_mm", -10000, 0, "mm", u::mm);
  p.vibrator_static_moment_kg_m = vib.number("static_moment_kg_m", 0.0, 1e4, "kg m");
  p.vibrator.com_z_m = p.vibrator_axis_z_m;

  const auto gb = m.child("globe_bearing");
  p.globe_bearing.mass_kg = gb.number("mass_kg", 0.1, 1e5, "kg");
  p.globe_bearing.inertia_kg_m2 = gb.vector3("inertia_kg_m2", 1e-6, 1e7, "kg m^2");
  p.globe_bearing_z_m = gb.number("joint_z_mm", -10000, 0, "mm", u::mm);
  p.globe_bearing.com_z_m = p.globe_bearing_z_m;

  const auto cs = m.child("connecting_shaft");
  p.connecting_shaft.mass_kg = cs.number("mass_kg", 0.1, 1e5, "kg");
  p.connecting_shaft.inertia_kg_m2 = cs.vector3("inertia_kg_m2", 1e-6, 1e7, "kg m^2");
  p.ball_pin_z_m = cs.number("ball_pin_z_mm", -10000, 0, "mm", u::mm);
  p.universal_z_m = cs.number("universal_z_mm", -10000, 0, "mm", u::mm);
  p.connecting_shaft.com_z_m = 0.5 * (p.ball_pin_z_m + p.universal_z_m);
  p.drive_shaft.com_z_m = p.universal_z_m - 0.5 * p.drive_shaft_length_m;

  const auto ab = m.child("absorbers");
  p.absorber_k_N_per_m = ab.vector3("stiffness_N_per_mm", 1e-3, 1e7, "N/mm", u::N_per_mm);
  p.absorber_c_Ns_per_m = ab.vector3("damping_Ns_per_mm", 0.0, 1e6, "N s/mm", u::Ns_per_mm);
  p.absorber_ring_radius_m = ab.number("ring_radius_mm", 10, 10000, "mm", u::mm);

  p.test_point_m = m.vector3("test_point_mm", -10000, 10000, "mm", u::mm);

  const auto c = m.child("contact");
  p.contact.h1 = c.number("stiffness_exponent", 1.0, 3.0);
  p.contact.h2 = c.number("damping_exponent", 0.5, 3.0);
  p.contact.h3 = c.number("indentation_exponent", 0.0, 3.0);
  // Table 1 is in the kg-s-mm-N system: F[N] = k d[mm]^h1 + c |v[mm/s]|^h2 d[mm]^h3.
  p.contact.k = u::power_law_stiffness_to_si(c.number("stiffness_N_per_mm", 1.0, 1e9, "N/mm^h1"), p.contact.h1);
  p.contact.c = c.number("damping_Ns_per_mm", 0.0, 1e7, "N s/mm (kg-s-mm units)") *
                std::pow(1e3, p.contact.h2 + p.contact.h3);
  p.contact.mu_s = c.number("mu_static", 0.0, 2.0);
  p.contact.mu_d = c.number("mu_dynamic", 0.0, 2.0);
  p.contact.v_s = c.number("v_static_mm_s", 1e-3, 1e4, "mm/s", u::mm_per_s);
  p.contact.v_d = c.number("v_dynamic_mm_s", 1e-3, 1e5, "mm/s", u::mm_per_s);

  const auto ch = m.child("chamber");
  p.chamber = core::load_chamber_geometry(ch);
  p.sampling.azimuth = ch.integer("azimuth_samples", 8, 720);
  p.sampling.generator = ch.integer("generator_samples", 2, 100);

  const auto b = m.child("bed");
  p.bed.law = b.choice_or("law", "viscous", {"viscous", "hysteretic"}) == "hysteretic" ? BedLaw::Hysteretic
                                                                                     : BedLaw::Viscous;
  if (p.bed.law == BedLaw::Hysteretic)
    p.bed.rebound = b.number("rebound", 0.01, 1.0);
  else if (b.has("rebound"))
    b.fail("rebound", "applies to law: hysteretic only (this bed is viscous)");
  p.bed.modulus_Pa = b.number("modulus_MPa", 0.0, 1e4, "MPa", u::MPa);
  p.bed.exponent = b.number("exponent", 1.0, 4.0);
  p.bed.engage_ratio = b.number("engage_ratio", 0.1, 1.5);
  p.bed.viscosity_Pa_s = b.number("viscosity_kPa_s", 0.0, 1e6, "kPa s", 1e3);
  p.bed.friction = b.number("friction", 0.0, 2.0);
  p.bed.v_s = b.number("v_static_mm_s", 1e-2, 1e4, "mm/s", u::mm_per_s);
  p.bed.v_d = b.number("v_dynamic_mm_s", 1e-2, 1e5, "mm/s", u::mm_per_s);

  const auto fx = m.child_or_empty("effects");
  {
    const auto e = fx.child_or_empty("joint_friction");
    p.effects.joint_friction.enabled = e.boolean_or("enabled", false);
    p.effects.joint_friction.coulomb_Nm = e.number_or("coulomb_Nm", 0.0, 0.0, 1e5, "N m");
    p.effects.joint_friction.viscous_Nms = e.number_or("viscous_Nms", 0.0, 0.0, 1e5, "N m s");
  }
  {
    const auto e = fx.child_or_empty("absorber_nonlinearity");
    p.effects.absorber_nonlinearity.enabled = e.boolean_or("enabled", false);
    p.effects.absorber_nonlinearity.cubic_N_per_m3 = e.number_or("cubic_N_per_m3", 0.0, -1e14, 1e14, "N/m^3");
    p.effects.absorber_nonlinearity.hysteresis = e.number_or("hysteresis", 0.0, 0.0, 2.0);
  }
  {
    const auto e = fx.child_or_empty("motor_droop");
    p.effects.motor_droop.enabled = e.boolean_or("enabled", false);
    p.effects.motor_droop.droop_rad_s_per_Nm = e.number_or("droop_rad_s_per_kNm", 0.0, 0.0, 100.0, "rad/s per kN m", 1e-3);
  }
  {
    const auto e = fx.child_or_empty("cardan_misalignment");
    p.effects.cardan_misalignment.enabled = e.boolean_or("enabled", false);
    p.effects.cardan_misalignment.angle_rad = e.number_or("angle_deg", 0.0, 0.0, 40.0, "deg", u::deg);
  }
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
  std::string element;
  const double bound = stable_step_bound(p, &element, with_bed);
  if (p.dt_s > bound) {
    std::ostringstream s;
    s << "<= " << bound << " s = sqrt(m/k) of the stiffest element, " << element;
    bad("time_step_s", p.dt_s, s.str());
  }
}

namespace {
std::string v3(const Eigen::Vector3d& v, double scale = 1.0) {
  std::ostringstream s;
  s << std::setprecision(12) << "[" << v[0] * scale << ", " << v[1] * scale << ", " << v[2] * scale << "]";
  return s.str();
}
std::string list(const std::vector<double>& v, double scale) {
  std::ostringstream s;
  s << std::setprecision(12) << "[";
  for (std::size_t i = 0; i < v.size(); ++i) s << (i ? ", " : "") << v[i] * scale;
  s << "]";
  return s.str();
}
}  // namespace

std::string to_yaml(const MechanismParams& p) {
  std::ostringstream y;
  y << std::setprecision(12);
  const auto& e = p.effects;
  y << "mbd:\n"
    << "  time_step_s: " << p.dt_s << "\n"
    << "  gravity_m_s2: " << p.gravity_m_s2 << "\n"
    << "  drive:\n"
    << "    speed_rpm: " << p.drive_speed_rad_s / u::rpm << "\n"
    << "    ramp_s: " << p.drive_ramp_s << "\n"
    << "    max_torque_kNm: " << p.drive_max_torque_Nm / 1e3 << "\n"
    << "    mass_kg: " << p.drive_shaft.mass_kg << "\n"
    << "    inertia_kg_m2: " << v3(p.drive_shaft.inertia_kg_m2) << "\n"
    << "    length_mm: " << p.drive_shaft_length_m * 1e3 << "\n";
  auto body = [&](const char* name, const BodyParams& b) {
    y << "  " << name << ":\n"
      << "    mass_kg: " << b.mass_kg << "\n"
      << "    com_z_mm: " << b.com_z_m * 1e3 << "\n"
      << "    inertia_kg_m2: " << v3(b.inertia_kg_m2) << "\n";
  };
  body("fixed_cone", p.fixed_cone);
  body("floating_cone", p.floating_cone);
  y << "  vibrator:\n"
    << "    mass_kg: " << p.vibrator.mass_kg << "\n"
    << "    inertia_kg_m2: " << v3(p.vibrator.inertia_kg_m2) << "\n"
    << "    axis_z_mm: " << p.vibrator_axis_z_m * 1e3 << "\n"
    << "    static_moment_kg_m: " << p.vibrator_static_moment_kg_m << "\n"
    << "  globe_bearing:\n"
    << "    mass_kg: " << p.globe_bearing.mass_kg << "\n"
    << "    inertia_kg_m2: " << v3(p.globe_bearing.inertia_kg_m2) << "\n"
    << "    joint_z_mm: " << p.globe_bearing_z_m * 1e3 << "\n"
    << "  connecting_shaft:\n"
    << "    mass_kg: " << p.connecting_shaft.mass_kg << "\n"
    << "    inertia_kg_m2: " << v3(p.connecting_shaft.inertia_kg_m2) << "\n"
    << "    ball_pin_z_mm: " << p.ball_pin_z_m * 1e3 << "\n"
    << "    universal_z_mm: " << p.universal_z_m * 1e3 << "\n"
    << "  absorbers:\n"
    << "    stiffness_N_per_mm: " << v3(p.absorber_k_N_per_m, 1e-3) << "\n"
    << "    damping_Ns_per_mm: " << v3(p.absorber_c_Ns_per_m, 1e-3) << "\n"
    << "    ring_radius_mm: " << p.absorber_ring_radius_m * 1e3 << "\n"
    << "  test_point_mm: " << v3(p.test_point_m, 1e3) << "\n"
    << "  contact:\n"
    << "    stiffness_N_per_mm: " << p.contact.k / std::pow(1e3, p.contact.h1) << "\n"
    << "    stiffness_exponent: " << p.contact.h1 << "\n"
    << "    damping_Ns_per_mm: " << p.contact.c / std::pow(1e3, p.contact.h2 + p.contact.h3) << "\n"
    << "    damping_exponent: " << p.contact.h2 << "\n"
    << "    indentation_exponent: " << p.contact.h3 << "\n"
    << "    mu_static: " << p.contact.mu_s << "\n"
    << "    mu_dynamic: " << p.contact.mu_d << "\n"
    << "    v_static_mm_s: " << p.contact.v_s * 1e3 << "\n"
    << "    v_dynamic_mm_s: " << p.contact.v_d * 1e3 << "\n"
    << "  chamber:\n"
    << "    mantle_z_mm: " << list(p.chamber.mantle.z, 1e3) << "\n"
    << "    mantle_r_mm: " << list(p.chamber.mantle.r, 1e3) << "\n"
    << "    concave_z_mm: " << list(p.chamber.concave.z, 1e3) << "\n"
    << "    concave_r_mm: " << list(p.chamber.concave.r, 1e3) << "\n"
    << "    azimuth_samples: " << p.sampling.azimuth << "\n"
    << "    generator_samples: " << p.sampling.generator << "\n"
    << "  bed:\n"
    << "    law: " << (p.bed.law == BedLaw::Hysteretic ? "hysteretic" : "viscous") << "\n"
    << (p.bed.law == BedLaw::Hysteretic ? "    rebound: " + std::to_string(p.bed.rebound) + "\n" : std::string())
    << "    modulus_MPa: " << p.bed.modulus_Pa / 1e6 << "\n"
    << "    exponent: " << p.bed.exponent << "\n"
    << "    engage_ratio: " << p.bed.engage_ratio << "\n"
    << "    viscosity_kPa_s: " << p.bed.viscosity_Pa_s / 1e3 << "\n"
    << "    friction: " << p.bed.friction << "\n"
    << "    v_static_mm_s: " << p.bed.v_s * 1e3 << "\n"
    << "    v_dynamic_mm_s: " << p.bed.v_d * 1e3 << "\n"
    << "  effects:\n"
    << "    joint_friction: {enabled: " << (e.joint_friction.enabled ? "true" : "false")
    << ", coulomb_Nm: " << e.joint_friction.coulomb_Nm << ", viscous_Nms: " << e.joint_friction.viscous_Nms << "}\n"
    << "    absorber_nonlinearity: {enabled: " << (e.absorber_nonlinearity.enabled ? "true" : "false")
    << ", cubic_N_per_m3: " << e.absorber_nonlinearity.cubic_N_per_m3
    << ", hysteresis: " << e.absorber_nonlinearity.hysteresis << "}\n"
    << "    motor_droop: {enabled: " << (e.motor_droop.enabled ? "true" : "false")
    << ", droop_rad_s_per_kNm: " << e.motor_droop.droop_rad_s_per_Nm * 1e3 << "}\n"
    << "    cardan_misalignment: {enabled: " << (e.cardan_misalignment.enabled ? "true" : "false")
    << ", angle_deg: " << e.cardan_misalignment.angle_rad / u::deg << "}\n";
  return y.str();
}

MechanismParams load_mechanism_params_file(const std::string& path) {
  auto root = core::ConfigNode::load_file(path);
  auto p = load_mechanism_params(root.child("mbd"));
  if (root.has("run")) core::load_run_options(root.child("run"));
  core::load_coupling_options(root.child_or_empty("coupling"));
  root.ignore("dem");
  root.ignore("flow");  // the chamber flow model's section (chamber/flow_config.hpp)
  root.finish();
  return p;
}

}  // namespace mbd
