// diagnose: where a simulation and real recordings differ, which omitted physics explains it, the model
// with it fitted, and the fit before/after (issue 6; DESIGN.md "scripts/crusher diagnose").
//   diagnose --recording FILE [--recording FILE...] --config BASE.yaml --out DIR
//            [--model-seconds S] [--settle-s S] [--no-plots]
//            [--columns MAP [--delimiter D] [--decimal C]] [--resolution LIST]
// FILE: CSV (t_s, x_m, y_m, z_m, power_W, speed_rad_s), a plant export read through --columns
// (analysis/plant_export.hpp) or, when built with ROS, a bag with /crusher/test_point and /crusher/drive.
// The first recording trains, the others are held out.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/diagnosis.hpp"
#include "analysis/flow_run.hpp"
#include "analysis/mbd_model.hpp"
#include "analysis/plant_export.hpp"
#include "analysis/summary_diagnosis.hpp"
#include "core/cli_args.hpp"
#include "core/config.hpp"
#include "core/run_program.hpp"
#include "mbd/mechanism_params.hpp"

#ifdef CRUSHER_WITH_ROS
#include <inertia_crusher/DriveState.h>
#include <inertia_crusher/TestPoint.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#endif

namespace fs = std::filesystem;
using namespace analysis;

namespace {

const char* kUsage =
    "usage: diagnose --recording FILE [--recording FILE...] --config BASE.yaml --out DIR\n"
    "       diagnose --summary TABLE.yaml --config BASE.yaml --out DIR   (plant averages per speed, e.g. Table 5)\n"
    "                [--model-seconds S (default 3)] [--settle-s S (default 4)] [--no-plots]\n"
    "                [--setpoint-rpm R (once per recording, in order: the drive set point)]\n"
    "                [--setpoint whole-rpm|measured (without --setpoint-rpm: the config's speed when the\n"
    "                 mean speed is within 3 % of it, else the mean rounded to whole rpm or the mean)]\n"
    "                [--columns t=COL[UNIT],x=COL[UNIT],... (a plant export; applies to every FILE)]\n"
    "                [--delimiter ,|;|tab|'|' (default ,)] [--decimal .|, (default .)]\n"
    "                [--resolution KEY=VALUE[UNIT],... (logger resolution; default: from the data)]\n"
    "                [--zero-unknown x,y,z (displacement sensors not zeroed at the machine's rest: their\n"
    "                 means are not compared)]\n"
    "                [--part FILE (after a --recording: the same recording continued in another file, e.g.\n"
    "                 a logger's hourly files; joined in order, the time between them kept as a gap)]\n"
    "  FILE: CSV with header t_s,x_m,y_m,z_m,power_W,speed_rad_s, or a .bag with /crusher/test_point\n"
    "  and /crusher/drive (ROS builds only). The first recording trains; the others are held out.\n"
    "  TABLE.yaml: source, uncertainty_pct and one row per speed (src/analysis/README.md); the model is the\n"
    "  config's fast mode (flow load) over its run.duration_s after run.settle_s unless --model-seconds.\n"
    "  Candidates: the omitted-effect modules and the config's diagnosis.uncertain values.\n"
    "  --columns keys and units: t (s, ms, us); x, y, z (m, mm, um); ax, ay, az (m/s^2, mm/s^2, g);\n"
    "  power (W, kW, MW); speed (rad/s, rpm, 1/min, Hz). Other columns are ignored; at least t and one of\n"
    "  x, y, z, ax, ay, az; without speed, --setpoint-rpm gives the drive speed. Rows with a missing value\n"
    "  are skipped and gaps fitted as they are (both reported). E.g. --columns t=time[s],x=disp_x[mm],\n"
    "  y=disp_y[mm],power=P[kW],speed=n[rpm] --delimiter ';' --decimal , --resolution x=0.01mm,power=0.1kW\n";

#ifdef CRUSHER_WITH_ROS
// Test-point samples with the drive state linearly interpolated to their stamps.
Recording read_bag(const std::string& path) {
  rosbag::Bag bag;
  try {
    bag.open(path, rosbag::bagmode::Read);
  } catch (const std::exception& e) {
    throw std::invalid_argument(path + ": cannot open bag (" + e.what() + ")");
  }
  std::vector<double> tp_t, dx, dy, dz, dr_t, sp, pw;
  rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{"/crusher/test_point", "/crusher/drive"}));
  for (const auto& m : view) {
    if (auto tp = m.instantiate<inertia_crusher::TestPoint>()) {
      tp_t.push_back(tp->header.stamp.toSec());
      dx.push_back(tp->displacement.x);
      dy.push_back(tp->displacement.y);
      dz.push_back(tp->displacement.z);
    } else if (auto d = m.instantiate<inertia_crusher::DriveState>()) {
      dr_t.push_back(d->header.stamp.toSec());
      sp.push_back(d->speed);
      pw.push_back(d->power);
    } else {
      throw std::invalid_argument(path + ": topic " + m.getTopic() + " has type " + m.getDataType() +
                                  "; accepted: inertia_crusher/TestPoint on /crusher/test_point, "
                                  "inertia_crusher/DriveState on /crusher/drive");
    }
  }
  bag.close();
  if (tp_t.empty() || dr_t.empty())
    throw std::invalid_argument(path + ": bag lacks messages on /crusher/test_point (" + std::to_string(tp_t.size()) +
                                ") or /crusher/drive (" + std::to_string(dr_t.size()) + "); both are needed");
  Recording r;
  r.source = path;
  std::size_t j = 0;
  for (std::size_t i = 0; i < tp_t.size(); ++i) {
    const double t = tp_t[i];
    if (t < dr_t.front() || t > dr_t.back()) continue;
    if (!r.t_s.empty() && t <= r.t_s.back()) continue;  // duplicate stamps
    while (j + 1 < dr_t.size() && dr_t[j + 1] < t) ++j;
    const std::size_t k = std::min(j + 1, dr_t.size() - 1);
    const double a = dr_t[k] > dr_t[j] ? (t - dr_t[j]) / (dr_t[k] - dr_t[j]) : 0.0;
    r.t_s.push_back(t);
    r.x_m.push_back(dx[i]);
    r.y_m.push_back(dy[i]);
    r.z_m.push_back(dz[i]);
    r.speed_rad_s.push_back(sp[j] + a * (sp[k] - sp[j]));
    r.power_W.push_back(pw[j] + a * (pw[k] - pw[j]));
  }
  // Re-use the CSV checks (monotonic time, gaps, positive speed, finite values).
  std::ostringstream csv;
  csv.precision(12);
  csv << "t_s,x_m,y_m,z_m,power_W,speed_rad_s\n";
  for (std::size_t i = 0; i < r.size(); ++i)
    csv << r.t_s[i] << ',' << r.x_m[i] << ',' << r.y_m[i] << ',' << r.z_m[i] << ',' << r.power_W[i] << ','
        << r.speed_rad_s[i] << '\n';
  return parse_recording_csv(csv.str(), path + " (bag, merged)");
}
#endif

