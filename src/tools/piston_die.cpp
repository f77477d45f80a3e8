// piston_die: virtual piston-die test on the calibrated bonded-particle rock (or a plant's lab results) and the
// chamber flow model's material parameters fitted from it (src/chamber/piston_die.hpp).
//   piston_die --out DIR [--bpm FILE] [--quick] [--threads N] [--seed N] [--replicates K] [--reloads K] [--lab CSV]
//   piston_die --out DIR --pool DIR1,DIR2,...      (the pourings of earlier runs fitted together, no DEM)
// Writes DIR/piston_die.csv (s_max,phase,s,p_MPa), DIR/psd.csv (s_max,sieve_mm,passing_pct; s_max "feed" for the
// feed), DIR/psd_fit.csv (the fitted breakage event, same columns), DIR/flow_material.yaml, DIR/piston_die_pourings.txt
// (every pouring in full, piston_die_record.hpp: what --pool reads), with two or more pourings
// DIR/piston_die_pourings.csv (every pouring's loops: pouring,seed,loose_solid_fraction,s_max,phase,s,p_MPa),
// DIR/piston_die_fits.csv (each pouring's own fit, the pooled one, which flow_material.yaml holds, and with three or
// more the jackknife's: the pooled fit without each pouring, also as DIR/jackknife/flow_material_without_seed<S>.yaml,
// which `crusher validate --rock-spread DIR` reads) and, through plot_piston_die.py, DIR/piston_die.png and DIR/psd.png
// (with --reloads also DIR/piston_die_reloads.png).
// With --reloads also DIR/piston_die_reloads.csv and DIR/piston_die_reload_curves.csv (write_reloads).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/jackknife.hpp"
#include "chamber/piston_die.hpp"
#include "chamber/piston_die_record.hpp"
#include "core/cli_args.hpp"
#include "core/openmp_wait.hpp"
#include "core/run_program.hpp"
#include "dem/world.hpp"

namespace fs = std::filesystem;

