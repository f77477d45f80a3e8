// Real-time factor of the MBD-only run (equivalent bed load by default), one core:
//   mbd_bench --config launch_free_configs/gyp1200_400rpm.yaml --seconds 10 [--load bed|none]
// Prints the simulated time, wall time, real-time factor and a Table-5-style summary (test-point
// amplitude in x = half the peak-to-peak per drive cycle, mean and std over cycles; mean power).
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

#include "core/cli_args.hpp"
#include "core/config.hpp"
#include "mbd/mechanism.hpp"
#include "mbd/mechanism_params.hpp"
#include "mbd/simulate.hpp"

namespace {
void usage() {
  std::cerr << "usage: mbd_bench --config FILE [--seconds S] [--settle S] [--load bed|none] [--speed-rpm N] [--csv OUT.csv] [--diag]\n"
               "       calibration overrides: [--static-moment KG_M] [--bed-modulus-MPa E] [--bed-viscosity-kPa-s C]\n"
               "       [--bed-hysteretic REBOUND] (rate-independent bed law with that rebound, no viscosity)\n";
}
}  // namespace

int main(int argc, char** argv) {
  std::string config, load = "bed";
  double seconds = 10.0, settle = 4.0, rpm = -1;
  double static_moment = -1, viscosity = -1, modulus = -1, rebound = -1;
  bool diag = false;
  std::string csv;
  try {
    core::CliArgs args(argc, argv);  // each number checked: the flag, the value and the range it accepts
    while (args.next()) {
      const std::string a = args.flag();
      if (a == "--config") config = args.value();
      else if (a == "--seconds") seconds = args.number(0.01, 1e5, "s");
      else if (a == "--settle") settle = args.number(0, 1e5, "s");
      else if (a == "--load") load = args.value();
      else if (a == "--speed-rpm") rpm = args.number(1, 5000, "rpm");
      else if (a == "--static-moment") static_moment = args.number(0, 1e5, "kg m");
      else if (a == "--bed-viscosity-kPa-s") viscosity = args.number(0, 1e9, "kPa s");
      else if (a == "--bed-modulus-MPa") modulus = args.number(1e-6, 1e9, "MPa");
      else if (a == "--bed-hysteretic") rebound = args.number(0.01, 1, "(rebound)");
      else if (a == "--diag") diag = true;
      else if (a == "--csv") csv = args.value();
      else {
        usage();
        return 2;
      }
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "mbd_bench: " << e.what() << "\n";
    return 2;
  }
  if (config.empty()) {
    usage();
    return 2;
  }
  try {
    auto params = mbd::load_mechanism_params_file(config);
    if (rpm > 0) params.drive_speed_rad_s = rpm * 2.0 * M_PI / 60.0;
    if (static_moment >= 0) params.vibrator_static_moment_kg_m = static_moment;
    if (viscosity >= 0) params.bed.viscosity_Pa_s = viscosity * 1e3;
    if (modulus >= 0) params.bed.modulus_Pa = modulus * 1e6;
    if (rebound >= 0) {
      params.bed.law = mbd::BedLaw::Hysteretic;
      params.bed.rebound = rebound;
      params.bed.viscosity_Pa_s = 0;
    }
    mbd::validate(params);
    if (diag) {  // state of the mechanism every 0.5 s (calibration aid)
      mbd::Mechanism m(params, load == "none" ? mbd::LoadModel::None : mbd::LoadModel::Bed);
      for (int k = 1; k * 0.5 <= seconds + settle + 1e-9; ++k) {
        m.advance(0.5);
        const auto tp = m.test_point();
        const auto d = m.drive();
        const auto e = m.energy();
        std::printf("t %.1f nut_deg %.3f gap_mm %.2f bed_kN %.1f contact_kN %.1f spin %.3f cerr %.2e tp_mm [%.2f %.2f %.2f] P_kW %.1f "
                    "W %.0f D %.0f E %.0f\n",
                    m.time(), m.nutation_angle() * 180 / M_PI, m.min_gap() * 1e3, m.bed_force() / 1e3,
                    m.contact_force() / 1e3, m.mantle_spin(), m.constraint_error(), tp.displacement.x() * 1e3,
                    tp.displacement.y() * 1e3, tp.displacement.z() * 1e3, d.power / 1e3, e.drive_work,
                    e.dissipation(), e.mechanical_energy());
      }
      return 0;
    }
    mbd::SimOptions o;
    o.duration_s = seconds;
    o.settle_s = settle;
    o.load = load;
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    const auto rec = mbd::simulate(params, o);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
    const double sim = seconds + settle;
    if (!csv.empty()) {  // recording in the plant-CSV layout of DESIGN.md
      std::ofstream f(csv);
      f << "t_s,x_m,y_m,z_m,power_W,speed_rad_s\n";
      f.precision(9);
      for (std::size_t k = 0; k < rec.t_s.size(); ++k)
        f << rec.t_s[k] << ',' << rec.x_m[k] << ',' << rec.y_m[k] << ',' << rec.z_m[k] << ',' << rec.power_W[k] << ','
          << rec.speed_rad_s[k] << '\n';
      if (!f) throw std::runtime_error("cannot write " + csv);
    }
    // Amplitude per drive cycle (half peak-to-peak of x, mbd::cycle_amplitudes), power mean.
    const double period = 2.0 * M_PI / params.drive_speed_rad_s;
    const std::vector<double> amps = mbd::cycle_amplitudes(rec.t_s, rec.x_m, period);
    double am = 0, as = 0, pm = 0, ps = 0, wm = 0;
    for (double a : amps) am += a;
    am /= amps.size();
    for (double a : amps) as += (a - am) * (a - am);
    as = std::sqrt(as / std::max<std::size_t>(1, amps.size() - 1));
    for (double p : rec.power_W) pm += p;
    pm /= rec.power_W.size();
    for (double p : rec.power_W) ps += (p - pm) * (p - pm);
    ps = std::sqrt(ps / rec.power_W.size());
    for (double w : rec.speed_rad_s) wm += w;
    wm /= rec.speed_rad_s.size();
    std::printf("mbd_bench config %s load %s speed_rpm %.1f\n", config.c_str(), load.c_str(),
                params.drive_speed_rad_s * 60.0 / (2.0 * M_PI));
    std::string element;
    const double bound = mbd::stable_step_bound(params, &element);
    std::printf("time_step_s %g stable_step_bound_s %g (%s)\n", params.dt_s, bound, element.c_str());
    std::printf("simulated_s %.3f wall_s %.3f real_time_factor %.1f cpu_s %.3f cpu_real_time_factor %.1f steps %ld\n",
                sim, wall, sim / wall, cpu, sim / cpu, std::lround(sim / params.dt_s));
    std::printf("amplitude_x_mm mean %.3f std %.3f (half peak-to-peak per cycle, %zu cycles)\n", am * 1e3,
                as * 1e3, amps.size());
    std::printf("power_kW mean %.2f std %.2f  mean_speed_rpm %.2f\n", pm / 1e3, ps / 1e3, wm * 60 / (2 * M_PI));
  } catch (const std::exception& e) {
    std::cerr << "mbd_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
