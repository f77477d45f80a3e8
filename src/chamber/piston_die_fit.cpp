// Fits of the flow model's material parameters to piston-die results, lab CSV input and the yaml writer
// (see piston_die.hpp for the laws).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <sstream>
#include <stdexcept>

#include "chamber/piston_die.hpp"

namespace chamber {
namespace {

// Nelder-Mead minimiser (unconstrained; callers transform bounded parameters).
std::vector<double> nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double> x0,
                                double step, int max_iter, double* fmin) {
  const std::size_t n = x0.size();
  std::vector<std::vector<double>> v(n + 1, x0);
  std::vector<double> fv(n + 1);
  for (std::size_t i = 0; i < n; ++i) v[i + 1][i] += step;
  for (std::size_t i = 0; i <= n; ++i) fv[i] = f(v[i]);
  for (int it = 0; it < max_iter; ++it) {
    std::vector<std::size_t> idx(n + 1);
    for (std::size_t i = 0; i <= n; ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return fv[a] < fv[b]; });
    const std::size_t best = idx[0], worst = idx[n], second = idx[n - 1];
    if (std::abs(fv[worst] - fv[best]) <= 1e-12 * (1.0 + std::abs(fv[best]))) break;
    std::vector<double> c(n, 0.0);
    for (std::size_t i = 0; i <= n; ++i)
      if (i != worst)
        for (std::size_t k = 0; k < n; ++k) c[k] += v[i][k] / n;
    auto along = [&](double t) {
      std::vector<double> x(n);
      for (std::size_t k = 0; k < n; ++k) x[k] = c[k] + t * (v[worst][k] - c[k]);
      return x;
    };
    const auto xr = along(-1.0);
    const double fr = f(xr);
    if (fr < fv[best]) {
      const auto xe = along(-2.0);
      const double fe = f(xe);
      if (fe < fr) v[worst] = xe, fv[worst] = fe;
      else v[worst] = xr, fv[worst] = fr;
    } else if (fr < fv[second]) {
      v[worst] = xr, fv[worst] = fr;
    } else {
      const auto xc = along(fr < fv[worst] ? -0.5 : 0.5);
      const double fc = f(xc);
      if (fc < std::min(fr, fv[worst])) {
        v[worst] = xc, fv[worst] = fc;
      } else {  // shrink towards the best
        for (std::size_t i = 0; i <= n; ++i) {
          if (i == best) continue;
          for (std::size_t k = 0; k < n; ++k) v[i][k] = v[best][k] + 0.5 * (v[i][k] - v[best][k]);
          fv[i] = f(v[i]);
        }
      }
    }
  }
  std::size_t b = 0;
  for (std::size_t i = 1; i <= n; ++i)
    if (fv[i] < fv[b]) b = i;
  if (fmin) *fmin = fv[b];
  return v[b];
}

double logistic(double u) { return 1.0 / (1.0 + std::exp(-u)); }
double logit(double p) { return std::log(p / (1.0 - p)); }