namespace {

struct Args {
  std::string out, bpm, lab, command;
  std::vector<std::string> pool;  // --pool: run folders whose piston_die_pourings.txt are fitted together
  bool quick = false;
  double speed = 0;  // m/s, 0: the default
  int threads = 1;
  unsigned long long seed = 1;
  double dt_safety = 0.0;  // 0: the library's default
  int rocks = 0;           // 0: the library's default
  std::vector<double> ratios;  // empty: the library's default
  double die_mm = 0;       // 0: the library's default
  int replicates = 1;      // pourings (seeds seed, seed + 1, ...), fitted pooled; >= 2: also scatter.lump_std
  int reloads = 0;         // pressings of each bed again to the same s_max after the first (not fitted)
  double shift_mm = 0;     // each reload after the bed is pushed this far down the die
  double sweep = 0;        // sideways piston speed / its vertical speed in every pressing
};

constexpr const char* kUsage =
    "usage: piston_die --out DIR [--bpm FILE] [--quick] [--threads N] [--seed N] [--dt-safety X] [--rocks N] "
    "[--die-mm D] [--ratios S1,S2,...] [--speed-m-s V] [--replicates K] [--reloads K [--shift-mm F]] "
    "[--sweep R] [--lab CSV] [--pool DIR1,DIR2,...]\n"
    "  --replicates K: K pourings (seeds N ... N + K - 1), the material fitted on all of them pooled, each pouring's "
    "own fit in piston_die_fits.csv, scatter.lump_std from the peaks' spread; a pouring whose deeper loop blows up "
    "keeps the loops it completed; with K >= 3 the jackknife (the pooled fit without each pouring)\n"
    "  --reloads K: after each first pressing, K more of the same bed to the same s_max (nothing re-poured): the loop "
    "energy, bonds broken and product of each, printed and in piston_die_reloads.csv (not fitted)\n"
    "  --shift-mm F: before each reload the bed is pushed F mm down the die (floor and piston together, the bed "
    "sliding along the wall) and left to rest: how far a compacted bed must move to loosen\n"
    "  --sweep R: in every pressing the piston also slides sideways at R x its vertical speed (out while loading, "
    "back while unloading), the bed pressed and sheared at once as under the gyrating mantle; its sideways work is "
    "printed apart (the fits written are then those of the swept pressings)\n"
    "  --pool DIR1,DIR2,...: no DEM; the pourings recorded in each DIR/piston_die_pourings.txt (earlier runs of this "
    "program, the same die) fitted together as --replicates does\n  --lab CSV: a laboratory piston-die file (columns "
    "s,p_MPa[,phase]; phase load/unload or 0/1) fitted instead of the DEM test\n";

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr, "piston_die: %s\n%s", why.c_str(), kUsage);
  std::exit(2);
}

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 0; i < argc; ++i) a.command += (i ? " " : "") + std::string(argv[i]);
  try {
    core::CliArgs args(argc, argv);
    while (args.next()) {
      const std::string s = args.flag();
      if (s == "--out") a.out = args.value();
      else if (s == "--bpm") a.bpm = args.value();
      else if (s == "--lab") a.lab = args.value();
      else if (s == "--pool") {
        std::stringstream list(args.value());
        for (std::string item; std::getline(list, item, ',');) {
          if (item.empty()) usage("--pool takes run folders separated by commas, got an empty one");
          a.pool.push_back(item);
        }
      }
      else if (s == "--quick") a.quick = true;
      else if (s == "--speed-m-s") a.speed = args.number(0.01, 20, "m/s");
      else if (s == "--ratios") {
        std::stringstream list(args.value());
        for (std::string item; std::getline(list, item, ',');) {
          char* end = nullptr;
          const double x = std::strtod(item.c_str(), &end);
          if (item.empty() || *end || !(x > 0 && x <= 0.6))
            usage("--ratios takes ascending compression ratios in (0, 0.6] separated by commas, got '" + item + "'");
          a.ratios.push_back(x);
        }
      } else if (s == "--rocks") a.rocks = static_cast<int>(args.integer(1, 100000));
      else if (s == "--die-mm") a.die_mm = static_cast<double>(args.integer(50, 2000));
      else if (s == "--replicates") a.replicates = static_cast<int>(args.integer(2, 100));
      else if (s == "--reloads") a.reloads = static_cast<int>(args.integer(1, 20));
      else if (s == "--shift-mm") a.shift_mm = static_cast<double>(args.integer(1, 200));
      else if (s == "--sweep") {  // the piston's sideways / vertical speed
        a.sweep = args.number(0.0, 5.0);
        if (a.sweep == 0.0) usage("--sweep 0 is the plain die: leave --sweep out (accepted (0, 5])");
      }
      else if (s == "--threads") a.threads = static_cast<int>(args.integer(1, 256));
      else if (s == "--seed") a.seed = static_cast<unsigned long long>(args.integer(1, 1000000000));
      else if (s == "--dt-safety") {  // fraction of min(0.3 Rayleigh, bond) step
        a.dt_safety = args.number(0.0, 1.0);
        if (a.dt_safety == 0.0) usage("--dt-safety must be in (0, 1] (fraction of min(0.3 Rayleigh, bond) step), got 0");
      }
      else if (s == "-h" || s == "--help") {
        std::printf("%s", kUsage);
        std::exit(0);
      } else {
        usage("unknown argument '" + s + "' (accepted: --out, --bpm, --quick, --threads, --seed, --dt-safety, --rocks, "
              "--die-mm, --ratios, --speed-m-s, --replicates, --reloads, --shift-mm, --sweep, --lab, --pool)");
      }
    }
  } catch (const std::invalid_argument& e) {
    usage(e.what());
  }
  if (a.out.empty()) usage("--out DIR is required");
  if ((a.shift_mm > 0 || a.sweep > 0) && a.reloads == 0)
    usage("--shift-mm and --sweep are measured on the reloads (piston_die_reloads.csv): they need --reloads K");
  if (!a.lab.empty() && (a.quick || !a.bpm.empty() || a.replicates > 1 || a.reloads > 0))
    usage("--lab fits lab data: --quick, --bpm, --replicates, --reloads, --shift-mm and --sweep do not apply");
  if (!a.pool.empty() && (!a.lab.empty() || a.quick || !a.bpm.empty() || a.replicates > 1 || a.rocks > 0 ||
                          a.die_mm > 0 || !a.ratios.empty() || a.speed > 0 || a.reloads > 0))
    usage("--pool fits recorded pourings: --lab, --quick, --bpm, --replicates, --rocks, --die-mm, --ratios, "
          "--speed-m-s, --reloads, --shift-mm and --sweep do not apply");
  return a;
}

