// calibrate: Taguchi calibration of the bonded-particle model on the Brazilian test (paper section 2.4).
//   calibrate --out DIR [--config launch_free_configs/calibration.yaml] [--confirm-only]
//             [--bpm launch_free_configs/bpm_calibrated.yaml] [--threads N]
// Full run: packs the disk, runs the 16 L16 runs (Table 2 factors), ANOVA of F_cd (Eq. 27) and the critical
// compression ratio, marginal means (CSV + PNG), the Taguchi optimum, a confirmation run refined until the
// critical force is within the tolerance, single-particle compression of the four rock shapes, and
// DIR/bpm_calibrated.yaml for the crusher. --confirm-only: one Brazilian run with the stored model ->
// DIR/confirmation.json (critical_force_kN, tensile_strength_MPa, critical_compression_ratio, wall_s).
// A run that blows up leaves its DEM state in DIR/blowup_<run>.csv (doe_run_<n>, confirmation_<n>,
// single_particle_<n>, confirmation) and the error names the run and the file.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/openmp_wait.hpp"
#include "core/run_program.hpp"
#include "core/units.hpp"
#include "rocks/calibration.hpp"
#include "rocks/rock_file.hpp"
#include "rocks/shape.hpp"

namespace fs = std::filesystem;
using namespace rocks;
using core::units::kPi;

namespace {

struct Args {
  std::string out, config = "launch_free_configs/calibration.yaml", bpm = "launch_free_configs/bpm_calibrated.yaml";
  bool confirm_only = false;
  int threads = 2;
};

[[noreturn]] void usage(const std::string& why) {
  std::fprintf(stderr,
               "calibrate: %s\nusage: calibrate --out DIR [--config FILE] [--confirm-only] [--bpm FILE] [--threads N]\n",
               why.c_str());
  std::exit(2);
}

Args parse(int argc, char** argv) {
  Args a;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage("option " + s + " needs a value");
      return argv[++i];
    };
    if (s == "--out") a.out = value();
    else if (s == "--config") a.config = value();
    else if (s == "--bpm") a.bpm = value();
    else if (s == "--confirm-only") a.confirm_only = true;
    else if (s == "--threads") {
      const std::string v = value();
      char* end = nullptr;
      const long n = std::strtol(v.c_str(), &end, 10);
      if (*end || n < 1 || n > 256) usage("--threads must be an integer in [1, 256], got '" + v + "'");
      a.threads = static_cast<int>(n);
    } else if (s == "-h" || s == "--help") usage("help");
    else usage("unknown argument '" + s + "'");
  }
  if (a.out.empty()) usage("--out DIR is required");
  return a;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string json_num(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s.precision(8);
  s << v;
  return s.str();
}

RockPacking pack_disk(const CalibrationConfig& c, const BpmModel& m) {
  CylinderShape disk(c.diameter, c.length);
  return pack_shape(disk, m.metaparticles, m.packing);
}

void write_confirmation(const std::string& file, const PlatenTestResult& r, const CalibrationConfig& c, double wall) {
  std::ofstream o(file);
  o << "{\n  \"critical_force_kN\": " << json_num(r.peak_force * 1e-3)
    << ",\n  \"tensile_strength_MPa\": " << json_num(brazilian_tensile_strength(r.peak_force, c.diameter, c.length) * 1e-6)
    << ",\n  \"critical_compression_ratio\": " << json_num(r.critical_compression_ratio)
    << ",\n  \"target_force_kN\": " << json_num(c.target_force * 1e-3)
    << ",\n  \"force_error\": " << json_num(r.peak_force / c.target_force - 1.0)
    << ",\n  \"bonds_broken\": " << r.bonds_broken << ",\n  \"tensile_breaks\": " << r.tensile_breaks
    << ",\n  \"shear_breaks\": " << r.shear_breaks << ",\n  \"stopped_after_drop\": " << (r.broke ? "true" : "false")
    << ",\n  \"dt_s\": " << json_num(r.dt) << ",\n  \"steps\": " << r.steps
    << ",\n  \"wall_s\": " << json_num(wall) << "\n}\n";
  if (!o) throw std::runtime_error("cannot write " + file);
}