std::string fmt(const char* f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

// Breakage fit over the resolved sieves (see piston_die.hpp).
void fit_breakage(const PistonDieResult& r, FlowMaterial& m) {
  std::vector<double> sieves;
  for (double mm : flow_sieves_mm()) sieves.push_back(mm * 1e-3);
  std::vector<std::size_t> use;
  for (std::size_t k = 0; k < sieves.size(); ++k)
    if (r.min_resolved > 0 && sieves[k] >= r.min_resolved * (1 - 1e-9)) use.push_back(k);
  const std::string classes = "classes above " + fmt("%g", r.min_resolved * 1e3) + " mm (>= " +
                              fmt("%.1f", r.min_resolved / std::max(r.metaparticle_diameter, 1e-12)) +
                              " volume-mean metaparticle diameters of " + fmt("%.1f", r.metaparticle_diameter * 1e3) +
                              " mm)";
  double change = 0.0;
  for (const auto& L : r.loops)
    for (std::size_t k : use) change = std::max(change, std::abs(L.passing[k] - r.feed_passing[k]));
  if (use.empty() || r.loops.empty() || change < 0.01) {
    m.breakage_note = "breakage not fitted (" + std::string(use.empty() ? "no resolved sieve" : "no measurable breakage") +
                      "): defaults";
    return;
  }
  // Feed classes that are resolved and carry >= 10 % of the feed: q needs two of them.
  int feed_classes = 0;
  for (std::size_t i = 0; i + 1 < use.size(); ++i)
    if (r.feed_passing[use[i + 1]] - r.feed_passing[use[i]] >= 0.10) ++feed_classes;
  const bool fit_q = feed_classes >= 2, fit_m = r.loops.size() >= 2;
  BreakageParams b0;
  auto unpack = [&](const std::vector<double>& u) {
    BreakageParams b = b0;
    std::size_t k = 0;
    // bounded: s_c in (0.01, 5), m in (0.3, 10), q in (0, 3), phi in (0, 1), gamma in (0.1, 10)
    b.s_c = 0.01 + 4.99 * logistic(u[k++]);
    if (fit_m) b.m = 0.3 + 9.7 * logistic(u[k++]);
    if (fit_q) b.q = 3.0 * logistic(u[k++]);
    b.phi = logistic(u[k++]);
    b.gamma = 0.1 + 9.9 * logistic(u[k++]);
    return b;
  };
  auto sse = [&](const BreakageParams& b) {
    double e = 0.0;
    for (const auto& L : r.loops) {
      const auto pred = breakage_event(r.feed_passing, sieves, L.s_reached, b);
      for (std::size_t k : use) e += std::pow(100.0 * (pred[k] - L.passing[k]), 2);
    }
    return e;
  };
  std::vector<double> u0{logit((b0.s_c - 0.01) / 4.99)};
  if (fit_m) u0.push_back(logit((b0.m - 0.3) / 9.7));
  if (fit_q) u0.push_back(logit(b0.q / 3.0));
  u0.push_back(logit(b0.phi));
  u0.push_back(logit((b0.gamma - 0.1) / 9.9));
  double best = 1e300;
  std::vector<double> ubest = u0;
  for (double start : {0.0, -0.7, 0.7}) {  // restarts from shifted s_c
    auto u = u0;
    u[0] += start;
    double f = 0.0;
    u = nelder_mead([&](const std::vector<double>& x) { return sse(unpack(x)); }, u, 0.5, 4000, &f);
    u = nelder_mead([&](const std::vector<double>& x) { return sse(unpack(x)); }, u, 0.1, 4000, &f);
    if (f < best) best = f, ubest = u;
  }
  m.breakage = unpack(ubest);
  m.psd_rms_pct = std::sqrt(best / (r.loops.size() * use.size()));
  m.fitted = {"s_c"};
  if (fit_m) m.fitted.push_back("m");
  if (fit_q) m.fitted.push_back("q");
  m.fitted.push_back("phi");
  m.fitted.push_back("gamma");
  m.breakage_note = "breakage fitted on " + classes + "; " + (fit_q ? "" : "q, ") + (fit_m ? "" : "m, ") +
                    "beta: defaults (the resolved sizes do not constrain them)";
}

}  // namespace

PowerLawFit fit_power_law(const std::vector<double>& s, const std::vector<double>& p, double s_min) {
  if (s.size() != p.size()) throw std::invalid_argument("fit_power_law: s and p differ in length");
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (!(s[k] > s_min) || !(p[k] > 0)) continue;
    const double x = std::log(s[k]), y = std::log(p[k]);
    sx += x, sy += y, sxx += x * x, sxy += x * y, ++n;
  }
  const double det = n * sxx - sx * sx;
  if (n < 2 || !(det > 1e-14 * n * n))
    throw std::invalid_argument("fit_power_law: need >= 2 loading points with distinct s > " + fmt("%g", s_min) +
                                " and p > 0, got " + std::to_string(n));
  PowerLawFit f;
  f.exponent = (n * sxy - sx * sy) / det;
  const double lnE = (sy - f.exponent * sx) / n;
  f.modulus = std::exp(lnE);
  f.points = n;
  double e = 0;
  for (std::size_t k = 0; k < s.size(); ++k)
    if (s[k] > s_min && p[k] > 0) e += std::pow(std::log(p[k]) - lnE - f.exponent * std::log(s[k]), 2);
  f.rms_log = std::sqrt(e / n);
  return f;
}

