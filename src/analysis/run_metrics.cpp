#include "analysis/run_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace analysis {
namespace {

constexpr double kTwoPi = 6.283185307179586;

MeanStd stats(const std::vector<double>& v) {
  MeanStd r;
  r.samples = static_cast<int>(v.size());
  if (v.empty()) return r;
  double s = 0;
  for (double x : v) s += x;
  r.mean = s / v.size();
  double q = 0;
  for (double x : v) q += (x - r.mean) * (x - r.mean);
  r.std = v.size() > 1 ? std::sqrt(q / (v.size() - 1)) : 0.0;
  return r;
}

// Calls f(begin, end) for each whole drive cycle [t_from + k T, t_from + (k+1) T).
template <class F>
void for_each_cycle(const std::vector<double>& t, double speed, double t_from, F f) {
  if (!(speed > 0)) throw std::invalid_argument("run metrics: drive speed must be > 0 rad/s");
  const double period = kTwoPi / speed;
  std::size_t i = std::lower_bound(t.begin(), t.end(), t_from) - t.begin();
  double start = t_from;
  while (i < t.size()) {
    double end = start + period;
    if (t.back() < end - 1e-12) break;  // incomplete last cycle
    std::size_t j = i;
    while (j < t.size() && t[j] < end) ++j;
    if (j > i + 1) f(i, j);
    i = j;
    start = end;
  }
}

// JSON has no inf or nan: a non-finite number is written as null and its field named in `bad`.
struct JsonOut {
  std::ostringstream o;
  std::vector<std::string>* bad;
  void num(const std::string& field, double x) {
    if (std::isfinite(x)) {
      o << x;
    } else {
      o << "null";
      if (bad && (bad->empty() || bad->back() != field)) bad->push_back(field);
    }
  }
};

// Statistics over whole drive cycles after the settle: null (not 0) when the run has none (DESIGN: null where a value
// does not exist).
void json_mean_std(JsonOut& j, const char* name, const MeanStd& m) {
  j.o << "  \"" << name << "\": {\"mean\": ";
  if (m.samples > 0) j.num(std::string(name) + ".mean", m.mean); else j.o << "null";
  j.o << ", \"std\": ";
  if (m.samples > 0) j.num(std::string(name) + ".std", m.std); else j.o << "null";
  j.o << ", \"cycles\": " << m.samples << "},\n";
}

void json_array(JsonOut& j, const char* name, const std::vector<double>& v) {
  j.o << "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    j.o << (i ? ", " : "");
    j.num(name, v[i]);
  }
  j.o << "]";
}

std::string escape(const std::string& s) {
  std::string r;
  for (char c : s) {
    if (c == '"' || c == '\\') r += '\\';
    r += c;
  }
  return r;
}
}  // namespace

MeanStd cycle_amplitude(const std::vector<double>& t, const std::vector<double>& v, double speed, double t_from) {
  std::vector<double> amps;
  for_each_cycle(t, speed, t_from, [&](std::size_t a, std::size_t b) {
    auto [lo, hi] = std::minmax_element(v.begin() + a, v.begin() + b);
    amps.push_back(0.5 * (*hi - *lo));
  });
  return stats(amps);
}

MeanStd cycle_mean(const std::vector<double>& t, const std::vector<double>& v, double speed, double t_from) {
  std::vector<double> means;
  for_each_cycle(t, speed, t_from, [&](std::size_t a, std::size_t b) {
    double s = 0;
    for (std::size_t k = a; k < b; ++k) s += v[k];
    means.push_back(s / (b - a));
  });
  return stats(means);
}

RunSummary summarize(const RunSignals& s, double speed, double t_from) {
  RunSummary r;
  auto scaled = [](MeanStd m, double f) {
    m.mean *= f;
    m.std *= f;
    return m;
  };
  r.amplitude_x_mm = scaled(cycle_amplitude(s.t_s, s.x_m, speed, t_from), 1e3);
  r.amplitude_y_mm = scaled(cycle_amplitude(s.t_s, s.y_m, speed, t_from), 1e3);
  r.amplitude_z_mm = scaled(cycle_amplitude(s.t_s, s.z_m, speed, t_from), 1e3);
  r.power_kW = scaled(cycle_mean(s.t_s, s.power_W, speed, t_from), 1e-3);
  r.speed_rad_s = cycle_mean(s.t_s, s.speed_rad_s, speed, t_from);
  r.simulated_s = s.t_s.empty() ? 0.0 : s.t_s.back();
  return r;
}