std::string f(const char* fmt, double x) {
  char b[64];
  std::snprintf(b, sizeof b, fmt, x);
  return b;
}

// The values a fit gives, by name (piston_die_fits.csv's columns after pouring,seed,loops).
std::vector<std::pair<std::string, double>> fitted_values(const chamber::MaterialFit& m) {
  const auto& x = m.material;
  const auto& b = x.breakage;
  // s_c at the smallest resolved class's lower bound: what the product below it hinges on (src/chamber/README.md);
  // NaN where no size was resolved (breakage not fitted)
  const double s_c_resolved = b.x_resolved > 0 ? b.s_c * std::pow(b.x_resolved / b.x_ref, -b.q) : std::nan("");
  return {{"loose_solid_fraction", x.loose_fraction}, {"modulus_MPa", x.modulus_Pa * 1e-6}, {"exponent", x.exponent},
          {"rms_ln_p", m.pressure_fit.rms_log},       {"rebound", x.rebound},              {"s_c", b.s_c},
          {"m", b.m},                                 {"q", b.q},                          {"phi", b.phi},
          {"gamma", b.gamma},                         {"s_c_at_resolved", s_c_resolved},   {"psd_rms_pct", m.psd_rms_pct}};
}

// Writes every pouring's own fit, the pooled one (pouring "pooled") and the jackknife's (pouring "without", seed the one
// left out); returns one line per value: pooled, mean and sample std of the pourings' own fits, min-max, and with the
// jackknife its standard error sqrt((K - 1) / K sum (x_(i) - mean)^2).
std::vector<std::string> write_pouring_fits(const std::string& file, const std::vector<chamber::PistonDieResult>& pourings,
                                            const std::vector<chamber::MaterialFit>& each,
                                            const std::vector<chamber::MaterialFit>& jack,
                                            const chamber::MaterialFit& pooled) {
  const auto pooled_values = fitted_values(pooled);
  std::vector<std::vector<std::pair<std::string, double>>> rows, jrows;
  for (const auto& e : each) rows.push_back(fitted_values(e));
  for (const auto& e : jack) jrows.push_back(fitted_values(e));
  std::ofstream csv(file);
  csv << "pouring,seed,loops";
  for (const auto& [name, v] : pooled_values) csv << "," << name;
  csv << "\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    csv << i << "," << pourings[i].seed << "," << pourings[i].loops.size();
    for (const auto& [name, v] : rows[i]) csv << "," << f("%.6g", v);
    csv << "\n";
  }
  csv << "pooled,,";
  for (const auto& [name, v] : pooled_values) csv << "," << f("%.6g", v);
  csv << "\n";
  for (std::size_t i = 0; i < jrows.size(); ++i) {
    csv << "without," << pourings[i].seed << ",";
    for (const auto& [name, v] : jrows[i]) csv << "," << f("%.6g", v);
    csv << "\n";
  }
  std::vector<std::string> lines{"pooled fit of " + std::to_string(pourings.size()) +
                                 " pourings; each value: pooled (the pourings' own fits: mean +- sample std, min-max" +
                                 (jack.empty() ? ")" : "; the pooled value's jackknife standard error)")};
  for (std::size_t k = 0; k < pooled_values.size(); ++k) {
    std::vector<double> own, loo;
    for (const auto& row : rows) own.push_back(row[k].second);
    for (const auto& row : jrows) loo.push_back(row[k].second);
    double mean = 0, var = 0, lo = own.front(), hi = lo;  // a NaN stays NaN
    for (double v : own) mean += v / own.size(), lo = std::min(lo, v), hi = std::max(hi, v);
    for (double v : own) var += std::pow(v - mean, 2) / (own.size() - 1);
    lines.push_back("  " + pooled_values[k].first + " " + f("%.4g", pooled_values[k].second) + " (" + f("%.4g", mean) +
                    " +- " + f("%.3g", std::sqrt(var)) + ", " + f("%.4g", lo) + "-" + f("%.4g", hi) +
                    (loo.empty() ? "" : "; +- " + f("%.3g", analysis::jackknife_std(loo))) + ")");
  }
  return lines;
}