Recording read_any(const std::string& path, const PlantFormat* plant) {
  if (plant) return read_plant_export(path, *plant);
  const std::string ext = fs::path(path).extension().string();
  if (ext == ".bag") {
#ifdef CRUSHER_WITH_ROS
    return read_bag(path);
#else
    throw std::invalid_argument(path + ": bag input needs a build with ROS (CRUSHER_WITH_ROS); convert it to "
                                "CSV (t_s,x_m,y_m,z_m,power_W,speed_rad_s) or rebuild with ROS");
#endif
  }
  return read_recording_csv(path);
}

// fitted.yaml: the config (its base chain resolved) with the named terms at their fitted values.
std::string fitted_yaml(const ConfigModel& cfg, const std::string& effect, const std::vector<TermFit>& named,
                        const ParamSet& fitted, const std::vector<Term>& terms) {
  std::ostringstream y;
  y << "# Written by diagnose from " << cfg.file() << ": " << effect;
  for (const auto& c : named)
    y << "\n#   " << c.term.key() << (c.term.scale ? " scaled by " : " = ") << c.value << " +- " << c.sigma << " "
      << c.term.unit;
  if (named.empty()) y << " (model unchanged)";
  y << "\n";
  YAML::Node root = cfg.with(fitted, terms);
  YAML::Emitter em;
  em << root;
  y << em.c_str() << "\n";
  return y.str();
}

void write_text(const fs::path& p, const std::string& s) {
  std::ofstream f(p);
  f << s;
  if (!f) throw std::runtime_error(p.string() + ": cannot write");
}

