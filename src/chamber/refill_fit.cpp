#include "chamber/refill_fit.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include "chamber/bed_compaction.hpp"
#include "chamber/bed_refill.hpp"

namespace chamber {

std::vector<double> refill_slice_work(const FlowMaterial& m, double gap, double stroke, double frequency_hz, int cycles,
                                      double gravity, int steps_per_cycle) {
  if (!(gap > 0) || !(stroke > 0) || stroke >= gap || !(frequency_hz > 0) || cycles < 1 || steps_per_cycle < 100)
    throw std::invalid_argument("refill_slice_work: needs 0 < stroke < gap, frequency > 0, cycles >= 1");
  const CompactionScale scale = compaction_scale(m);
  const double pi = std::acos(-1.0), h = 1.0 / (frequency_hz * steps_per_cycle);
  mbd::BedCell cell;
  BedRefill refill;
  std::vector<double> work(static_cast<std::size_t>(cycles), 0.0);
  double s_before = 0, p_before = 0;
  for (int c = 0; c < cycles; ++c)
    for (int i = 1; i <= steps_per_cycle; ++i) {
      const double t = (double(c) * steps_per_cycle + i) * h;
      const double s = stroke * (1.0 - std::cos(2.0 * pi * frequency_hz * t)) / (2.0 * gap);  // 1 - x / gap
      const double u = scale.u(s);
      const double p =
          bed_refilling(cell, refill, u, h, m.modulus_Pa, m.exponent, m.rebound, m.refill_length_m, gravity).p;
      work[static_cast<std::size_t>(c)] += 0.5 * (p + p_before) * (s - s_before);
      s_before = s, p_before = p;
    }
  for (double& w : work) w /= m.loose_fraction * m.solid_density;
  return work;
}

namespace {
// The law's mean reload (cycles 2 on) at rpm, J/kg.
double mean_reload(const FlowMaterial& m, double gap, double stroke, int cycles, double gravity, double rpm) {
  const std::vector<double> w = refill_slice_work(m, gap, stroke, rpm / 60.0, cycles, gravity);
  if (w.size() < 2) return w[0];
  double sum = 0;
  for (std::size_t i = 1; i < w.size(); ++i) sum += w[i];
  return sum / double(w.size() - 1);
}
}  // namespace

double refill_reload_ratio(const FlowMaterial& m, double gap, double stroke, int cycles, double gravity, double rpm,
                           double reference_rpm) {
  return mean_reload(m, gap, stroke, cycles, gravity, rpm) / mean_reload(m, gap, stroke, cycles, gravity, reference_rpm);
}

RefillFit fit_refill_length(const FlowMaterial& m, double gap, double stroke, int cycles, double gravity,
                            const std::vector<SliceReload>& data, double reference_rpm, const std::vector<double>& fit_rpm) {
  std::map<int, double> reference;  // pouring -> its reload at the reference speed
  for (const auto& d : data)
    if (d.rpm == reference_rpm && d.reload_J_kg > 0) reference[d.pouring] = d.reload_J_kg;
  std::vector<std::pair<double, double>> ratios;  // rpm, measured ratio
  for (const auto& d : data)
    if (d.rpm != reference_rpm && d.reload_J_kg > 0 && reference.count(d.pouring) &&
        std::find(fit_rpm.begin(), fit_rpm.end(), d.rpm) != fit_rpm.end())
      ratios.push_back({d.rpm, d.reload_J_kg / reference[d.pouring]});
  if (ratios.empty())
    throw std::invalid_argument("fitting the refill length needs a pouring with reloads at " +
                                std::to_string(reference_rpm) + " rpm and at a fitted speed");
  double fastest = 0;
  for (const auto& r : ratios) fastest = std::max(fastest, r.first);
  auto law = [&](double d, double rpm) {
    FlowMaterial l = m;
    l.refill_length_m = d;
    return refill_reload_ratio(l, gap, stroke, cycles, gravity, rpm, reference_rpm);
  };
  auto cost = [&](double d) {  // the law's reload at the reference speed once, then at each fitted speed once
    FlowMaterial l = m;
    l.refill_length_m = d;
    const double reference_reload = mean_reload(l, gap, stroke, cycles, gravity, reference_rpm);
    std::map<double, double> at;  // the law's ratio per speed
    double sum = 0;
    for (const auto& r : ratios) {
      if (!at.count(r.first)) at[r.first] = mean_reload(l, gap, stroke, cycles, gravity, r.first) / reference_reload;
      const double e = std::log(r.second / at[r.first]);
      sum += e * e;
    }
    return sum;
  };
  // the search's upper end: the first minimum of the law's ratio at the fastest fitted speed (faster than the
  // reference: the ratio falls from 1 with d, then returns to 1), on a log grid of 20 points per decade
  const double lo = 1e-4;
  double hi = lo, prev = law(lo, fastest);
  for (int i = 1; i <= 100; ++i) {
    const double d = lo * std::pow(10.0, i / 20.0), r = law(d, fastest);
    hi = d;
    if (fastest > reference_rpm ? r > prev : r < prev) break;
    prev = r;
  }
  // golden section on ln d between lo and hi, started from the grid's best
  double best = lo, best_cost = cost(lo);
  for (int i = 1; i <= 40; ++i) {
    const double d = lo * std::pow(hi / lo, i / 40.0), c = cost(d);
    if (c < best_cost) best = d, best_cost = c;
  }
  double a = std::max(lo, best / std::pow(hi / lo, 1.0 / 40.0)), b = std::min(hi, best * std::pow(hi / lo, 1.0 / 40.0));
  const double phi = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = std::exp(std::log(b) - phi * std::log(b / a)), x2 = std::exp(std::log(a) + phi * std::log(b / a));
  double f1 = cost(x1), f2 = cost(x2);
  for (int i = 0; i < 40; ++i) {
    if (f1 < f2) {
      b = x2, x2 = x1, f2 = f1;
      x1 = std::exp(std::log(b) - phi * std::log(b / a)), f1 = cost(x1);
    } else {
      a = x1, x1 = x2, f1 = f2;
      x2 = std::exp(std::log(a) + phi * std::log(b / a)), f2 = cost(x2);
    }
  }
  RefillFit fit;
  fit.length_m = f1 < f2 ? x1 : x2;
  const double c = std::min({f1, f2, best_cost});
  if (best_cost < std::min(f1, f2)) fit.length_m = best;
  fit.ratios = static_cast<int>(ratios.size());
  fit.rms_log = std::sqrt(c / fit.ratios);
  return fit;
}

}  // namespace chamber
