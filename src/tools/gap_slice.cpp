// gap_slice: the virtual gap slice on the calibrated bonded-particle rock (src/chamber/gap_slice.hpp): a bed pressed
// across gravity by a plate moving like the mantle, cycle after cycle at each drive speed, and what each cycle costs
// beside what the flow model's shipped law charges (each pressing from loose).
//   gap_slice --out DIR [--bpm FILE] [--config CFG] [--quick] [--rpm R1,R2,...] [--cycles K] [--gap-mm G]
//             [--depth-mm D] [--stroke-mm S] [--rocks N] [--seed N] [--threads N] [--dt-safety X]
// Writes DIR/gap_slice.csv (rpm,cycle,work_J_kg,closing_J_kg,peak_kN,peak_kPa,top_mm,sank_mm,bonds_broken,
// law_J_kg) and DIR/gap_slice_trace.csv (rpm,cycle,t_s,gap_mm,force_kN), plotted by plot_gap_slice.py in
// DIR/gap_slice.png.
//   gap_slice --fit-refill DIR1,DIR2,... --fit-rpm R1,... --out DIR [--config CFG] [--gap-mm G] [--stroke-mm S]
// fits the refill law's length (chamber/refill_fit.hpp) to slices already run (each DIR's gap_slice.csv, one pouring
// each): each pouring's reloads at the --fit-rpm speeds over its reloads at 400 rpm; the other speeds are predicted,
// not fitted. Writes DIR/refill_fit.csv (pouring,rpm,measured,law,fitted) and prints refill.length_mm.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "chamber/flow_config.hpp"
#include "chamber/gap_slice.hpp"
#include "chamber/piston_die.hpp"
#include "chamber/refill_fit.hpp"
#include "core/cli_args.hpp"
#include "core/openmp_wait.hpp"
#include "core/run_program.hpp"
#include "dem/world.hpp"
#include "rocks/bpm_config.hpp"

namespace fs = std::filesystem;

namespace {

struct Args {
  std::string out, bpm, config, command;
  bool quick = false;
  std::vector<double> rpm;  // empty: the library's (400 and 600)
  int cycles = 0, rocks = 0, threads = 1;
  double gap_mm = 0, depth_mm = 0, stroke_mm = 0, dt_safety = 0;  // 0: the library's defaults
  unsigned long long seed = 1;
  std::vector<std::string> fit_dirs;  // --fit-refill: slices already run
  std::vector<double> fit_rpm;
};

constexpr double kReferenceRpm = 400;  // the speed each pouring's reloads are divided by (the calibration's)

constexpr const char* kUsage =
    "usage: gap_slice --out DIR [--bpm FILE] [--config CFG] [--quick] [--rpm R1,R2,...] [--cycles K] [--gap-mm G] "
    "[--depth-mm D] [--stroke-mm S] [--rocks N] [--seed N] [--threads N] [--dt-safety X]\n"
    "       gap_slice --fit-refill DIR1,DIR2,... --fit-rpm R1,... --out DIR [--config CFG] [--gap-mm G] [--stroke-mm S]\n"
    "  a bed of the BPM rock between a fixed plate and one moving like the mantle, x = gap - stroke (1 - cos wt) / 2, "
    "gravity across the stroke, K cycles at each drive speed (rpm, default 400,600) on copies of one poured bed\n"
    "  --config CFG: the flow material whose shipped law (each pressing from loose) is printed beside each cycle "
    "(default launch_free_configs/gyp1200_400rpm.yaml)\n"
    "  --fit-refill DIR1,DIR2,... --fit-rpm R1,...: no DEM; fits the flow model's refill length (flow.material.refill."
    "length_mm) to those slices' reloads at R1,... over their reloads at 400 rpm, with the --config's material and "
    "the slices' --gap-mm and --stroke-mm (default 120 and 15)\n"
    "  --quick: a small slice (16 rocks of 28-32 mm, gap and depth 80 mm, 2 cycles): seconds-to-minutes, the numbers "
    "not representative\n";

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr, "gap_slice: %s\n%s", why.c_str(), kUsage);
  std::exit(2);
}