int run_lab(const Args& a) {
  const auto pts = chamber::read_lab_csv(a.lab);
  const chamber::MaterialFit m = chamber::fit_flow_material_lab(pts);
  std::ofstream csv(a.out + "/piston_die.csv");
  csv << "s_max,phase,s,p_MPa\n";
  double s_max = 0;  // the deepest pressing of the lab data (the material's max_compression is the solid limit)
  for (const auto& q : pts) s_max = std::max(s_max, q.s);
  for (const auto& q : pts) csv << f("%.4f", s_max) << "," << (q.phase == 1 ? "unload" : "load") << ","
                                << q.s << "," << q.p * 1e-6 << "\n";
  chamber::write_flow_material_yaml(m, a.out + "/flow_material.yaml",
                                    {"written by: " + a.command, "source: laboratory piston-die data " + a.lab + " (" +
                                                                     std::to_string(pts.size()) + " points)"});
  std::printf("lab fit: E %.4g MPa, n %.4f, rebound %.4f, max_compression %.4f\n", m.material.modulus_Pa * 1e-6, m.material.exponent,
              m.material.rebound, m.material.max_compression);
  return 0;
}

// The DEM test: one pouring, or --replicates K of them (seeds a.seed ...).
std::vector<chamber::PistonDieResult> run_dem(const Args& a, std::string& source) {
  const std::string bpm_file = a.bpm.empty() ? core::source_file("launch_free_configs/bpm_calibrated.yaml") : a.bpm;
  if (bpm_file.empty() || !fs::exists(bpm_file))
    usage("--bpm: file '" + (bpm_file.empty() ? std::string("launch_free_configs/bpm_calibrated.yaml") : bpm_file) +
          "' not found (a bpm yaml such as launch_free_configs/bpm_calibrated.yaml)");
  const rocks::BpmModel bpm = rocks::load_bpm_model(bpm_file);
  chamber::PistonDieOptions o;
  o.threads = a.threads;
  o.seed = a.seed;
  o.verbose = true;
  o.blowup_dump_path = a.out + "/blowup_piston_die.csv";  // the run's folder
  if (a.dt_safety > 0) o.dt_safety = a.dt_safety;
  if (a.quick) {  // a small die: minutes become seconds, the numbers are not representative
    o.die_diameter = 0.10;
    o.rock_min = 0.028, o.rock_max = 0.032;
    o.rock_count = 18;
    o.piston_speed = 0.4;
  }
  if (a.speed > 0) o.piston_speed = a.speed;
  if (a.rocks > 0) o.rock_count = a.rocks;
  if (a.die_mm > 0) o.die_diameter = a.die_mm * 1e-3;
  if (!a.ratios.empty()) o.compression_ratios = a.ratios;
  o.reloads = a.reloads;
  o.reload_shift = a.shift_mm * 1e-3;
  o.sweep = a.sweep;
  std::vector<chamber::PistonDieResult> pourings;
  // Replicates: a pouring whose deeper loop blows up (a jammed bed; half the step jams it too, measured) keeps the
  // loops it completed, and one that blows up in its first loop is left out (named, its state dumped per seed), so
  // neither that pouring's completed work nor the other pourings' is lost.
  o.keep_loops_on_blowup = a.replicates > 1;
  std::vector<std::string> lost;
  for (int i = 0; i < a.replicates; ++i) {
    o.seed = a.seed + static_cast<unsigned long long>(i);
    if (a.replicates > 1) o.blowup_dump_path = a.out + "/blowup_piston_die_seed" + std::to_string(o.seed) + ".csv";
    try {
      pourings.push_back(chamber::run_piston_die(bpm, o));
    } catch (const dem::BlowUp& e) {
      if (a.replicates == 1) throw;
      lost.push_back("seed " + std::to_string(o.seed));
      std::fprintf(stderr, "piston_die: pouring %d (seed %llu) blew up before completing a loop, left out: %s\n", i,
                   o.seed, e.what());
      continue;
    }
    if (!pourings.back().blowup.empty())
      std::fprintf(stderr, "piston_die: pouring %d (seed %llu): %s\n", i, o.seed, pourings.back().blowup.c_str());
    chamber::write_pourings(pourings, a.out + "/piston_die_pourings.txt");  // each pouring kept as soon as it is done
  }
  if (pourings.empty()) throw std::runtime_error("every pouring blew up before completing a loop (see the dumps)");
  if (!lost.empty()) {
    std::string l;
    for (const auto& x : lost) l += (l.empty() ? "" : ", ") + x;
    std::fprintf(stderr, "piston_die: %zu of %d pourings kept (left out, no loop completed: %s)\n", pourings.size(),
                 a.replicates, l.c_str());
  }
  source = "virtual piston-die test (src/chamber/piston_die.cpp) on the BPM " + bpm_file + (a.quick ? " (--quick)" : "");
  return pourings;
}