// One platen test of the calibration, named for its messages and files: a blow-up's state dump goes to
// OUT/blowup_<name>.csv (the run's own folder, never a fixed name in the temporary folder), and any failure
// names the run.
PlatenTestResult platen_test(const RockPacking& rock, const dem::BondParams& bp, PlatenTestOptions o,
                             const std::string& out, const std::string& name) {
  o.blowup_dump_path = out + "/blowup_" + name + ".csv";
  try {
    return run_platen_test(rock, bp, o);
  } catch (const std::exception& e) {
    throw std::runtime_error(name + ": " + e.what());
  }
}

PlatenTestOptions test_options(const CalibrationConfig& c) {
  PlatenTestOptions o = c.test;
  o.threads = 1;  // parallelism is over runs
  return o;
}

int confirm_only(const Args& a) {
  const auto t0 = std::chrono::steady_clock::now();
  const CalibrationConfig c = CalibrationConfig::load(a.config);
  const BpmModel m = load_bpm_model(a.bpm);
  std::fprintf(stderr, "calibrate --confirm-only: %s, bond %s\n", a.bpm.c_str(), bpm_model_yaml(m, 0).c_str());
  const RockPacking disk = pack_disk(c, m);
  PlatenTestOptions o = test_options(c);
  o.verbose = true;
  const PlatenTestResult r = platen_test(disk, m.bond.params(), o, a.out, "confirmation");
  write_force_curve_csv(r, a.out + "/confirmation_curve.csv");
  write_confirmation(a.out + "/confirmation.json", r, c, seconds_since(t0));
  std::printf("confirmation: critical force %.3f kN (target %.1f kN, %+.1f %%), tensile strength %.3f MPa, "
              "critical compression ratio %.4f, wall %.1f s\n",
              r.peak_force * 1e-3, c.target_force * 1e-3, 100.0 * (r.peak_force / c.target_force - 1.0),
              brazilian_tensile_strength(r.peak_force, c.diameter, c.length) * 1e-6, r.critical_compression_ratio,
              seconds_since(t0));
  return 0;
}