template <class T>
void append(std::vector<T>& to, const std::vector<T>& items) { to.insert(to.end(), items.begin(), items.end()); }

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 0; i < argc; ++i) a.command += (i ? " " : "") + std::string(argv[i]);
  try {
    core::CliArgs args(argc, argv);
    while (args.next()) {
      const std::string s = args.flag();
      if (s == "--out") a.out = args.value();
      else if (s == "--bpm") a.bpm = args.value();
      else if (s == "--config") a.config = args.value();
      else if (s == "--quick") a.quick = true;
      else if (s == "--fit-refill") append(a.fit_dirs, args.list());  // (a repeated flag adds to the list)
      else if (s == "--fit-rpm") append(a.fit_rpm, args.numbers(1, 3000, "rpm"));
      else if (s == "--rpm") append(a.rpm, args.numbers(1, 3000, "rpm"));
      else if (s == "--cycles") a.cycles = static_cast<int>(args.integer(1, 100));
      else if (s == "--gap-mm") a.gap_mm = args.number(20, 1000, "mm");
      else if (s == "--depth-mm") a.depth_mm = args.number(20, 1000, "mm");
      else if (s == "--stroke-mm") a.stroke_mm = args.number(0.1, 500, "mm");
      else if (s == "--rocks") a.rocks = static_cast<int>(args.integer(1, 100000));
      else if (s == "--seed") a.seed = static_cast<unsigned long long>(args.integer(1, 1000000000));
      else if (s == "--threads") a.threads = static_cast<int>(args.integer(1, 256));
      else if (s == "--dt-safety") {
        a.dt_safety = args.number(0.0, 1.0);
        if (a.dt_safety == 0.0) usage("--dt-safety must be in (0, 1] (fraction of min(0.3 Rayleigh, bond) step), got 0");
      } else if (s == "-h" || s == "--help") {
        std::printf("%s", kUsage);
        std::exit(0);
      } else {
        usage("unknown argument '" + s + "' (accepted: --out, --bpm, --config, --quick, --fit-refill, --fit-rpm, --rpm, --cycles, --gap-mm, "
              "--depth-mm, --stroke-mm, --rocks, --seed, --threads, --dt-safety)");
      }
    }
  } catch (const std::invalid_argument& e) {
    usage(e.what());
  }
  if (a.out.empty()) usage("--out DIR is required");
  if (a.fit_dirs.empty() != a.fit_rpm.empty()) usage("--fit-refill and --fit-rpm go together");
  for (double r : a.fit_rpm)
    if (r == kReferenceRpm) usage("--fit-rpm: 400 rpm is the reference the other speeds are divided by; name others");
  return a;
}

std::string existing(const std::string& given, const std::string& fallback, const char* flag) {
  const std::string file = given.empty() ? core::source_file(fallback) : given;
  if (file.empty() || !fs::exists(file))
    usage(std::string(flag) + ": file '" + (file.empty() ? fallback : file) + "' not found");
  return file;
}

// Each pouring's mean reload (cycles 2 on) per speed, from DIR/gap_slice.csv.
std::vector<chamber::SliceReload> read_reloads(const std::vector<std::string>& dirs) {
  std::vector<chamber::SliceReload> out;
  for (std::size_t i = 0; i < dirs.size(); ++i) {
    const std::string file = dirs[i] + "/gap_slice.csv";
    std::ifstream in(file);
    if (!in) usage("--fit-refill: " + file + " not found (a folder written by gap_slice)");
    std::string line;
    std::getline(in, line);
    if (line.rfind("rpm,cycle,work_J_kg", 0) != 0) usage("--fit-refill: " + file + " is not a gap_slice.csv");
    std::vector<std::pair<double, std::pair<double, int>>> by_rpm;  // rpm, (sum, n) of its reloads
    while (std::getline(in, line)) {
      double rpm = 0, work = 0;
      int cycle = 0;
      if (std::sscanf(line.c_str(), "%lf,%d,%lf", &rpm, &cycle, &work) != 3) usage("--fit-refill: bad line in " + file + ": " + line);
      if (cycle < 2) continue;
      auto it = std::find_if(by_rpm.begin(), by_rpm.end(), [&](const auto& e) { return e.first == rpm; });
      if (it == by_rpm.end()) by_rpm.push_back({rpm, {0.0, 0}}), it = by_rpm.end() - 1;
      it->second.first += work, it->second.second += 1;
    }
    for (const auto& e : by_rpm) out.push_back({static_cast<int>(i), e.first, e.second.first / e.second.second});
  }
  return out;
}

