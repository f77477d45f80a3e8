#include "analysis/mbd_model.hpp"

#include <cmath>
#include <stdexcept>

#include "analysis/metrics.hpp"
#include "core/config_schema.hpp"
#include "mbd/simulate.hpp"

namespace analysis {

std::vector<Term> mbd_candidates() {
  // Upper ends: well beyond what the mechanism plausibly shows (running torque ~2 kN m; absorber
  // k1 = 320 kN/m at ~3 mm amplitude: k3 = 5e11 N/m^3 adds 15 times k1 there; the frame runs far above
  // its absorber mode, so only a strong cubic term shows in the motion). Droop: mbd accepts only
  // droop >= dt / (drive-line inertia), 0.0205 rad/s per kN m at 400 rpm (1 ms step); 3 drops the
  // speed by ~5 rad/s at the running torque.
  std::vector<Term> c = default_candidates();
  for (auto& e : c)
    if (e.name == "motor_droop") e.lo = 0.021, e.hi = 3.0;
  return c;
}

std::vector<Term> module_candidates() {
  auto term = [](const char* section, const char* name, const char* parameter, const char* unit, double lo, double hi,
                 double nominal) {
    Term t;
    t.kind = Term::Effect;
    t.section = section;
    t.name = name;
    t.parameter = parameter;
    t.unit = unit;
    t.lo = lo;
    t.hi = hi;
    t.nominal = nominal;
    return t;
  };
  return {
      // Oiled bronze on steel: hydrodynamic 0.001-0.005, mixed 0.01-0.05, boundary 0.05-0.15 (src/mbd/README.md);
      // 0.1 adds 90 kW at 400 rpm on the shipped model.
      term("mbd", "bearing_friction", "mu", "", 0.0, 0.1, 0.0),
      // Motor 0.93-0.96 x belts 0.95-0.98 near full load, less at part load; 1: the recorded power is the shaft's.
      term("mbd", "drive_efficiency", "efficiency", "", 0.5, 1.0, 1.0),
      // The shipped chamber passes 81 t/h at 400 rpm and 57 at 600 choke fed: 200 leaves it choke fed.
      term("flow", "feed_limited", "max_feed_tph", "t/h", 20.0, 200.0, 200.0),
      // A liner is changed after a few tens of mm of wear.
      term("flow", "worn_liners", "setting_increase_mm", "mm", 0.0, 30.0, 0.0),
      // The nip's escape path is at most a few cells long; from ~20 mm on the friction hill is too stiff for the
      // mechanism's explicit coupling (30 mm blows up at 400 and 600 rpm; src/chamber/README.md).
      term("flow", "squeeze_flow", "escape_length_mm", "mm", 0.0, 15.0, 0.0),
      // Up to rock on steel (Table 4); the bed may shear within itself at less.
      term("flow", "liner_friction", "wall_friction", "", 0.0, 0.7, 0.0),
  };
}

std::vector<Term> series_candidates() {
  auto c = mbd_candidates();
  for (const auto& t : module_candidates())
    if (t.section == "mbd") c.push_back(t);
  return c;
}

std::vector<Term> summary_candidates() {
  auto c = mbd_candidates();
  for (const auto& t : module_candidates()) c.push_back(t);
  return c;
}

const std::vector<EffectModule>& effect_modules() {
  using M = mbd::MechanismParams;
  using F = chamber::FlowParams;
  static const std::vector<EffectModule> modules = {
      {"mbd", "joint_friction", "test/mbd/test_effects.cpp",
       [](const M& m, const F&) { return m.effects.joint_friction.enabled; }},
      {"mbd", "absorber_nonlinearity", "test/mbd/test_effects.cpp",
       [](const M& m, const F&) { return m.effects.absorber_nonlinearity.enabled; }},
      {"mbd", "motor_droop", "test/mbd/test_effects.cpp",
       [](const M& m, const F&) { return m.effects.motor_droop.enabled; }},
      {"mbd", "cardan_misalignment", "test/mbd/test_effects.cpp",
       [](const M& m, const F&) { return m.effects.cardan_misalignment.enabled; }},
      {"mbd", "bearing_friction", "test/mbd/test_bearing_friction.cpp",
       [](const M& m, const F&) { return m.effects.bearing_friction.enabled; }},
      {"mbd", "drive_efficiency", "test/mbd/test_drive_efficiency.cpp",
       [](const M& m, const F&) { return m.effects.drive_efficiency.enabled; }},
      {"flow", "feed_limited", "test/chamber/test_chamber_effects.cpp",
       [](const M&, const F& f) { return f.effects.feed_limited.enabled; }},
      {"flow", "worn_liners", "test/chamber/test_chamber_effects.cpp",
       [](const M&, const F& f) { return f.effects.worn_liners.enabled; }},
      {"flow", "squeeze_flow", "test/chamber/test_chamber_effects.cpp",
       [](const M&, const F& f) { return f.effects.squeeze_flow.enabled; }},
      {"flow", "liner_friction", "test/chamber/test_chamber_effects.cpp",
       [](const M&, const F& f) { return f.effects.liner_friction.enabled; }},
  };
  return modules;
}

static const EffectModule* effect_module(const std::string& name) {
  for (const auto& e : effect_modules())
    if (name == e.name) return &e;
  return nullptr;
}

static std::string effect_names(const std::string& section) {
  std::string out;
  for (const auto& e : effect_modules())
    if (section == e.section) out += (out.empty() ? "" : ", ") + std::string(e.name);
  return out;
}

std::string mbd_effect_names() { return effect_names("mbd"); }

mbd::MechanismParams with_effect(const mbd::MechanismParams& base, const std::string& effect, double value) {
  mbd::MechanismParams p = base;
  auto& e = p.effects;
  e.joint_friction.enabled = e.absorber_nonlinearity.enabled = e.motor_droop.enabled =
      e.cardan_misalignment.enabled = e.bearing_friction.enabled = e.drive_efficiency.enabled = false;
  if (effect == "none") return p;
  if (is_flow_effect(effect))
    throw std::invalid_argument("effect '" + effect + "' is a chamber flow-model effect (flow.effects." + effect +
                                "), not a mechanism one: it acts in flow runs only (make_recording --load flow)");
  if (effect == "joint_friction") {
    e.joint_friction.enabled = true;
    e.joint_friction.coulomb_Nm = value;
  } else if (effect == "absorber_nonlinearity") {
    e.absorber_nonlinearity.enabled = true;
    e.absorber_nonlinearity.cubic_N_per_m3 = value;
  } else if (effect == "motor_droop") {
    e.motor_droop.enabled = true;
    e.motor_droop.droop_rad_s_per_Nm = value * 1e-3;  // YAML: rad/s per kN m
  } else if (effect == "cardan_misalignment") {
    e.cardan_misalignment.enabled = true;
    e.cardan_misalignment.angle_rad = value * M_PI / 180.0;  // YAML: deg
  } else if (effect == "bearing_friction") {
    e.bearing_friction.enabled = true;
    e.bearing_friction.mu = value;  // YAML: mu (the radii keep base's values)
  } else if (effect == "drive_efficiency") {
    e.drive_efficiency.enabled = true;
    e.drive_efficiency.efficiency = value;  // YAML: efficiency (the no-load loss keeps base's value)
  } else {
    throw std::invalid_argument("unknown effect '" + effect + "'; accepted: none, " + mbd_effect_names() + " (" +
                                flow_effect_names() + ": flow runs only)");
  }
  return p;
}

std::string flow_effect_names() { return effect_names("flow"); }
bool is_flow_effect(const std::string& effect) {
  const EffectModule* e = effect_module(effect);
  return e && std::string(e->section) == "flow";
}

chamber::FlowParams with_flow_effect(const chamber::FlowParams& base, const std::string& effect, double value) {
  chamber::FlowParams f = base;
  f.effects.feed_limited.enabled = f.effects.worn_liners.enabled = f.effects.squeeze_flow.enabled =
      f.effects.liner_friction.enabled = false;
  if (effect == "feed_limited") {
    if (!(value > 0)) throw std::invalid_argument("feed_limited: max_feed_tph must be > 0, got " + std::to_string(value));
    f.effects.feed_limited.enabled = true;
    f.effects.feed_limited.max_feed_kg_s = value / 3.6;  // YAML: t/h
  } else if (effect == "worn_liners") {
    if (!(value >= 0 && value <= 100))
      throw std::invalid_argument("worn_liners: setting_increase_mm must be in [0, 100], got " + std::to_string(value));
    f.effects.worn_liners.enabled = true;
    f.effects.worn_liners.setting_increase_m = value * 1e-3;  // YAML: mm
  } else if (effect == "squeeze_flow") {
    const double hi = chamber::SqueezeFlow::kMaxEscapeLength_mm;
    if (!(value >= 0 && value <= hi))
      throw std::invalid_argument("squeeze_flow: escape_length_mm must be in [0, " + core::format_number(hi) +
                                  "], got " + std::to_string(value));
    f.effects.squeeze_flow.enabled = true;
    f.effects.squeeze_flow.escape_length_m = value * 1e-3;  // YAML: mm
  } else if (effect == "liner_friction") {
    if (!(value >= 0 && value <= 2))
      throw std::invalid_argument("liner_friction: wall_friction must be in [0, 2], got " + std::to_string(value));
    f.effects.liner_friction.enabled = true;
    f.effects.liner_friction.wall_friction = value;
  } else if (effect != "none" && !effect_module(effect)) {  // (the chamber's own names are the branches above)
    throw std::invalid_argument("unknown effect '" + effect + "'; accepted: none, " + mbd_effect_names() + ", " +
                                flow_effect_names());
  }
  return f;
}

mbd::MechanismParams at_speed(const mbd::MechanismParams& base, double speed_rad_s) {
  if (!(speed_rad_s > 0)) throw std::invalid_argument("drive speed must be positive, got " + std::to_string(speed_rad_s));
  mbd::MechanismParams p = base;
  p.drive_speed_rad_s = speed_rad_s;
  p.dt_s = std::min(base.dt_s, base.dt_s * base.drive_speed_rad_s / speed_rad_s);
  return p;
}

ModelFn make_mbd_model(const ConfigModel& config, const std::vector<Term>& terms, const MbdModelOptions& opt) {
  return [config, terms, opt](const ParamSet& set, double speed, double seconds) {
    mbd::SimOptions so;
    so.duration_s = seconds;
    so.sample_hz = opt.sample_hz;
    so.load = opt.load;
    so.settle_s = opt.settle_s;
    const mbd::MechanismParams p = at_speed(config.mechanism(set, terms), speed);
    return from_fields(mbd::simulate(p, so), "model(" + to_string(set) + ")");
  };
}

ModelFn make_mbd_model(const mbd::MechanismParams& base, const MbdModelOptions& opt) {
  return make_mbd_model(ConfigModel::from_mechanism(with_effect(base, "none", 0.0)), mbd_candidates(), opt);
}

}  // namespace analysis