// --pool: the recorded pourings of earlier runs; one die and one rock only, each seed once.
std::vector<chamber::PistonDieResult> read_pool(const Args& a, std::string& source) {
  std::vector<chamber::PistonDieResult> pourings;
  source = "pourings recorded by earlier runs, fitted together (--pool):";
  for (const auto& dir : a.pool) {
    const auto more = chamber::read_pourings(dir + "/piston_die_pourings.txt");
    source += " " + dir + " (seeds";
    for (const auto& r : more) source += " " + std::to_string(r.seed);
    source += ")";
    pourings.insert(pourings.end(), more.begin(), more.end());
  }
  try {  // a pouring pressed again later (deeper) adds its loops to its record
    pourings = chamber::merge_repressed_pourings(pourings);
  } catch (const std::invalid_argument& e) {
    usage(std::string("--pool: ") + e.what() + "; pool folders of different seeds, or the same pourings pressed to other "
          "depths");
  }
  const auto& r0 = pourings.front();
  for (std::size_t i = 0; i < pourings.size(); ++i) {
    const auto& r = pourings[i];
    if (std::abs(r.die_diameter - r0.die_diameter) > 1e-9 || std::abs(r.solid_density - r0.solid_density) > 1e-9 ||
        std::abs(r.min_resolved - r0.min_resolved) > 1e-12 || std::abs(r.rock_min - r0.rock_min) > 1e-12 ||
        std::abs(r.rock_max - r0.rock_max) > 1e-12)
      usage("--pool: pouring seed " + std::to_string(r.seed) + " is of another test (die " +
            f("%.1f", r.die_diameter * 1e3) + " mm, rocks " + f("%.1f", r.rock_min * 1e3) + "-" +
            f("%.1f", r.rock_max * 1e3) + " mm) than seed " + std::to_string(r0.seed) + "'s (die " +
            f("%.1f", r0.die_diameter * 1e3) + " mm, rocks " + f("%.1f", r0.rock_min * 1e3) + "-" +
            f("%.1f", r0.rock_max * 1e3) + " mm): only pourings of one die and rock are pooled");
  }
  return pourings;
}