// Aligned recording and model (before, after) for the plots: first `seconds` of each data set.
void write_overlay(const fs::path& p, const Dataset& d, const Comparison& before, const Comparison& after,
                   double seconds) {
  std::ofstream f(p);
  f.precision(9);
  f << "t_s";
  // Channels compared (a set point or a channel not recorded has no model curve).
  std::vector<int> cs;
  for (int c = 0; c < kNumChannels; ++c)
    if (before.ch[c].compared && after.ch[c].compared) cs.push_back(c);
  for (const char* w : {"rec", "before", "after"})
    for (int c : cs) f << ',' << w << '_' << kChannelNames[c];
  f << '\n';
  const double t0 = d.rec.t_s.front();
  for (std::size_t i = 0; i < d.rec.size() && d.rec.t_s[i] < t0 + seconds; ++i) {
    f << d.rec.t_s[i];
    for (int c : cs) f << ',' << d.rec.channel(c)[i];
    for (int c : cs) f << ',' << before.model_on_recording_times[c][i];
    for (int c : cs) f << ',' << after.model_on_recording_times[c][i];
    f << '\n';
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::vector<std::string>> recs;  // each recording's files (--part adds to the last)
  std::string config, out, summary;
  double model_seconds = 3.0, settle_s = 4.0;
  bool model_seconds_given = false, settle_given = false;
  bool plots = true, whole_rpm = true;
  std::vector<double> setpoint_rpm;
  std::string columns, delimiter, decimal, resolution;
  std::array<bool, kNumChannels> zero_unknown{};
  try {
    core::CliArgs args(argc, argv);
    while (args.next()) {
      const std::string a = args.flag();
      auto value = [&] { return args.value(); };
      auto number = [&](double lo, double hi) { return args.number(lo, hi); };
      if (a == "--recording") recs.push_back({value()});
      else if (a == "--part") {
        if (recs.empty()) throw std::invalid_argument("--part FILE continues a recording: give its --recording first");
        recs.back().push_back(value());
      }
      else if (a == "--config") config = value();
      else if (a == "--out") out = value();
      else if (a == "--summary") summary = value();
      else if (a == "--model-seconds") model_seconds = number(0.3, 60), model_seconds_given = true;
      else if (a == "--settle-s") settle_s = number(0, 60), settle_given = true;
      else if (a == "--no-plots") plots = false;
      else if (a == "--setpoint-rpm") setpoint_rpm.push_back(number(1, 5000));
      else if (a == "--columns") columns = value();
      else if (a == "--delimiter") delimiter = value();
      else if (a == "--decimal") decimal = value();
      else if (a == "--resolution") resolution = value();
      else if (a == "--zero-unknown") zero_unknown = parse_zero_unknown(value());
      else if (a == "--setpoint") {
        const std::string v = value();
        if (v != "whole-rpm" && v != "measured")
          throw std::invalid_argument("--setpoint " + v + ": accepted whole-rpm (default) or measured");
        whole_rpm = v == "whole-rpm";
      }
      else if (a == "-h" || a == "--help") { std::cout << kUsage; return 0; }
      else throw std::invalid_argument("unknown argument '" + a + "'");
    }
    if (config.empty() || out.empty()) throw std::invalid_argument("--config and --out are required");
    if (recs.empty() == summary.empty())
      throw std::invalid_argument("give --recording FILE (time series, one or more) or --summary FILE (averages), not both");
    if (!summary.empty()) {
      const bool series_only = !columns.empty() || !delimiter.empty() || !decimal.empty() || !resolution.empty() ||
                               !setpoint_rpm.empty() ||
                               std::any_of(zero_unknown.begin(), zero_unknown.end(), [](bool z) { return z; });
      if (series_only)
        throw std::invalid_argument("--columns, --delimiter, --decimal, --resolution, --setpoint-rpm and "
                                    "--zero-unknown read time series (--recording), not a --summary");
      const ConfigModel cfg(config);
      // The fast model: every module, the chamber's too (summary_candidates), and the uncertain values.
      std::vector<Term> candidates = summary_candidates();
      for (const auto& t : cfg.uncertain()) candidates.push_back(t);
      const auto data = read_summary(summary);
      const auto run = cfg.flow_run({}, candidates).run;
      const analysis::FlowRunOptions w =
          analysis::run_window(run, config, model_seconds_given ? model_seconds : -1, settle_given ? settle_s : -1);
      model_seconds = w.duration_s, settle_s = w.settle_s;
      std::cerr << "diagnose: summary " << summary << " (" << data.rows.size() << " speeds), model " << config
                << " (flow, " << model_seconds << " s after " << settle_s << " s)\n";
      SummaryDiagnosisOptions so;
      const SummaryDiagnosis d =
          diagnose_summary(data, make_flow_summary_model(cfg, candidates, model_seconds, settle_s), candidates, so);
      fs::create_directories(out);
      const fs::path dir(out);
      write_text(dir / "diagnosis.json", summary_diagnosis_json(d));
      write_text(dir / "report.md", summary_diagnosis_markdown(d));
      write_text(dir / "fitted.yaml", fitted_yaml(cfg, d.effect, d.selection.named, d.selection.fitted, candidates));
      if (plots) core::run_plot_script("diagnose", "plot_diagnosis.py", dir.string());
      std::cout << "effect " << d.effect << "\n" << d.reason << "\n";
      for (const auto& c : d.selection.named)
        std::cout << c.term.key() << (c.term.scale ? " x " : " ") << c.value << " +- " << c.sigma << " " << c.term.unit << "\n";
      std::cout << "wall_s " << d.wall_s << " model_runs " << d.model_runs << "\nwrote " << out << "\n";
      return 0;
    }

    const mbd::MechanismParams base = mbd::load_mechanism_params_file(config);
    const ConfigModel cfg(config);  // the model the terms change; its diagnosis.uncertain values are candidates
    std::vector<Term> candidates = series_candidates();
    for (const auto& t : cfg.uncertain()) candidates.push_back(t);

    PlantFormat plant;
    if (!columns.empty()) {
      plant.columns = parse_column_map(columns);
      if (!delimiter.empty()) plant.delimiter = parse_delimiter(delimiter);
      if (!decimal.empty()) plant.decimal = parse_decimal(decimal);
    } else if (!delimiter.empty() || !decimal.empty()) {
      throw std::invalid_argument("--delimiter and --decimal read a plant export: give its --columns too");
    } else {
      for (int c = 0; c < kAx; ++c) plant.columns[c].to_si = 1.0;  // --resolution without a unit: SI
    }
    if (!resolution.empty()) parse_resolutions(resolution, plant);
    std::vector<Recording> recordings;
    for (std::size_t i = 0; i < recs.size(); ++i) {
      plant.setpoint_rad_s = i < setpoint_rpm.size() ? setpoint_rpm[i] * 2.0 * M_PI / 60.0 : 0.0;
      std::vector<Recording> parts;
      for (const auto& file : recs[i]) parts.push_back(read_any(file, columns.empty() ? nullptr : &plant));
      recordings.push_back(join_parts(parts));
      recordings.back().resolution = plant.resolution;
      recordings.back().zero_unknown = zero_unknown;
      for (const auto& note : recordings.back().notes)
        std::cerr << "diagnose: " << recordings.back().source << ": " << note << "\n";
    }

    MbdModelOptions mo;
    mo.settle_s = settle_s;
    DiagnosisOptions opt;
    opt.model_seconds = model_seconds;
    opt.setpoint_whole_rpm = whole_rpm;
    opt.nominal_setpoints_rad_s = {base.drive_speed_rad_s};
    for (double rpm : setpoint_rpm) opt.setpoints_rad_s.push_back(rpm * 2.0 * M_PI / 60.0);
    std::cerr << "diagnose: " << recordings.size() << " recording(s), model " << config << "\n";
    DiagnosisResult r = diagnose(recordings, make_mbd_model(cfg, candidates, mo), candidates, opt);

    fs::create_directories(out);
    const fs::path dir(out);
    write_text(dir / "diagnosis.json", diagnosis_json(r));
    write_text(dir / "report.md", diagnosis_markdown(r));
    write_text(dir / "fitted.yaml", fitted_yaml(cfg, r.effect, r.named, r.fitted, candidates));

    if (plots) {
      int i = 0;
      for (std::size_t k = 0; k < r.train.size(); ++k)
        write_overlay(dir / ("overlay_" + std::to_string(i++) + ".csv"), r.train[k], r.before_train[k], r.after_train[k], 1.0);
      for (std::size_t k = 0; k < r.heldout.size(); ++k)
        write_overlay(dir / ("overlay_" + std::to_string(i++) + ".csv"), r.heldout[k], r.before_heldout[k], r.after_heldout[k], 1.0);
      core::run_plot_script("diagnose", "plot_diagnosis.py", dir.string());
    }
    std::cout << "effect " << r.effect << "\n" << r.reason << "\n";
    for (const auto& c : r.named)
      std::cout << c.term.key() << (c.term.scale ? " x " : " ") << c.value << " +- " << c.sigma << " " << c.term.unit << "\n";
    std::cout << "wall_s " << r.wall_s << " model_runs " << r.model_runs << "\nwrote " << out << "\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "diagnose: error: " << e.what() << "\n" << kUsage;
    return 2;
  }
}
