#include "analysis/flow_run.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "chamber/flow_load.hpp"
#include "core/config_schema.hpp"
#include "mbd/mechanism.hpp"

namespace analysis {

FlowRunResult run_flow(const mbd::MechanismParams& mech, const chamber::FlowParams& flow, const FlowRunOptions& o) {
  if (!(o.duration_s > 0) || !(o.settle_s >= 0) || !(o.sample_hz > 0))
    throw std::invalid_argument("run_flow: needs duration_s > 0, settle_s >= 0, sample_hz > 0");
  const auto w0 = std::chrono::steady_clock::now();
  mbd::Mechanism m(mech, mbd::LoadModel::None);
  chamber::FlowLoad load(flow, mech);
  const double dt = mech.dt_s;
  const long every = std::max(1L, std::lround(1.0 / (o.sample_hz * dt)));
  const long settle = std::lround(o.settle_s / dt), total = settle + std::lround(o.duration_s / dt);
  FlowRunResult r;
  auto& s = r.signals;
  chamber::ProductWindow win;
  double nut = 0, spin = 0, contact_N = 0;
  long nut_n = 0, contact_n = 0;
  const long trace = o.trace_every_s > 0 ? std::max(1L, std::lround(o.trace_every_s / dt)) : 0;
  double fed0 = 0, out0 = 0, work0 = 0, tr_nut = 0;
  for (long i = 1; i <= total; ++i) {
    if (i == settle + 1) win = chamber::snapshot(load.model(), m.time());  // the window opens at the settle time
    load.step(m);
    if (trace) {
      tr_nut += m.nutation_angle();
      if (i % trace == 0) {
        const auto& f = load.model();
        const double span = trace * dt, work = m.flows().motor_input_work;
        std::fprintf(stderr,
                     "t %.2f s: charge %.1f kg, feed %.0f t/h, product %.0f t/h, nutation %.3f deg, power %.1f kW\n",
                     m.time(), f.mass_kg(), (f.fed_kg() - fed0) / span * 3.6, (f.discharged_kg() - out0) / span * 3.6,
                     tr_nut / trace * 180 / M_PI, (work - work0) / span * 1e-3);
        fed0 = f.fed_kg(), out0 = f.discharged_kg(), work0 = work, tr_nut = 0;
      }
    }
    if (i > settle) {
      nut += m.nutation_angle(), spin += m.mantle_spin(), ++nut_n;
      const double f = m.contact_force();
      contact_N += f, contact_n += f > 0;
    }
    if (i % every == 0) {
      const auto tp = m.test_point();
      const auto d = m.drive();
      s.t_s.push_back(m.time());
      s.x_m.push_back(tp.displacement.x());
      s.y_m.push_back(tp.displacement.y());
      s.z_m.push_back(tp.displacement.z());
      s.power_W.push_back(d.input_power);  // what the plant logs (effects.drive_efficiency)
      s.speed_rad_s.push_back(d.speed);
    }
  }
  chamber::close_window(win, load.model(), m.time());
  r.summary = summarize(s, mech.drive_speed_rad_s, o.settle_s);
  ProductSummary p;
  p.throughput_tph = win.throughput_tph();
  const auto c = win.by_class();
  for (double kg : c) p.mass_discharged_kg += kg;
  const auto pass = load.model().passing(c);
  for (std::size_t k = 0; k < flow.sieves_m.size(); ++k) {
    p.sieve_mm.push_back(flow.sieves_m[k] * 1e3);
    p.passing_pct.push_back(100 * pass[k]);
  }
  r.summary.product = p;
  r.p80_mm = passing_size_mm(p.sieve_mm, p.passing_pct, 80);
  r.passing_12mm_pct = passing_at_mm(p.sieve_mm, p.passing_pct, 12);
  r.passing_1mm_pct = passing_at_mm(p.sieve_mm, p.passing_pct, 1);
  r.product_compressions = load.model().product_compressions();
  r.chamber_kg = load.model().mass_kg();
  const auto window_kW = [&](double J0, double J1) { return (J1 - J0) / std::max(1e-9, win.t1 - win.t0) * 1e-3; };
  r.crushing_kW = window_kW(win.energy0, win.energy1);
  r.mean_nutation_deg = nut_n ? nut / nut_n * 180 / M_PI : 0;
  r.friction_kW = window_kW(win.friction0, win.friction1);
  r.extrusion_kW = window_kW(win.extrusion0, win.extrusion1);
  r.mean_spin_rpm = nut_n ? spin / nut_n * 30 / M_PI : 0;
  r.contact_pct = nut_n ? 100.0 * contact_n / nut_n : 0;
  r.contact_kN = nut_n ? contact_N / nut_n * 1e-3 : 0;
  r.extruded_pct = win.extruded_pct();
  r.extruded_gap_mm = 1e3 * win.extruded_gap_m();
  const auto& fm = load.model();
  for (int b = 0; b < fm.bands(); ++b) {
    FlowRunResult::Band band;
    band.gap_min_m = 1e9;
    double cap = 0;
    for (int q = 0; q < fm.sectors(); ++q) {
      const std::size_t k = static_cast<std::size_t>(b) * fm.sectors() + q;
      band.z_m = fm.cell_point(k).z();
      band.gap_min_m = std::min(band.gap_min_m, fm.cell_gap(k));
      band.gap_max_m = std::max(band.gap_max_m, fm.cell_gap(k));
      band.kg += fm.cell_mass(k);
      cap += fm.cell_loose_density(k) * fm.cell_area(k) * fm.cell_gap(k);
      band.nipped += fm.cell_pressure(k) > 0 ? 1.0 / fm.sectors() : 0.0;
      band.compressions += fm.cell_compressions(k) * fm.cell_mass(k);
    }
    band.fill = cap > 0 ? band.kg / cap : 0;
    band.compressions = band.kg > 0 ? band.compressions / band.kg : 0;
    r.bands.push_back(band);
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  r.summary.wall_s = r.wall_s;
  r.summary.load = "flow";
  return r;
}

FlowRunOptions run_window(const core::RunOptions& run, const std::string& who, double seconds, double settle) {
  FlowRunOptions o;
  o.settle_s = settle >= 0 ? settle : run.settle_s;
  o.duration_s = seconds > 0 ? seconds : run.duration_s - o.settle_s;
  if (!(o.duration_s > 0))
    throw std::invalid_argument(who + ": run.duration_s must exceed the settle time (" +
                                core::format_number(o.settle_s) + " s)");
  return o;
}

std::map<std::string, double> table5_values(const FlowRunResult& r) {
  const auto& s = r.summary;
  const double tph = s.product ? s.product->throughput_tph : NAN;
  return {{"amplitude_x_mm_mean", s.amplitude_x_mm.mean}, {"amplitude_x_mm_std", s.amplitude_x_mm.std},
          {"power_kW_mean", s.power_kW.mean},           {"power_kW_std", s.power_kW.std},
          {"throughput_tph", tph},                      {"specific_energy_kWh_per_t", tph > 0 ? s.power_kW.mean / tph : NAN},
          {"p80_mm", r.p80_mm > 0 ? r.p80_mm : NAN},    {"passing_12mm_pct", r.passing_12mm_pct},
          {"passing_1mm_pct", r.passing_1mm_pct},       {"wall_s", r.wall_s},
          {"compressions", r.product_compressions},     {"chamber_kg", r.chamber_kg},
          {"nutation_deg", r.mean_nutation_deg},        {"crushing_kW", r.crushing_kW},
          {"extruded_product_pct", r.extruded_pct},    {"cone_contact_pct", r.contact_pct}};
}

}  // namespace analysis