// Each pressing of each bed (0: the first, from the loose pour; 1, 2, ...: reloads of the same bed) as a row:
// pouring,seed,s_max,pressing,s_start (where the piston starts: a reload starts where the last let go),s_top (where
// the bed's highest sphere is then),s_reached,peak_MPa,loop_J_kg,loading_J_kg,loop_ratio (to the first's),
// bonds_broken (in that pressing and the push before it),fragments,shift_mm (pushed down the die before it),push_MPa
// (the push's peak),sweep_J_kg (the piston's sideways work, --sweep),passing_<sieve>mm (%); printed as a table too. Their curves in `curves` (pouring,seed,s_max,pressing,phase,s,p_MPa).
void write_reloads(const std::string& file, const std::string& curves,
                   const std::vector<chamber::PistonDieResult>& pourings) {
  std::ofstream csv(file), cv(curves);
  cv << "pouring,seed,s_max,pressing,phase,s,p_MPa\n";
  const auto& sv = chamber::flow_sieves_mm();
  csv << "pouring,seed,s_max,pressing,s_start,s_top,s_reached,peak_MPa,loop_J_kg,loading_J_kg,loop_ratio,bonds_broken,"
         "fragments,shift_mm,push_MPa,sweep_J_kg";
  for (double x : sv) csv << ",passing_" << f("%g", x) << "mm";
  csv << "\n";
  std::printf("reloads: pressing, from s (bed top at s), peak MPa, loop J/kg (x the first's), loading J/kg, "
              "bonds broken, passing 22.4 / 12 mm %%, pushed mm down the die first (push's peak MPa), sideways J/kg\n");
  const std::size_t k22 = std::find(sv.begin(), sv.end(), 22.4) - sv.begin();
  const std::size_t k12 = std::find(sv.begin(), sv.end(), 12.0) - sv.begin();
  for (std::size_t i = 0; i < pourings.size(); ++i)
    for (const auto& first : pourings[i].loops) {
      std::vector<const chamber::PressLoop*> all{&first};
      for (const auto& R : first.reloads) all.push_back(&R);
      for (std::size_t k = 0; k < all.size(); ++k) {
        const auto& L = *all[k];
        const double peak = chamber::loop_peak_pressure(L);
        const double ratio = first.energy_per_kg > 0 ? L.energy_per_kg / first.energy_per_kg : 0.0;
        csv << i << "," << pourings[i].seed << "," << L.s_max << "," << k << "," << f("%.6g", L.s.front()) << ","
            << f("%.6g", L.s_top) << "," << f("%.6g", L.s_reached) << ","
            << f("%.6g", peak * 1e-6) << "," << f("%.6g", L.energy_per_kg) << "," << f("%.6g", L.loading_energy_per_kg)
            << "," << f("%.6g", ratio) << "," << L.bonds_broken << "," << L.fragments << ","
            << f("%g", L.shift * 1e3) << "," << f("%.6g", L.shift_peak_pressure * 1e-6) << ","
            << f("%.6g", L.sweep_energy_per_kg);
        for (double x : L.passing) csv << "," << f("%.4f", 100 * x);
        csv << "\n";
        for (std::size_t q = 0; q < L.s.size(); ++q)
          cv << i << "," << pourings[i].seed << "," << L.s_max << "," << k << "," << (L.phase[q] ? "unload" : "load")
             << "," << f("%.6g", L.s[q]) << "," << f("%.6g", L.p[q] * 1e-6) << "\n";
        std::printf("  seed %llu s_max %.2f pressing %zu: from %.4f (%.4f), %.3f MPa, %.2f J/kg (x %.3f), %.2f J/kg, "
                    "%zu bonds, %.2f / %.2f %%, %.0f mm (%.3f MPa), %.2f J/kg\n", pourings[i].seed, L.s_max, k,
                    L.s.front(), L.s_top, peak * 1e-6, L.energy_per_kg, ratio, L.loading_energy_per_kg, L.bonds_broken,
                    k22 < L.passing.size() ? 100 * L.passing[k22] : 0.0,
                    k12 < L.passing.size() ? 100 * L.passing[k12] : 0.0, L.shift * 1e3,
                    L.shift_peak_pressure * 1e-6, L.sweep_energy_per_kg);
      }
    }
}