int full(const Args& a) {
  const auto t0 = std::chrono::steady_clock::now();
  const CalibrationConfig c = CalibrationConfig::load(a.config);
  fs::create_directories(fs::path(a.out) / "curves");
  const RockPacking disk = pack_disk(c, c.base);
  save_rock(disk, a.out + "/specimen_disk.rock");
  write_stl(CylinderShape(c.diameter, c.length).mesh(), a.out + "/specimen_disk.stl", "brazilian_disk");
  std::fprintf(stderr, "calibrate: disk %.0f x %.0f mm, %zu metaparticles (%s), density %.3f, %zu bonds; "
               "16 runs on %d threads\n",
               c.diameter * 1e3, c.length * 1e3, disk.size(), disk.distribution.c_str(), disk.density(),
               disk.bonds.size(), a.threads);
  const PlatenTestOptions opt = test_options(c);

  // ---- the L16 DOE
  std::vector<DoeRun> runs(16);
  int finished = 0;
  const auto t_doe = std::chrono::steady_clock::now();
  run_parallel(
      16, a.threads,
      [&](int i) {
        runs[i].row = i;
        runs[i].bond = doe_settings(c, i);
        runs[i].result = platen_test(disk, runs[i].bond.params(), opt, a.out, "doe_run_" + std::to_string(i + 1));
      },
      [&](int i) {
        ++finished;
        const double el = seconds_since(t_doe);
        std::fprintf(stderr, "run %d/16 (L16 row %d): F_c %.3f kN, ccr %.3f %%, %zu bonds broken; elapsed %.0f s, ETA %.0f s\n",
                     finished, i + 1, runs[i].force_kN(), runs[i].ccr_pct(), runs[i].result.bonds_broken, el,
                     el / finished * (16 - finished));
      });
  const double doe_wall = seconds_since(t_doe);

  const auto& L = l16_array();
  std::vector<double> fcs(16), fcd(16), ccr(16);
  {
    std::ofstream o(a.out + "/doe_runs.csv");
    o << "run,normal_strength_MPa,shear_strength_MPa,error_level,shear_stiffness_GPa_per_m,bond_disk_radius_mm,"
         "critical_force_kN,force_difference_kN,critical_compression_ratio_pct,tensile_strength_MPa,bonds_broken,"
         "tensile_breaks,shear_breaks,split,dt_s,wall_s\n";
    for (int i = 0; i < 16; ++i) {
      const auto& r = runs[i].result;
      fcs[i] = runs[i].force_kN();
      fcd[i] = std::abs(fcs[i] - c.target_force * 1e-3);  // Eq. 27
      ccr[i] = runs[i].ccr_pct();
      o << i + 1 << "," << runs[i].bond.sigma_c * 1e-6 << "," << runs[i].bond.tau_c * 1e-6 << "," << L[i][2] << ","
        << runs[i].bond.kt * 1e-9 << "," << runs[i].bond.disk_radius * 1e3 << "," << fcs[i] << "," << fcd[i] << ","
        << ccr[i] << "," << brazilian_tensile_strength(r.peak_force, c.diameter, c.length) * 1e-6 << ","
        << r.bonds_broken << "," << r.tensile_breaks << "," << r.shear_breaks << "," << (r.broke ? 1 : 0) << ","
        << r.dt << "," << r.wall_s << "\n";
      write_force_curve_csv(r, a.out + "/curves/doe_run_" + std::to_string(i + 1) + ".csv");
    }
  }
  const std::vector<std::string> names{"Normal critical stress", "Shear critical stress", "Error",
                                       "Shear stiffness", "Bond disk radius"};
  const AnovaTable an_f = anova(L, fcd, names, {2}, 4);
  const AnovaTable an_c = anova(L, ccr, names, {2}, 4);
  {
    std::ofstream o(a.out + "/anova.txt");
    o << format_anova(an_f, "force difference F_cd (kN), Eq. 27") << "\n"
      << format_anova(an_c, "critical compression ratio (%)");
    std::ofstream csv(a.out + "/anova.csv");
    csv << "response,source,df,ss,ms,F,p\n";
    for (const auto* t : {&an_f, &an_c}) {
      const std::string resp = t == &an_f ? "force_difference_kN" : "critical_compression_ratio_pct";
      for (const auto& r : t->factors)
        csv << resp << "," << r.source << "," << r.df << "," << r.ss << "," << r.ms << "," << r.F << "," << r.p << "\n";
      csv << resp << ",Error," << t->error.df << "," << t->error.ss << "," << t->error.ms << ",,\n";
      csv << resp << ",Total," << t->total.df << "," << t->total.ss << ",,,\n";
    }
  }
  std::cerr << format_anova(an_f, "force difference F_cd (kN)") << format_anova(an_c, "critical compression ratio (%)");
  const auto mm_f = marginal_means(L, fcd, 4);
  const auto mm_c = marginal_means(L, ccr, 4);
  {
    const std::vector<const std::vector<double>*> lv{&c.normal_strength, &c.shear_strength, nullptr,
                                                     &c.shear_stiffness, &c.disk_radius};
    const double unit[5] = {1e-6, 1e-6, 1.0, 1e-9, 1e3};
    std::ofstream o(a.out + "/marginal_means.csv");
    o << "response,factor,level,value,mean\n";
    for (int col = 0; col < 5; ++col)
      for (int l = 0; l < 4; ++l) {
        const double v = lv[col] ? (*lv[col])[l] * unit[col] : l + 1;
        o << "force_difference_kN," << names[col] << "," << l + 1 << "," << v << "," << mm_f[col][l] << "\n";
        o << "critical_compression_ratio_pct," << names[col] << "," << l + 1 << "," << v << "," << mm_c[col][l] << "\n";
      }
  }

  // ---- Taguchi optimum (smallest marginal mean of F_cd per factor), then refine strengths to the target
  const std::vector<int> best = taguchi_optimum(mm_f);
  BondSettings opt_bond = c.base.bond;
  opt_bond.sigma_c = c.normal_strength[best[0] - 1];
  opt_bond.tau_c = c.shear_strength[best[1] - 1];
  opt_bond.kt = c.shear_stiffness[best[3] - 1];
  opt_bond.kn = c.stiffness_ratio * opt_bond.kt;
  opt_bond.disk_radius = c.disk_radius[best[4] - 1];
  std::fprintf(stderr, "Taguchi optimum: normal %.1f MPa, shear %.1f MPa, k_bt %.0f GPa/m, disk %.2f mm\n",
               opt_bond.sigma_c * 1e-6, opt_bond.tau_c * 1e-6, opt_bond.kt * 1e-9, opt_bond.disk_radius * 1e3);
  struct Step {
    BondSettings bond;
    double scale;
    PlatenTestResult r;
  };
  std::vector<Step> steps;
  BondSettings cur = opt_bond;
  double scale = 1.0;
  for (int it = 0; it <= c.max_refinements; ++it) {
    // one thread: OpenMP barriers on an oversubscribed 2-core machine cost more than they gain
    const PlatenTestResult r = platen_test(disk, cur.params(), opt, a.out, "confirmation_" + std::to_string(it));
    steps.push_back({cur, scale, r});
    write_force_curve_csv(r, a.out + "/curves/confirmation_" + std::to_string(it) + ".csv");
    const double err = r.peak_force / c.target_force - 1.0;
    std::fprintf(stderr, "confirmation %d: strength scale %.4f -> F_c %.3f kN (%+.1f %%), ccr %.3f %%\n", it, scale,
                 r.peak_force * 1e-3, 100 * err, r.critical_compression_ratio * 100);
    if (std::abs(err) <= c.tolerance || !(r.peak_force > 0.0)) break;
    // the critical force scales nearly linearly with both bond strengths: scale them together
    double s = c.target_force / r.peak_force;
    if (steps.size() >= 2) {  // secant in log space on the last two points
      const auto& p = steps[steps.size() - 2];
      const double dl = std::log(r.peak_force / p.r.peak_force), ds = std::log(scale / p.scale);
      if (std::abs(dl) > 1e-6 && std::abs(ds) > 1e-9) {
        const double slope = std::max(0.3, std::min(2.0, dl / ds));
        s = std::exp(std::log(c.target_force / r.peak_force) / slope);
      }
    }
    scale *= s;
    cur.sigma_c = opt_bond.sigma_c * scale;
    cur.tau_c = opt_bond.tau_c * scale;
  }
  const Step& fin = steps.back();
  const double fin_err = fin.r.peak_force / c.target_force - 1.0;
  BpmModel model = c.base;
  model.bond = fin.bond;
  write_confirmation(a.out + "/confirmation.json", fin.r, c, fin.r.wall_s);
  write_force_curve_csv(fin.r, a.out + "/confirmation_curve.csv");

  // ---- single-particle compression of the four rock shapes with the calibrated model
  std::vector<PlatenTestResult> rock_res;
  std::vector<std::size_t> rock_n;
  std::vector<double> rock_density(4, 0.0);
  if (c.single_particle) {
    rock_res.resize(4);
    rock_n.resize(4);
    run_parallel(
        4, a.threads,
        [&](int k) {
          const std::string name = "single_particle_" + std::to_string(k + 1);
          const SingleParticleRock rock = single_particle_rock(c, model, k);
          const RockPacking& rk = rock.packing;
          save_rock(rk, a.out + "/rock" + std::to_string(k + 1) + ".rock");
          write_stl(rock.shape->mesh(), a.out + "/rock" + std::to_string(k + 1) + ".stl", rock.shape->name());
          PlatenTestOptions o = single_particle_options(c);
          o.threads = 1;
          rock_n[k] = rk.size();
          rock_density[k] = rk.density();
          rock_res[k] = platen_test(rk, model.bond.params(), o, a.out, name);
          write_force_curve_csv(rock_res[k], a.out + "/curves/" + name + ".csv");
        },
        [&](int k) {
          std::fprintf(stderr, "single particle %d (%.0f mm, %zu metaparticles, density %.2f): F_c %.3f kN, ccr %.3f %%\n", k + 1,
                       c.rock_sizes[k] * 1e3, rock_n[k], rock_density[k], rock_res[k].peak_force * 1e-3,
                       rock_res[k].critical_compression_ratio * 100);
        });
  }

  // ---- outputs for the crusher and for people
  {
    std::ofstream o(a.out + "/bpm_calibrated.yaml");
    char buf[512];
    o << "# Calibrated bonded-particle model, written by `calibrate` (src/tools/calibrate.cpp) from " << a.config << ".\n";
    o << "# Valid for the metaparticle sizes below only (coarse-graining: recalibrate when they change).\n";
    std::snprintf(buf, sizeof buf,
                  "# Taguchi optimum levels (Table 2 order): normal %d, shear %d, stiffness %d, disk %d; strengths then "
                  "scaled by %.4f.\n# Confirmation (Brazilian %.0f x %.0f mm): F_c = %.3f kN (target %.2f kN, %+.2f %%), "
                  "sigma_t = %.3f MPa (Eq. 26), critical compression ratio %.4f.\n",
                  best[0], best[1], best[3], best[4], fin.scale, c.diameter * 1e3, c.length * 1e3,
                  fin.r.peak_force * 1e-3, c.target_force * 1e-3, 100 * fin_err,
                  brazilian_tensile_strength(fin.r.peak_force, c.diameter, c.length) * 1e-6,
                  fin.r.critical_compression_ratio);
    o << buf << "bpm:\n" << bpm_model_yaml(model, 2);
  }
  {
    std::ofstream o(a.out + "/calibration_summary.json");
    o << "{\n  \"doe_wall_s\": " << json_num(doe_wall) << ",\n  \"threads\": " << a.threads
      << ",\n  \"particles\": " << disk.size() << ",\n  \"bonds\": " << disk.bonds.size()
      << ",\n  \"dt_s\": " << json_num(runs[0].result.dt)
      << ",\n  \"closing_speed_m_s\": " << json_num(opt.closing_speed) << ",\n  \"runs\": [";
    for (int i = 0; i < 16; ++i)
      o << (i ? ", " : "") << "{\"critical_force_kN\": " << json_num(fcs[i]) << ", \"F_cd_kN\": " << json_num(fcd[i])
        << ", \"ccr_pct\": " << json_num(ccr[i]) << "}";
    o << "],\n  \"optimum_levels\": [" << best[0] << ", " << best[1] << ", " << best[3] << ", " << best[4] << "]"
      << ",\n  \"strength_scale\": " << json_num(fin.scale) << ",\n  \"confirmation_runs\": " << steps.size()
      << ",\n  \"critical_force_kN\": " << json_num(fin.r.peak_force * 1e-3) << ",\n  \"force_error\": " << json_num(fin_err)
      << ",\n  \"single_particle_critical_force_kN\": [";
    for (std::size_t k = 0; k < rock_res.size(); ++k) o << (k ? ", " : "") << json_num(rock_res[k].peak_force * 1e-3);
    o << "],\n  \"single_particle_ccr\": [";
    for (std::size_t k = 0; k < rock_res.size(); ++k) o << (k ? ", " : "") << json_num(rock_res[k].critical_compression_ratio);
    o << "],\n  \"total_wall_s\": " << json_num(seconds_since(t0)) << "\n}\n";
  }
  core::run_plot_script("calibrate", "plot_calibration.py", a.out);
  std::printf("DOE: 16 runs in %.1f s on %d threads; optimum F_c %.3f kN (%+.1f %% of %.1f kN) after %zu confirmation "
              "run(s); outputs in %s\n",
              doe_wall, a.threads, fin.r.peak_force * 1e-3, 100 * fin_err, c.target_force * 1e-3, steps.size(),
              a.out.c_str());
  return std::abs(fin_err) <= c.tolerance ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  core::prefer_passive_openmp_wait(argv);  // the DEM's threads sleep while they wait (a shared machine)
  const Args a = parse(argc, argv);
  try {
    fs::create_directories(a.out);
    return a.confirm_only ? confirm_only(a) : full(a);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "calibrate: %s\n", e.what());
    return 1;
  }
}
