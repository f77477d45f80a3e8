// make_recording: a test recording from the model with one concealed effect switched on, plus sensor
// noise, a time offset and a displacement-gain error. The effect's name is not written to the file.
//   make_recording --config BASE.yaml --effect NAME|none --value V [--load bed|flow] [--noise-std R]
//                  [--time-offset-s S] [--gain G] [--seconds S] [--seed N] [--speed-rpm RPM] [--settle-s S]
//                  [--set KEY=V] [--scale KEY=F] --out FILE.csv
// --set / --scale conceal a miscalibrated config value (any schema key, KEY[i] for a list element; --scale
// multiplies every number under the key), as the diagnosis refits them (analysis/param_set.hpp).
// --noise-std is relative: noise std = R x channel scale (std of the channel, at least 1 % of its mean).
// --load bed (default): the mechanism with the equivalent bed (mbd::simulate); --load flow: under the chamber flow
// model (analysis::run_flow, the config's flow: section), the only load the chamber effects act in.
// With --columns it writes a plant-style export instead (analysis/plant_export.hpp): the mapped columns in
// their units, delimiter and decimal separator, values rounded to --resolution, and plant habits on demand:
// the speed logged at its set point, rows of missing values, a gap, another sample rate.
#include <cmath>
#include <cstdlib>
#include <random>
#include <iostream>
#include <string>

#include "analysis/flow_run.hpp"
#include "analysis/mbd_model.hpp"
#include "analysis/param_set.hpp"
#include "chamber/flow_config.hpp"
#include "analysis/plant_export.hpp"
#include "analysis/sensor_model.hpp"
#include "core/cli_args.hpp"
#include "core/config.hpp"
#include "core/units.hpp"
#include "mbd/simulate.hpp"

using namespace analysis;