double path_integral(const std::vector<double>& s, const std::vector<double>& p) {
  if (s.size() != p.size()) throw std::invalid_argument("path_integral: s and p differ in length");
  double w = 0.0;
  for (std::size_t k = 1; k < s.size(); ++k) w += 0.5 * (p[k] + p[k - 1]) * (s[k] - s[k - 1]);
  return w;
}

double hysteretic_loop_loss(double E, double n, double rebound, double D) {
  return (1.0 - rebound) * E * std::pow(D, n + 1.0) / (n + 1.0);  // bed_law.hpp, bed_hysteretic
}

double fit_rebound(double E, double n, const std::vector<double>& D, const std::vector<double>& loss, double* rms) {
  if (D.empty() || D.size() != loss.size())
    throw std::invalid_argument("fit_rebound: need as many loop losses as compressions (>= 1)");
  double ww = 0, wl = 0;
  for (std::size_t k = 0; k < D.size(); ++k) {
    const double W = hysteretic_loop_loss(E, n, 0.0, D[k]);
    ww += W * W, wl += W * loss[k];
  }
  if (!(ww > 0)) throw std::invalid_argument("fit_rebound: compressions must be > 0");
  const double r = std::clamp(1.0 - wl / ww, 0.0, 1.0);
  if (rms) {
    double e = 0;
    for (std::size_t k = 0; k < D.size(); ++k) e += std::pow(hysteretic_loop_loss(E, n, r, D[k]) - loss[k], 2);
    *rms = std::sqrt(e / D.size());
  }
  return r;
}

double progeny_B(double x, double y, const BreakageParams& b) {
  if (!(x > 0)) return 0.0;
  const double r = std::min(x / y, 1.0);
  return std::clamp(b.phi * std::pow(r, b.gamma) + (1.0 - b.phi) * std::pow(r, b.beta), 0.0, 1.0);
}

double selection_S(double x, double s, const BreakageParams& b) {
  if (!(s > 0)) return 0.0;
  const double sc = b.s_c * std::pow(x / b.x_ref, -b.q);
  return 1.0 - std::exp(-std::pow(s / sc, b.m));
}

std::vector<double> breakage_event(const std::vector<double>& P, const std::vector<double>& a, double s,
                                   const BreakageParams& b) {
  const std::size_t K = a.size();
  if (P.size() != K || K < 2) throw std::invalid_argument("breakage_event: need >= 2 sieves and one passing each");
  // classes c = 0 (pan, below a[0]), 1..K-1 (a[c-1], a[c]], K (above a[K-1])
  std::vector<double> f(K + 1), lo(K + 1), hi(K + 1);
  for (std::size_t c = 0; c <= K; ++c) {
    f[c] = (c < K ? P[c] : 1.0) - (c ? P[c - 1] : 0.0);
    lo[c] = c ? a[c - 1] : 0.0;
    hi[c] = c < K ? a[c] : a[K - 1] * std::sqrt(2.0);
  }
  std::vector<double> out(K + 1, 0.0);
  for (std::size_t j = 0; j <= K; ++j) {
    // the pan's breakage stays in the pan: S = 0 there
    const double S = j ? selection_S(std::sqrt(lo[j] * hi[j]), s, b) : 0.0;
    out[j] += (1.0 - S) * f[j];
    for (std::size_t c = 0; c <= j; ++c)  // b_cj = B(hi_c; y_j) - B(lo_c; y_j), y_j = hi_j (b_jj: stays)
      out[c] += S * f[j] * (progeny_B(c == j ? hi[j] : hi[c], hi[j], b) - progeny_B(lo[c], hi[j], b));
  }
  std::vector<double> cum(K);
  double acc = 0.0;
  for (std::size_t k = 0; k < K; ++k) cum[k] = (acc += out[k]);
  return cum;
}

