// The fast mode without ROS: the mechanism under the chamber flow model (run.load flow), its Table 5 figures and
// real-time factor on one core.
//   flow_bench --config launch_free_configs/gyp1200_400rpm.yaml [--seconds S] [--settle S] [--speed-rpm N]
//              [--static-moment KG_M] [--modulus-MPa E] [--exponent N] [--rebound R] [--bands B] [--sectors S]
//              [--exact] (the figures to 17 digits: a speed-up that keeps the results bit for bit shows it here)
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "analysis/flow_run.hpp"
#include "chamber/flow_config.hpp"
#include "core/cli_args.hpp"
#include "core/run_config.hpp"

namespace {
void usage() {
  std::cerr << "usage: flow_bench --config FILE [--seconds S] [--settle S] [--speed-rpm N] [--static-moment KG_M]\n"
               "                  [--modulus-MPa E] [--exponent N] [--rebound R] [--loose F] [--bands B] [--sectors S]\n"
               "                  [--profile] (per height band at the end: gap, mass, fill, nipped share)\n"
               "                  [--trace] (every 0.5 s on stderr: charge, feed and product rates, nutation, power)\n"
               "                  [--exact] (the figures and the product PSD to 17 digits, wall time left out)\n";
}
}  // namespace

int main(int argc, char** argv) {
  std::string config;
  double seconds = 6, settle = 4, rpm = -1, sm = -1, E = -1, n = -1, r = -1, loose = -1;
  int bands = -1, sectors = -1;
  bool profile = false, trace = false, exact = false;
  try {
    core::CliArgs args(argc, argv);
    while (args.next()) {
      const std::string a = args.flag();
      if (a == "-h" || a == "--help") return usage(), 0;
      else if (a == "--profile") profile = true;
      else if (a == "--trace") trace = true;
      else if (a == "--exact") exact = true;
      else if (a == "--config") config = args.value();
      else if (a == "--seconds") seconds = args.number(0.1, 1e4);
      else if (a == "--settle") settle = args.number(0, 1e4);
      else if (a == "--speed-rpm") rpm = args.number(1, 2000);
      else if (a == "--static-moment") sm = args.number(0, 1e4);
      else if (a == "--modulus-MPa") E = args.number(1e-3, 1e6);
      else if (a == "--exponent") n = args.number(1, 6);
      else if (a == "--rebound") r = args.number(0.01, 1);
      else if (a == "--loose") loose = args.number(0.2, 0.8);
      else if (a == "--bands") bands = static_cast<int>(args.number(2, 400));
      else if (a == "--sectors") sectors = static_cast<int>(args.number(1, 360));
      else throw std::invalid_argument("unknown argument '" + a + "'");
    }
    if (config.empty()) throw std::invalid_argument("--config FILE is required");
  } catch (const std::exception& e) {
    std::cerr << "flow_bench: " << e.what() << "\n";
    usage();
    return 2;
  }
  try {
    auto [mech, flow, run] = chamber::load_flow_run_config(config);
    if (rpm > 0) mech.drive_speed_rad_s = rpm * 2 * M_PI / 60;
    if (sm >= 0) mech.vibrator_static_moment_kg_m = sm;
    if (E > 0) flow.material.modulus_Pa = E * 1e6;
    if (n > 0) flow.material.exponent = n;
    if (r > 0) flow.material.rebound = r;
    if (loose > 0) flow.material.loose_fraction = loose;
    if (bands > 0) flow.bands = bands;
    if (sectors > 0) flow.sectors = sectors;
    mbd::validate(mech, false);
    analysis::FlowRunOptions o;
    o.duration_s = seconds;
    o.settle_s = settle;
    if (trace) o.trace_every_s = 0.5;
    const auto res = analysis::run_flow(mech, flow, o);
    const auto& s = res.summary;
    const auto& p = *s.product;
    const double sim = seconds + settle;
    std::printf("flow_bench config %s speed_rpm %.1f static_moment %.2f cells %d x %d\n", config.c_str(),
                mech.drive_speed_rad_s * 60 / (2 * M_PI), mech.vibrator_static_moment_kg_m, flow.bands, flow.sectors);
    std::printf("simulated_s %.2f wall_s %.3f real_time_factor %.1f\n", sim, res.wall_s, sim / res.wall_s);
    std::printf("amplitude_x_mm mean %.3f std %.3f  power_kW mean %.2f std %.2f  nutation_deg %.3f\n",
                s.amplitude_x_mm.mean, s.amplitude_x_mm.std, s.power_kW.mean, s.power_kW.std, res.mean_nutation_deg);
    std::printf("throughput_tph %.2f specific_energy_kWh_per_t %.3f crushing_kW %.2f (extrusion %.2f) chamber_kg %.1f "
                "compressions %.2f\n",
                p.throughput_tph, p.throughput_tph > 0 ? s.power_kW.mean / p.throughput_tph : NAN, res.crushing_kW,
                res.extrusion_kW, res.chamber_kg, res.product_compressions);
    std::printf("P80_mm %.2f passing_12mm_pct %.1f passing_1mm_pct %.2f friction_kW %.2f mantle_spin_rpm %.2f\npsd",
                res.p80_mm, res.passing_12mm_pct, res.passing_1mm_pct, res.friction_kW, res.mean_spin_rpm);
    for (std::size_t k = 0; k < p.sieve_mm.size(); ++k) std::printf(" %g:%.1f", p.sieve_mm[k], p.passing_pct[k]);
    std::printf("\nproduct_extruded_pct %.1f (mean gap %.2f mm; the rest fell out as the gap opened)\n", res.extruded_pct,
                res.extruded_gap_mm);
    std::printf("cone_contact_pct %.1f (mean normal force %.1f kN: the liners' metal contact, Eq. 11)\n", res.contact_pct,
                res.contact_kN);
    if (exact) {
      for (const auto& [name, v] : analysis::table5_values(res))
        if (name != "wall_s") std::printf("exact %s %.17g\n", name.c_str(), v);
      for (std::size_t k = 0; k < p.sieve_mm.size(); ++k) std::printf("exact passing_pct_%g %.17g\n", p.sieve_mm[k], p.passing_pct[k]);
      std::printf("exact mass_discharged_kg %.17g\n", p.mass_discharged_kg);
    }
    if (profile)
      for (const auto& b : res.bands)
        std::printf("band z_mm %.0f gap_mm %.1f-%.1f kg %.2f fill %.2f nipped %.2f compressions %.2f\n", b.z_m * 1e3,
                    b.gap_min_m * 1e3, b.gap_max_m * 1e3, b.kg, b.fill, b.nipped, b.compressions);
  } catch (const std::exception& e) {
    std::cerr << "flow_bench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