// The pooled fit of the pourings and every output file.
int fit_and_write(const Args& a, const std::vector<chamber::PistonDieResult>& pourings, const std::string& source) {
  const chamber::PistonDieResult& r = pourings.front();
  if (a.reloads > 0)  // first: measured, not fitted, so a fit that fails does not lose them
    write_reloads(a.out + "/piston_die_reloads.csv", a.out + "/piston_die_reload_curves.csv", pourings);
  chamber::MaterialFit m = chamber::fit_flow_material(pourings);  // pooled over the pourings
  std::string scatter;
  std::vector<std::string> spread;
  if (pourings.size() > 1) {
    std::vector<chamber::MaterialFit> each, jack;
    for (const auto& q : pourings) each.push_back(chamber::fit_flow_material(q));
    if (pourings.size() >= 3) jack = chamber::leave_one_out_fits(pourings);
    spread = write_pouring_fits(a.out + "/piston_die_fits.csv", pourings, each, jack, m);
    m.material.lump_std = chamber::lump_std_of_pourings(pourings);
    double s_common = 0.0;
    const auto peaks = chamber::common_depth_peaks(pourings, &s_common);
    scatter = "scatter: " + std::to_string(pourings.size()) + " pourings (seeds";
    for (const auto& q : pourings) scatter += " " + std::to_string(q.seed);
    scatter += "), peaks at s_max " + f("%.2f", s_common) + " (the deepest all completed)";
    for (double p : peaks) scatter += " " + f("%.4f", p * 1e-6);
    scatter += " MPa, N_eff of the first " + f("%.2f", chamber::die_effective_lumps(r)) + ": lump_std " + f("%.4f", m.material.lump_std);
    for (std::size_t i = 0; i < pourings.size(); ++i)
      if (!pourings[i].blowup.empty())
        scatter += "; pouring " + std::to_string(i) + " " + pourings[i].blowup.substr(0, pourings[i].blowup.find(':')) +
                   ", its completed loops kept";
    // The jackknife's materials: jackknife/ for the power law, jackknife/solid_divergence/ for the other
    // (validate --rock-spread takes the folder of its config's law).
    for (const auto law : {chamber::PressureLaw::power, chamber::PressureLaw::solid_divergence}) {
      if (jack.empty()) break;
      const bool div = law == chamber::PressureLaw::solid_divergence;
      if (div) jack = chamber::leave_one_out_fits(pourings, law);
      const std::string dir = a.out + "/jackknife" + (div ? "/solid_divergence" : "");
      const std::string pooled = a.out + (div ? "/flow_material_solid_divergence.yaml" : "/flow_material.yaml");
      fs::create_directories(dir);
      for (std::size_t i = 0; i < jack.size(); ++i) {
        auto J = jack[i];
        J.material.lump_std = m.material.lump_std;  // the scatter is the whole sample's, not refitted
        chamber::write_flow_material_yaml(
            J, dir + "/flow_material_without_seed" + std::to_string(pourings[i].seed) + ".yaml",
            {"written by: " + a.command, "the jackknife of " + pooled + ": the pooled fit of its " +
                                             std::to_string(pourings.size()) + " pourings without seed " +
                                             std::to_string(pourings[i].seed)});
      }
    }
  }

  std::ofstream csv(a.out + "/piston_die.csv");
  csv << "s_max,phase,s,p_MPa\n";
  for (const auto& L : r.loops)
    for (std::size_t k = 0; k < L.s.size(); ++k)
      csv << L.s_max << "," << (L.phase[k] ? "unload" : "load") << "," << f("%.6g", L.s[k]) << ","
          << f("%.6g", L.p[k] * 1e-6) << "\n";
  if (pourings.size() > 1) {  // every pouring's curves, for the scatter's record
    std::ofstream all(a.out + "/piston_die_pourings.csv");
    all << "pouring,seed,loose_solid_fraction,s_max,phase,s,p_MPa\n";
    for (std::size_t i = 0; i < pourings.size(); ++i)
      for (const auto& L : pourings[i].loops)
        for (std::size_t k = 0; k < L.s.size(); ++k)
          all << i << "," << pourings[i].seed << "," << f("%.6g", pourings[i].loose_solid_fraction) << "," << L.s_max
              << "," << (L.phase[k] ? "unload" : "load") << "," << f("%.6g", L.s[k]) << "," << f("%.6g", L.p[k] * 1e-6)
              << "\n";
  }
  if (!a.pool.empty()) chamber::write_pourings(pourings, a.out + "/piston_die_pourings.txt");  // the pool, for a later one
  const auto& sv = chamber::flow_sieves_mm();
  std::ofstream psd(a.out + "/psd.csv"), fit(a.out + "/psd_fit.csv");
  psd << "s_max,sieve_mm,passing_pct\n";
  fit << "s_max,sieve_mm,passing_pct\n";
  for (std::size_t k = 0; k < sv.size(); ++k) psd << "feed," << sv[k] << "," << f("%.4f", 100 * r.feed_passing[k]) << "\n";
  std::vector<double> sieves;
  for (double mm : sv) sieves.push_back(mm * 1e-3);
  for (const auto& L : r.loops) {
    const auto pred = chamber::breakage_event(r.feed_passing, sieves, L.s_reached, m.material.breakage);
    for (std::size_t k = 0; k < sv.size(); ++k) {
      psd << L.s_max << "," << sv[k] << "," << f("%.4f", 100 * L.passing[k]) << "\n";
      fit << L.s_max << "," << sv[k] << "," << f("%.4f", 100 * pred[k]) << "\n";
    }
  }
  std::vector<std::string> prov{
      "written by: " + a.command, source,
      std::to_string(r.rocks) + " rocks " + f("%.1f", r.rock_min * 1e3) + "-" + f("%.1f", r.rock_max * 1e3) +
          " mm, " + std::to_string(r.particles) + " particles, " + std::to_string(r.bonds) + " bonds, rock mass " +
          f("%.4f", r.rock_mass) + " kg",
      "die " + f("%.1f", r.die_diameter * 1e3) + " mm diameter, loose bed height " + f("%.2f", r.bed_height * 1e3) +
          " mm, piston " + f("%.3g", r.piston_speed) + " m/s, dt " + f("%.3g", r.dt) + " s, settled " +
          f("%.3f", r.settle_time) + " s, wall " + f("%.0f", r.wall_s) + " s"};
  for (const auto& L : r.loops)
    prov.push_back("s_max " + f("%.2f", L.s_max) + ": reached " + f("%.4f", L.s_reached) + ", peak " +
                   f("%.3f", chamber::loop_peak_pressure(L) * 1e-6) + " MPa, absorbed " +
                   f("%.2f", L.energy_per_kg) + " J/kg of " + f("%.2f", L.loading_energy_per_kg) +
                   " J/kg loading work, " + std::to_string(L.bonds_broken) + " bonds broken, " +
                   std::to_string(L.fragments) + " fragments, mass error " + f("%.1e", L.mass_error));
  if (!scatter.empty()) prov.push_back(scatter);
  prov.insert(prov.end(), spread.begin(), spread.end());
  chamber::write_flow_material_yaml(m, a.out + "/flow_material.yaml", prov);
  // The same rock with the law that diverges at the solid's density (src/chamber/bed_compaction.hpp), beside it.
  chamber::MaterialFit d = chamber::fit_flow_material(pourings, chamber::PressureLaw::solid_divergence);
  d.material.lump_std = m.material.lump_std;
  chamber::write_flow_material_yaml(d, a.out + "/flow_material_solid_divergence.yaml", prov);
  for (const auto& l : prov) std::printf("%s\n", l.c_str());
  std::printf("loose_solid_fraction %.4f; p = %.4g MPa s^%.4f (rms ln %.3f), rebound %.4f, max_compression %.4f\n",
              m.material.loose_fraction, m.material.modulus_Pa * 1e-6, m.material.exponent, m.pressure_fit.rms_log, m.material.rebound,
              m.material.max_compression);
  std::printf("solid_divergence (flow_material_solid_divergence.yaml): p = %.4g MPa u^%.4f, u = s / (1 - s / %.4f) (rms ln "
              "%.3f), rebound %.4f, max_compression %.4f\n",
              d.material.modulus_Pa * 1e-6, d.material.exponent, chamber::solid_compaction_limit(d.material.loose_fraction),
              d.pressure_fit.rms_log, d.material.rebound, d.material.max_compression);
  std::printf("breakage: s_c %.4f m %.4f q %.4f phi %.4f gamma %.4f beta %.4f (%s; rms %.2f %%)\n", m.material.breakage.s_c,
              m.material.breakage.m, m.material.breakage.q, m.material.breakage.phi, m.material.breakage.gamma, m.material.breakage.beta,
              m.breakage_note.c_str(), m.psd_rms_pct);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  core::prefer_passive_openmp_wait(argv);  // the DEM's threads sleep while they wait (a shared machine)
  const Args a = parse(argc, argv);
  try {
    fs::create_directories(a.out);
    int rc = 0;
    if (!a.lab.empty()) {
      rc = run_lab(a);
    } else {
      std::string source;
      const auto pourings = a.pool.empty() ? run_dem(a, source) : read_pool(a, source);
      rc = fit_and_write(a, pourings, source);
    }
    core::run_plot_script("piston_die", "plot_piston_die.py", a.out);
    return rc;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "piston_die: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "piston_die: error: %s\n", e.what());
    return 1;
  }
}