FlowMaterial fit_flow_material(const PistonDieResult& r) {
  if (r.loops.empty()) throw std::invalid_argument("fit_flow_material: the result holds no load-unload loop");
  FlowMaterial m;
  m.solid_density = r.solid_density;
  m.loose_solid_fraction = r.loose_solid_fraction;
  // Every loop starts from the same settled bed (deterministic), so the deepest one's loading branch holds the
  // others': fit that one.
  const PressLoop* deep = &r.loops.front();
  for (const auto& L : r.loops)
    if (L.s_reached > deep->s_reached) deep = &L;
  std::vector<double> s, p, D, loss;
  for (std::size_t k = 0; k < deep->s.size(); ++k)
    if (deep->phase[k] == 0) s.push_back(deep->s[k]), p.push_back(deep->p[k]);
  m.pressure_fit = fit_power_law(s, p, 0.02);
  m.modulus = m.pressure_fit.modulus, m.exponent = m.pressure_fit.exponent;
  m.max_compression = 0.0;  // the largest s reached
  for (const auto& L : r.loops) {
    D.push_back(L.s_reached), loss.push_back(L.loop_energy);
    m.max_compression = std::max(m.max_compression, L.s_reached);
  }
  m.rebound = fit_rebound(m.modulus, m.exponent, D, loss, &m.rebound_rms);
  fit_breakage(r, m);
  return m;
}

std::vector<LabPoint> read_lab_csv(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::invalid_argument("--lab " + file + ": cannot read the file");
  std::vector<LabPoint> pts;
  std::string line;
  int no = 0;
  while (std::getline(in, line)) {
    ++no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.find_first_not_of(" \t") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    std::vector<std::string> cols;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) {
      c.erase(0, c.find_first_not_of(" \t"));
      c.erase(c.find_last_not_of(" \t") + 1);
      cols.push_back(c);
    }
    auto where = [&] { return "--lab " + file + " line " + std::to_string(no) + ": "; };
    char* end = nullptr;
    const double s = cols.empty() ? NAN : std::strtod(cols[0].c_str(), &end);
    if (cols.empty() || end == cols[0].c_str()) {
      if (pts.empty() && no == 1) continue;  // header
      throw std::invalid_argument(where() + "expected 's,p_MPa[,phase]' with numbers, got '" + line + "'");
    }
    if (cols.size() < 2 || cols.size() > 3)
      throw std::invalid_argument(where() + "expected 2 or 3 columns (s,p_MPa[,phase]), got " +
                                  std::to_string(cols.size()));
    LabPoint q;
    q.s = s;
    q.p = std::strtod(cols[1].c_str(), &end) * 1e6;
    if (*end || cols[1].empty() || !std::isfinite(q.p) || !std::isfinite(s) || s < 0 || s >= 1 || q.p < -1e3)
      throw std::invalid_argument(where() + "s must be in [0, 1) and p_MPa a number >= 0, got '" + line + "'");
    if (cols.size() == 3) {
      const std::string& ph = cols[2];
      if (ph == "0" || ph == "load" || ph == "loading") q.phase = 0;
      else if (ph == "1" || ph == "unload" || ph == "unloading") q.phase = 1;
      else throw std::invalid_argument(where() + "phase '" + ph + "': accepted load, unload, 0 or 1");
    }
    pts.push_back(q);
  }
  if (pts.size() < 3) throw std::invalid_argument("--lab " + file + ": need >= 3 data rows (s,p_MPa[,phase])");
  return pts;
}