double passing_size_mm(const std::vector<double>& x, const std::vector<double>& p, double pct) {
  for (std::size_t k = 1; k < x.size(); ++k)
    if (p[k - 1] < pct && p[k] >= pct) {
      const double f = (pct - p[k - 1]) / (p[k] - p[k - 1]);
      return std::exp(std::log(x[k - 1]) + f * (std::log(x[k]) - std::log(x[k - 1])));
    }
  if (!p.empty() && p.front() >= pct) return x.front();
  return -1;
}

double passing_at_mm(const std::vector<double>& x, const std::vector<double>& p, double xq) {
  if (x.empty()) return 0;
  if (xq <= x.front()) return p.front();
  for (std::size_t k = 1; k < x.size(); ++k)
    if (xq <= x[k]) {
      const double f = (std::log(xq) - std::log(x[k - 1])) / (std::log(x[k]) - std::log(x[k - 1]));
      return p[k - 1] + f * (p[k] - p[k - 1]);
    }
  return p.back();
}

std::string to_json(const RunSummary& s, std::vector<std::string>* non_finite) {
  JsonOut j{{}, non_finite};
  auto& o = j.o;
  o << std::setprecision(8);
  o << "{\n";
  o << "  \"config\": \"" << escape(s.config) << "\",\n";
  o << "  \"load\": \"" << escape(s.load) << "\",\n";
  json_mean_std(j, "amplitude_x_mm", s.amplitude_x_mm);
  json_mean_std(j, "amplitude_y_mm", s.amplitude_y_mm);
  json_mean_std(j, "amplitude_z_mm", s.amplitude_z_mm);
  json_mean_std(j, "power_kW", s.power_kW);
  json_mean_std(j, "drive_speed_rad_s", s.speed_rad_s);
  if (s.product) {
    const auto& p = *s.product;
    double tph = p.throughput_tph;
    o << "  \"throughput_tph\": ";
    j.num("throughput_tph", tph);
    o << ",\n  \"specific_energy_kWh_per_t\": ";
    if (tph > 0 && s.power_kW.samples > 0) j.num("specific_energy_kWh_per_t", s.power_kW.mean / tph); else o << "null";
    o << ",\n  \"mass_discharged_kg\": ";
    j.num("mass_discharged_kg", p.mass_discharged_kg);
    o << ",\n  \"mass_lost_kg\": ";
    j.num("mass_lost_kg", p.mass_lost_kg);
    o << ",\n  \"mass_crushed_kg\": ";
    j.num("mass_crushed_kg", p.mass_crushed_kg);
    o << ",\n  \"psd\": {\"sieve_mm\": ";
    json_array(j, "psd.sieve_mm", p.sieve_mm);
    o << ", \"passing_pct\": ";
    json_array(j, "psd.passing_pct", p.passing_pct);
    o << "},\n";
    const double p80 = passing_size_mm(p.sieve_mm, p.passing_pct, 80);
    const bool any = p.mass_discharged_kg > 0 && !p.sieve_mm.empty();
    o << "  \"p80_mm\": ";
    if (any && p80 > 0) j.num("p80_mm", p80); else o << "null";
    o << ",\n  \"passing_12mm_pct\": ";
    if (any) j.num("passing_12mm_pct", passing_at_mm(p.sieve_mm, p.passing_pct, 12)); else o << "null";
    o << ",\n  \"passing_1mm_pct\": ";
    if (any) j.num("passing_1mm_pct", passing_at_mm(p.sieve_mm, p.passing_pct, 1)); else o << "null";
    o << ",\n";
  } else {
    o << "  \"throughput_tph\": null,\n  \"specific_energy_kWh_per_t\": null,\n  \"mass_discharged_kg\": null,\n"
      << "  \"mass_lost_kg\": null,\n  \"mass_crushed_kg\": null,\n  \"psd\": null,\n"
      << "  \"p80_mm\": null,\n  \"passing_12mm_pct\": null,\n  \"passing_1mm_pct\": null,\n";
  }
  o << "  \"simulated_s\": ";
  j.num("simulated_s", s.simulated_s);
  o << ",\n  \"wall_s\": ";
  j.num("wall_s", s.wall_s);
  o << ",\n  \"stopped\": ";
  if (s.stopped.empty()) o << "null"; else o << "\"" << escape(s.stopped) << "\"";
  o << "\n}\n";
  return o.str();
}

}  // namespace analysis