int fit_refill(const Args& a, const chamber::FlowMaterial& mat) {
  const double gap = a.gap_mm > 0 ? a.gap_mm * 1e-3 : chamber::GapSliceOptions{}.gap;
  const double stroke = a.stroke_mm > 0 ? a.stroke_mm * 1e-3 : chamber::GapSliceOptions{}.stroke;
  constexpr int kCycles = 5;
  constexpr double kGravity = 9.81;
  const std::vector<chamber::SliceReload> data = read_reloads(a.fit_dirs);
  const chamber::RefillFit fit = chamber::fit_refill_length(mat, gap, stroke, kCycles, kGravity, data, kReferenceRpm, a.fit_rpm);
  chamber::FlowMaterial law = mat;
  law.refill_length_m = fit.length_m;
  fs::create_directories(a.out);
  std::ofstream csv(a.out + "/refill_fit.csv");
  csv << "pouring,rpm,measured,law,fitted\n";
  std::printf("refill law fitted to %d reload ratios (speeds %s over %.0f rpm; gap %.0f mm, stroke %.1f mm): "
              "refill.length_mm %.4g, rms of ln(measured / law) %.3f\n", fit.ratios, [&] {
                std::string r;
                for (double x : a.fit_rpm) r += (r.empty() ? "" : ",") + core::format_number(x);
                return r;
              }().c_str(), kReferenceRpm, gap * 1e3, stroke * 1e3, fit.length_m * 1e3, fit.rms_log);
  std::printf("%-40s %6s %9s %9s %s\n", "pouring", "rpm", "measured", "law", "");
  std::map<double, double> predicted_at;  // the law's ratio per speed, each computed once
  for (const auto& d : data) {
    if (d.rpm == kReferenceRpm) continue;
    const auto ref = std::find_if(data.begin(), data.end(),
                                  [&](const auto& e) { return e.pouring == d.pouring && e.rpm == kReferenceRpm; });
    if (ref == data.end()) continue;
    const double measured = d.reload_J_kg / ref->reload_J_kg;
    if (!predicted_at.count(d.rpm))
      predicted_at[d.rpm] = chamber::refill_reload_ratio(law, gap, stroke, kCycles, kGravity, d.rpm, kReferenceRpm);
    const double predicted = predicted_at[d.rpm];
    const bool fitted = std::find(a.fit_rpm.begin(), a.fit_rpm.end(), d.rpm) != a.fit_rpm.end();
    std::printf("%-40s %6.0f %9.3f %9.3f %s\n", a.fit_dirs[d.pouring].c_str(), d.rpm, measured, predicted,
                fitted ? "fitted" : "predicted");
    csv << a.fit_dirs[d.pouring] << "," << d.rpm << "," << measured << "," << predicted << "," << (fitted ? 1 : 0) << "\n";
  }
  // each pouring alone: the spread of its length is the rock's sampling
  std::vector<double> own;
  for (std::size_t i = 0; i < a.fit_dirs.size(); ++i) {
    std::vector<chamber::SliceReload> one;
    for (const auto& d : data)
      if (d.pouring == static_cast<int>(i)) one.push_back(d);
    try {
      own.push_back(chamber::fit_refill_length(mat, gap, stroke, kCycles, kGravity, one, kReferenceRpm, a.fit_rpm).length_m);
      std::printf("%-40s alone: refill.length_mm %.4g\n", a.fit_dirs[i].c_str(), own.back() * 1e3);
    } catch (const std::invalid_argument&) {
      std::printf("%-40s alone: no fitted speed beside %.0f rpm\n", a.fit_dirs[i].c_str(), kReferenceRpm);
    }
  }
  if (own.size() > 1) {
    double mean = 0, var = 0;
    for (double d : own) mean += d / own.size();
    for (double d : own) var += (d - mean) * (d - mean) / (own.size() - 1);
    std::printf("pourings alone: mean %.4g mm, std %.4g mm, standard error %.4g mm (%zu pourings)\n", mean * 1e3,
                std::sqrt(var) * 1e3, std::sqrt(var / own.size()) * 1e3, own.size());
  }
  csv.close();
  if (!csv) throw std::runtime_error("writing " + a.out + "/refill_fit.csv failed");
  std::printf("wrote %s/refill_fit.csv\n", a.out.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  core::prefer_passive_openmp_wait(argv);  // the DEM's threads sleep while they wait (a shared machine)
  const Args a = parse(argc, argv);
  try {
    if (!a.fit_dirs.empty())
      return fit_refill(a, chamber::load_flow_run_config(existing(a.config, "launch_free_configs/gyp1200_400rpm.yaml",
                                                                  "--config")).flow.material);
    const rocks::BpmModel bpm =
        rocks::load_bpm_model(existing(a.bpm, "launch_free_configs/bpm_calibrated.yaml", "--bpm"));
    const chamber::FlowMaterial mat =
        chamber::load_flow_run_config(existing(a.config, "launch_free_configs/gyp1200_400rpm.yaml", "--config"))
            .flow.material;
    chamber::GapSliceOptions o;
    o.threads = a.threads, o.seed = a.seed, o.verbose = true;
    o.blowup_dump_path = a.out + "/blowup_gap_slice.csv";
    if (a.quick) o.rock_count = 16, o.rock_min = 0.028, o.rock_max = 0.032, o.gap = o.depth = 0.08, o.cycles = 2;
    if (!a.rpm.empty()) {
      o.frequencies.clear();
      for (double r : a.rpm) o.frequencies.push_back(r / 60.0);
    }
    if (a.cycles) o.cycles = a.cycles;
    if (a.rocks) o.rock_count = a.rocks;
    if (a.gap_mm > 0) o.gap = a.gap_mm * 1e-3;
    if (a.depth_mm > 0) o.depth = a.depth_mm * 1e-3;
    if (a.stroke_mm > 0) o.stroke = a.stroke_mm * 1e-3;
    if (a.dt_safety > 0) o.dt_safety = a.dt_safety;
    o.validate();
    fs::create_directories(a.out);
    const chamber::GapSliceResult r = chamber::run_gap_slice(bpm, o);

    // the shipped law: the loose bed across the gap pressed by s = stroke / gap from loose, every cycle
    chamber::CompactionScale scale;
    if (mat.solid_divergence) scale.limit = chamber::solid_compaction_limit(mat.loose_fraction);
    const double s = o.stroke / o.gap;
    const double law = chamber::hysteretic_loop_loss(mat.modulus_Pa, mat.exponent, mat.rebound, s, scale) /
                       (mat.loose_fraction * mat.solid_density);
    std::ofstream csv(a.out + "/gap_slice.csv"), tr(a.out + "/gap_slice_trace.csv");
    csv << "rpm,cycle,work_J_kg,closing_J_kg,peak_kN,peak_kPa,top_mm,sank_mm,bonds_broken,law_J_kg\n";
    tr << "rpm,cycle,t_s,gap_mm,force_kN\n";
    std::printf("gap slice: %d rocks (%.1f kg, %zu particles, %zu bonds), bed %.1f mm at solid fraction %.3f; gap %.0f "
                "mm, depth %.0f mm, stroke %.1f mm (s %.3f); dt %.3g s; %.0f s\n",
                r.rocks, r.rock_mass, r.particles, r.bonds, r.bed_height * 1e3, r.loose_solid_fraction, o.gap * 1e3,
                o.depth * 1e3, o.stroke * 1e3, s, r.dt, r.wall_s);
    std::printf("the shipped law's pressing from loose (%s): %.4f J/kg per cycle\n", a.config.empty() ? "gyp1200_400rpm.yaml" : a.config.c_str(), law);
    std::printf("%6s %5s %10s %10s %8s %8s %8s %8s %6s %8s\n", "rpm", "cycle", "work J/kg", "close J/kg", "peak kN",
                "peak kPa", "top mm", "sank mm", "bonds", "/ law");
    for (const auto& run : r.runs) {
      const double rpm = run.frequency * 60.0;
      int k = 0;
      for (const auto& c : run.cycles) {
        ++k;
        char line[256];
        std::snprintf(line, sizeof line, "%.6g,%d,%.6g,%.6g,%.6g,%.6g,%.4f,%.4f,%zu,%.6g\n", rpm, k, c.work_per_kg,
                      c.loading_work_per_kg, c.peak_force * 1e-3, c.peak_pressure * 1e-3, c.top * 1e3,
                      c.com_drop * 1e3, c.bonds_broken, law);
        csv << line;
        std::printf("%6.0f %5d %10.4f %10.4f %8.3f %8.2f %8.1f %8.2f %6zu %8.3f\n", rpm, k, c.work_per_kg,
                    c.loading_work_per_kg, c.peak_force * 1e-3, c.peak_pressure * 1e-3, c.top * 1e3, c.com_drop * 1e3,
                    c.bonds_broken, c.work_per_kg / law);
      }
      if (!run.blowup.empty()) std::printf("%6.0f rpm: %s\n", rpm, run.blowup.c_str());
      for (std::size_t i = 0; i < run.t.size(); ++i) {
        char line[128];
        const int cycle = std::max(1, static_cast<int>(std::ceil(run.t[i] * run.frequency - 1e-9)));
        std::snprintf(line, sizeof line, "%.6g,%d,%.6g,%.5f,%.6g\n", rpm, cycle, run.t[i], run.gap[i] * 1e3,
                      run.force[i] * 1e-3);
        tr << line;
      }
    }
    csv.close(), tr.close();
    if (!csv || !tr) throw std::runtime_error("writing " + a.out + "/gap_slice.csv or gap_slice_trace.csv failed");
    std::printf("wrote %s/gap_slice.csv and gap_slice_trace.csv\n", a.out.c_str());
    if (core::run_plot_script("gap_slice", "plot_gap_slice.py", a.out)) std::printf("plot: %s/gap_slice.png\n", a.out.c_str());
  } catch (const std::invalid_argument& e) {
    usage(e.what());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "gap_slice: %s\n", e.what());
    return 1;
  }
  return 0;
}