FlowMaterial fit_flow_material_lab(const std::vector<LabPoint>& pts) {
  if (pts.size() < 3) throw std::invalid_argument("fit_flow_material_lab: need >= 3 points");
  // phases from the direction of s where not given; a loop starts where loading follows unloading
  std::vector<int> ph(pts.size());
  for (std::size_t k = 0; k < pts.size(); ++k) {
    if (pts[k].phase >= 0) ph[k] = pts[k].phase;
    else if (k == 0) ph[k] = 0;
    else ph[k] = pts[k].s > pts[k - 1].s ? 0 : pts[k].s < pts[k - 1].s ? 1 : ph[k - 1];
  }
  std::vector<std::vector<std::size_t>> loops;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    if (loops.empty() || (ph[k] == 0 && k > 0 && ph[k - 1] == 1)) loops.emplace_back();
    loops.back().push_back(k);
  }
  FlowMaterial m;
  std::vector<double> s, p, D, loss;
  bool unloaded = false;
  m.max_compression = 0.0;  // the largest s reached
  for (const auto& L : loops) {
    std::vector<double> ls, lp;
    double dmax = 0;
    bool has_unload = false;
    for (std::size_t k : L) {
      ls.push_back(pts[k].s), lp.push_back(pts[k].p);
      dmax = std::max(dmax, pts[k].s);
      if (ph[k] == 0) s.push_back(pts[k].s), p.push_back(pts[k].p);
      else has_unload = true;
    }
    m.max_compression = std::max(m.max_compression, dmax);
    if (has_unload) {
      D.push_back(dmax), loss.push_back(path_integral(ls, lp));
      unloaded = true;
    }
  }
  m.pressure_fit = fit_power_law(s, p, 0.02);
  m.modulus = m.pressure_fit.modulus, m.exponent = m.pressure_fit.exponent;
  if (unloaded) m.rebound = fit_rebound(m.modulus, m.exponent, D, loss, &m.rebound_rms);
  else m.comments.push_back("no unloading branch in the lab data: rebound default " + fmt("%g", m.rebound));
  m.comments.push_back("loose_solid_fraction not in the lab data: default " + fmt("%g", m.loose_solid_fraction));
  m.breakage_note = "breakage not fitted (the lab data holds no PSD): defaults";
  return m;
}

void write_flow_material_yaml(const FlowMaterial& m, const std::string& file,
                              const std::vector<std::string>& provenance) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("write_flow_material_yaml: cannot write '" + file + "'");
  for (const auto& l : provenance) out << "# " << l << "\n";
  for (const auto& l : m.comments) out << "# " << l << "\n";
  out << "# pressure fit: p = E s^n over " << m.pressure_fit.points << " loading points (s > 0.02), rms of ln p "
      << fmt("%.4f", m.pressure_fit.rms_log) << "; rebound fit rms " << fmt("%.4g", m.rebound_rms * 1e-6)
      << " MPa (loop energies)\n";
  out << "# " << m.breakage_note;
  if (!m.fitted.empty()) {
    out << "; fitted:";
    for (const auto& f : m.fitted) out << " " << f;
    out << " (rms " << fmt("%.2f", m.psd_rms_pct) << " % passing)";
  }
  out << "\n";
  const auto& b = m.breakage;
  out << "flow_material:\n";
  out << "  solid_density_kg_m3: " << fmt("%g", m.solid_density) << "\n";
  out << "  loose_solid_fraction: " << fmt("%.4f", m.loose_solid_fraction) << "\n";
  out << "  pressure: {modulus_MPa: " << fmt("%.6g", m.modulus * 1e-6) << ", exponent: " << fmt("%.4f", m.exponent)
      << ", rebound: " << fmt("%.4f", m.rebound) << ", max_compression: " << fmt("%.4f", m.max_compression) << "}\n";
  out << "  selection: {s_c: " << fmt("%.4f", b.s_c) << ", exponent: " << fmt("%.4f", b.m)
      << ", size_exponent: " << fmt("%.4f", b.q) << ", x_ref_mm: " << fmt("%g", b.x_ref * 1e3) << "}\n";
  out << "  progeny: {phi: " << fmt("%.4f", b.phi) << ", gamma: " << fmt("%.4f", b.gamma)
      << ", beta: " << fmt("%.4f", b.beta) << "}\n";
  if (!out) throw std::runtime_error("write_flow_material_yaml: writing '" + file + "' failed");
}

}  // namespace chamber