int main(int argc, char** argv) {
  const char* usage =
      "usage: make_recording --config BASE.yaml --effect none|joint_friction|absorber_nonlinearity|motor_droop|"
      "cardan_misalignment|bearing_friction|drive_efficiency|feed_limited|worn_liners|squeeze_flow|liner_friction --value V [--load bed|flow "
      "(default bed)] [--noise-std R (fraction, default 0.01)] [--time-offset-s S (default 0)] "
      "[--gain G (default 1)] [--zero-offset-mm DX,DY,DZ (default 0,0,0)] [--seconds S (default 10)] [--seed N (default 1)] [--speed-rpm RPM (default: "
      "config)] [--settle-s S (default 4)] [--set KEY=V] [--scale KEY=F] (repeatable: a config value concealed,\n"
      "  KEY as in diagnosis.uncertain, e.g. mbd.fixed_cone.mass_kg, flow.material.pressure.modulus_MPa) --out FILE.csv\n"
      "  plant-style export: --columns t=COL[UNIT],x=COL[UNIT],... (keys t x y z ax ay az power speed, as in\n"
      "  diagnose) [--delimiter ,|;|tab] [--decimal .|,] [--resolution KEY=VALUE[UNIT],...] [--speed-setpoint\n"
      "  (speed logged constant at the drive set point)] [--missing-rows N (rows written as NaN)]\n"
      "  [--gap T0:LEN (seconds left out, from the start)] [--sample-hz HZ (default 1000, whole model steps)]\n"
      "  V in the unit of mbd.effects.<name>.<main parameter>: coulomb_Nm, cubic_N_per_m3, droop_rad_s_per_kNm, "
      "angle_deg, mu, efficiency;\n"
      "  or of flow.effects.<name>.<main parameter> (needs --load flow): max_feed_tph, setting_increase_mm, escape_length_mm\n";
  std::string config, effect, out, load = "bed";
  double value = 0, seconds = 10, speed_rpm = -1, settle = 4;
  SensorErrors e;
  e.noise_rel = 0.01;
  bool have_value = false, speed_setpoint = false;
  std::string columns, delimiter, decimal, resolution;
  long missing_rows = 0;
  double gap_t0 = -1, gap_len = 0, sample_hz = 1000;
  std::vector<Term> concealed_terms;  // --set / --scale: config values changed before the run
  ParamSet concealed;
  try {
    core::CliArgs args(argc, argv);
    while (args.next()) {
      const std::string a = args.flag();
      auto str = [&] { return args.value(); };
      auto num = [&](double lo, double hi) { return args.number(lo, hi); };
      if (a == "--config") config = str();
      else if (a == "--effect") effect = str();
      else if (a == "--value") { value = num(-1e15, 1e15); have_value = true; }
      else if (a == "--noise-std") e.noise_rel = num(0, 10);
      else if (a == "--time-offset-s") e.time_offset_s = num(-1e4, 1e4);
      else if (a == "--gain") e.gain = num(1e-3, 1e3);
      else if (a == "--zero-offset-mm") {
        const std::string v = str();
        const std::vector<std::string> items = analysis::split_items(v);
        const std::invalid_argument refused("--zero-offset-mm " + v + ": accepted three numbers in mm, DX,DY,DZ");
        if (items.size() != 3) throw refused;
        for (std::size_t i = 0; i < 3; ++i) {
          double d = NAN;
          try {
            std::size_t used = 0;
            d = std::stod(items[i], &used);
            if (used != items[i].size()) d = NAN;  // trailing junk ("1.3mm")
          } catch (const std::exception&) {
          }
          if (!std::isfinite(d) || std::abs(d) > 1e3) throw refused;
          e.zero_offset_m[i] = d * 1e-3;
        }
      }
      else if (a == "--seconds") seconds = num(0.1, 3600);
      else if (a == "--seed") e.seed = static_cast<std::uint64_t>(num(0, 1e15));
      else if (a == "--speed-rpm") speed_rpm = num(1, 5000);
      else if (a == "--settle-s") settle = num(0, 60);
      else if (a == "--load") load = str();
      else if (a == "--out") out = str();
      else if (a == "--columns") columns = str();
      else if (a == "--delimiter") delimiter = str();
      else if (a == "--decimal") decimal = str();
      else if (a == "--resolution") resolution = str();
      else if (a == "--speed-setpoint") speed_setpoint = true;
      else if (a == "--missing-rows") missing_rows = args.integer(0, 1000000);
      else if (a == "--sample-hz") sample_hz = num(1, 1e5);
      else if (a == "--gap") {
        const std::string g = str();
        char* end = nullptr;
        gap_t0 = std::strtod(g.c_str(), &end);
        if (!end || *end != ':' || !(gap_t0 >= 0)) throw std::invalid_argument("--gap " + g + ": accepted T0:LEN in seconds");
        const char* rest = end + 1;
        gap_len = std::strtod(rest, &end);
        if (!end || *end || end == rest || !(gap_len > 0)) throw std::invalid_argument("--gap " + g + ": accepted T0:LEN in seconds");
      }
      else if (a == "--set" || a == "--scale") {
        const std::string kv = str();
        const auto eq = kv.find('=');
        if (eq == std::string::npos || eq == 0)
          throw std::invalid_argument(a + " " + kv + ": accepted KEY=NUMBER (a config key such as mbd.fixed_cone.mass_kg)");
        const double v = core::parse_number(a + " " + kv.substr(0, eq) + " value", kv.substr(eq + 1), -1e15, 1e15);
        Term t;
        t.kind = Term::Miscalibrated;
        t.name = t.parameter = kv.substr(0, eq);
        t.scale = a == "--scale";
        if (concealed.count(t.name)) throw std::invalid_argument(a + ": " + t.name + " is given twice");
        concealed_terms.push_back(t);
        concealed[t.name] = v;
      }
      else if (a == "-h" || a == "--help") { std::cout << usage; return 0; }
      else throw std::invalid_argument("unknown argument '" + a + "'");
    }
    if (config.empty() || effect.empty() || out.empty()) throw std::invalid_argument("--config, --effect and --out are required");
    if (effect != "none" && !have_value) throw std::invalid_argument("--value is required with --effect " + effect);
    if (load != "bed" && load != "flow")
      throw std::invalid_argument("--load '" + load + "' is not accepted; accepted: bed, flow");
    if (is_flow_effect(effect) && load != "flow")
      throw std::invalid_argument("--effect " + effect + " is a chamber flow-model effect (flow.effects." + effect +
                                  "): it needs --load flow");
    if (columns.empty() && (!delimiter.empty() || !decimal.empty() || !resolution.empty() || speed_setpoint ||
                            missing_rows || gap_t0 >= 0))
      throw std::invalid_argument("--delimiter, --decimal, --resolution, --speed-setpoint, --missing-rows and --gap "
                                  "write a plant export: give its --columns");
    PlantFormat plant;
    if (!columns.empty()) {
      plant.columns = parse_column_map(columns);
      if (!delimiter.empty()) plant.delimiter = parse_delimiter(delimiter);
      if (!decimal.empty()) plant.decimal = parse_decimal(decimal);
      if (!resolution.empty()) parse_resolutions(resolution, plant);
    }
    Recording model;
    double drive_speed = 0;
    const ConfigModel cfg_model(config);
    if (load == "bed") {
      mbd::MechanismParams p = cfg_model.mechanism(concealed, concealed_terms);
      p = with_effect(p, effect, value);
      if (speed_rpm > 0) p = at_speed(p, speed_rpm * core::units::rpm);
      mbd::validate(p);
      mbd::SimOptions so;
      so.duration_s = seconds;
      so.settle_s = settle;
      so.load = "bed";
      so.sample_hz = sample_hz;
      model = from_fields(mbd::simulate(p, so), "model");
      drive_speed = p.drive_speed_rad_s;
    } else {
      auto cfg = cfg_model.flow_run(concealed, concealed_terms);
      mbd::MechanismParams p = with_effect(cfg.mech, is_flow_effect(effect) ? "none" : effect, value);
      const chamber::FlowParams f = with_flow_effect(cfg.flow, effect, value);
      if (speed_rpm > 0) p = at_speed(p, speed_rpm * core::units::rpm);
      mbd::validate(p, false);
      FlowRunOptions fo;
      fo.duration_s = seconds;
      fo.settle_s = settle;
      fo.sample_hz = sample_hz;
      const FlowRunResult r = run_flow(p, f, fo);
      // The run's signals start at the run's start: keep the window after the settle time, its clock from 0.
      RunSignals w;
      const auto& s = r.signals;
      double t0 = -1;
      for (std::size_t i = 0; i < s.t_s.size(); ++i) {
        if (s.t_s[i] < settle - 1e-9) continue;
        if (t0 < 0) t0 = s.t_s[i];
        w.t_s.push_back(s.t_s[i] - t0);
        w.x_m.push_back(s.x_m[i]);
        w.y_m.push_back(s.y_m[i]);
        w.z_m.push_back(s.z_m[i]);
        w.power_W.push_back(s.power_W[i]);
        w.speed_rad_s.push_back(s.speed_rad_s[i]);
      }
      model = from_fields(w, "model");
      drive_speed = p.drive_speed_rad_s;
    }
    if (columns.empty()) {
      Recording rec = apply_sensor_errors(model, e);
      write_recording_csv(rec, out);
      std::cout << "wrote " << out << " (" << rec.size() << " samples, " << seconds << " s)\n";
      return 0;
    }
    if (plant.columns.count(kAx) || plant.columns.count(kAy) || plant.columns.count(kAz)) model = with_acceleration(model);
    Recording rec = apply_sensor_errors(model, e);
    if (speed_setpoint) rec.speed_rad_s.assign(rec.size(), drive_speed);
    if (gap_t0 >= 0) {
      const double t0 = rec.t_s.front();
      Recording a = rec.slice(t0, t0 + gap_t0), b = rec.slice(t0 + gap_t0 + gap_len, rec.t_s.back() + 1);
      for (std::size_t i = 0; i < b.size(); ++i) {
        a.t_s.push_back(b.t_s[i]);
        for (int c = 0; c < kNumChannels; ++c)
          if (b.has(c)) a.channel(c).push_back(b.channel(c)[i]);
      }
      rec = a;
    }
    std::vector<std::size_t> missing;
    std::mt19937_64 rng(e.seed + 7);
    std::uniform_int_distribution<std::size_t> row(0, rec.size() - 1);
    for (long i = 0; i < missing_rows; ++i) missing.push_back(row(rng));
    write_plant_export(rec, out, plant, missing);
    std::cout << "wrote " << out << " (plant export, " << rec.size() << " rows, " << seconds << " s)\n";
    return 0;
  } catch (const std::exception& ex) {
    std::cerr << "make_recording: error: " << ex.what() << "\n" << usage;
    return 2;
  }
}
