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

#include "chamber/bed_scatter.hpp"
#include "core/nelder_mead.hpp"

namespace chamber {
namespace {

// The hysteretic law needs some elastic recovery (it unloads over rebound x D): the smallest rebound a config accepts.
constexpr double kMinRebound = 0.01;

double logistic(double u) { return 1.0 / (1.0 + std::exp(-u)); }
double logit(double p) { return std::log(p / (1.0 - p)); }

std::string fmt(const char* f, double x) {
  char b[64];
  std::snprintf(b, sizeof b, f, x);
  return b;
}

// Breakage fit over the resolved sieves (see piston_die.hpp), on every pouring's loops together (each from its own
// feed).
void fit_breakage(const std::vector<const PistonDieResult*>& rs, MaterialFit& m) {
  const PistonDieResult& r = *rs.front();
  std::vector<double> sieves;
  for (double mm : flow_sieves_mm()) sieves.push_back(mm * 1e-3);
  double min_resolved = 0.0;  // the coarsest pouring's (the same BPM gives one value)
  for (const auto* q : rs) min_resolved = std::max(min_resolved, q->min_resolved);
  std::vector<std::size_t> use;
  for (std::size_t k = 0; k < sieves.size(); ++k)
    if (min_resolved > 0 && sieves[k] >= min_resolved * (1 - 1e-9)) use.push_back(k);
  const std::string classes = "classes above " + fmt("%g", min_resolved * 1e3) + " mm (>= " +
                              fmt("%.1f", min_resolved / std::max(r.metaparticle_diameter, 1e-12)) +
                              " volume-mean metaparticle diameters of " + fmt("%.1f", r.metaparticle_diameter * 1e3) +
                              " mm)";
  double change = 0.0;
  std::size_t loops = 0, fewest_loops = r.loops.size();
  for (const auto* q : rs) {
    loops += q->loops.size(), fewest_loops = std::min(fewest_loops, q->loops.size());
    for (const auto& L : q->loops)
      for (std::size_t k : use) change = std::max(change, std::abs(L.passing[k] - q->feed_passing[k]));
  }
  if (use.empty() || loops == 0 || change < 0.01) {
    m.breakage_note = "breakage not fitted (" + std::string(use.empty() ? "no resolved sieve" : "no measurable breakage") +
                      "): defaults";
    return;
  }
  // Feed classes that are resolved and carry >= 10 % of the feed (the pourings' mean): q needs two of them.
  int feed_classes = 0;
  for (std::size_t i = 0; i + 1 < use.size(); ++i) {
    double share = 0.0;
    for (const auto* q : rs) share += (q->feed_passing[use[i + 1]] - q->feed_passing[use[i]]) / double(rs.size());
    if (share >= 0.10) ++feed_classes;
  }
  const bool fit_q = feed_classes >= 2, fit_m = fewest_loops >= 2;
  BreakageParams b0;
  b0.x_resolved = min_resolved;  // below it: the strength's size effect through the fitted pressure law
  b0.q_below = bed_size_exponent(kPointLoadSizeExponent, m.material.exponent);
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
    for (const auto* q : rs)
      for (const auto& L : q->loops) {
        const auto pred = breakage_event(q->feed_passing, sieves, L.s_reached, b);
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
    auto cost = [&](const std::vector<double>& x) { return sse(unpack(x)); };
    auto r1 = core::nelder_mead(cost, u, std::vector<double>(u.size(), 0.5), 1e-12, 8000);
    auto r2 = core::nelder_mead(cost, r1.x, std::vector<double>(u.size(), 0.1), 1e-12, 8000);
    u = r2.x, f = r2.f;
    if (f < best) best = f, ubest = u;
  }
  m.material.breakage = unpack(ubest);
  m.psd_rms_pct = std::sqrt(best / (loops * use.size()));
  m.fitted = {"s_c"};
  if (fit_m) m.fitted.push_back("m");
  if (fit_q) m.fitted.push_back("q");
  m.fitted.push_back("phi");
  m.fitted.push_back("gamma");
  m.breakage_note = "breakage fitted on " + classes + (rs.size() > 1 ? ", " + std::to_string(rs.size()) + " pourings" : "") +
                    "; " + (fit_q ? "" : "q, ") + (fit_m ? "" : "m, ") +
                    "beta: defaults (the resolved sizes do not constrain them); below " + fmt("%g", min_resolved * 1e3) +
                    " mm s_c follows the ISRM point-load size effect through the bed's pressure law, exponent 0.45 / n = " +
                    fmt("%g", b0.q_below);
}

}  // namespace

PowerLawFit fit_power_law(const std::vector<double>& s, const std::vector<double>& p, double s_min,
                          const CompactionScale& scale) {
  if (s.size() != p.size()) throw std::invalid_argument("fit_power_law: s and p differ in length");
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  int n = 0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    if (!(s[k] > s_min) || !(p[k] > 0)) continue;
    const double x = std::log(scale.u(s[k])), y = std::log(p[k]);
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
  f.s_min = s_min;
  double e = 0;
  for (std::size_t k = 0; k < s.size(); ++k)
    if (s[k] > s_min && p[k] > 0) e += std::pow(std::log(p[k]) - lnE - f.exponent * std::log(scale.u(s[k])), 2);
  f.rms_log = std::sqrt(e / n);
  return f;
}

double path_integral(const std::vector<double>& s, const std::vector<double>& p) {
  if (s.size() != p.size()) throw std::invalid_argument("path_integral: s and p differ in length");
  double w = 0.0;
  for (std::size_t k = 1; k < s.size(); ++k) w += 0.5 * (p[k] + p[k - 1]) * (s[k] - s[k - 1]);
  return w;
}

double hysteretic_loop_loss(double E, double n, double rebound, double D, const CompactionScale& scale) {
  if (!scale.diverges()) return (1.0 - rebound) * E * std::pow(D, n + 1.0) / (n + 1.0);  // bed_law.hpp, bed_hysteretic
  // p ds = p(u) s'(u) du, s'(u) = (1 + u / L)^-2: loading E u^n from 0 to U = u(D), unloading E U^n ((u - ur) /
  // (rebound U))^n from U to ur = (1 - rebound) U; Simpson in t = u / U (loading) and t = (u - ur) / (rebound U).
  const double U = scale.u(D), L = scale.limit, ur = (1.0 - rebound) * U;
  auto ds = [L](double u) { return 1.0 / ((1.0 + u / L) * (1.0 + u / L)); };
  constexpr int kN = 2000;  // even
  double load = 0.0, back = 0.0;
  for (int i = 0; i <= kN; ++i) {
    const double t = double(i) / kN, w = (i == 0 || i == kN) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    const double tn = std::pow(t, n);
    load += w * tn * ds(t * U);
    back += w * tn * ds(ur + rebound * U * t);
  }
  return E * std::pow(U, n) * U * (load - rebound * back) / (3.0 * kN);
}

double fit_rebound(double E, double n, const std::vector<double>& D, const std::vector<double>& loss, double* rms,
                   const CompactionScale& scale) {
  if (D.empty() || D.size() != loss.size())
    throw std::invalid_argument("fit_rebound: need as many loop losses as compressions (>= 1)");
  auto misfit = [&](double r) {
    double e = 0;
    for (std::size_t k = 0; k < D.size(); ++k) e += std::pow(hysteretic_loop_loss(E, n, r, D[k], scale) - loss[k], 2);
    return e;
  };
  if (scale.diverges()) {  // the loss is not linear in the rebound here: golden section over [0.01, 1]
    for (double d : D)
      if (!(d > 0)) throw std::invalid_argument("fit_rebound: compressions must be > 0");
    double a = kMinRebound, b = 1.0;
    const double g = 0.5 * (std::sqrt(5.0) - 1.0);
    double c = b - g * (b - a), d = a + g * (b - a), fc = misfit(c), fd = misfit(d);
    while (b - a > 1e-7) {
      if (fc < fd) b = d, d = c, fd = fc, c = b - g * (b - a), fc = misfit(c);
      else a = c, c = d, fc = fd, d = a + g * (b - a), fd = misfit(d);
    }
    double r = 0.5 * (a + b), fr = misfit(r);  // or a bound, if that fits better
    if (const double f0 = misfit(kMinRebound); f0 <= fr) r = kMinRebound, fr = f0;
    if (const double f1 = misfit(1.0); f1 < fr) r = 1.0, fr = f1;
    if (rms) *rms = std::sqrt(fr / D.size());
    return r;
  }
  double ww = 0, wl = 0;
  for (std::size_t k = 0; k < D.size(); ++k) {
    const double W = hysteretic_loop_loss(E, n, 0.0, D[k]);
    ww += W * W, wl += W * loss[k];
  }
  if (!(ww > 0)) throw std::invalid_argument("fit_rebound: compressions must be > 0");
  const double r = std::clamp(1.0 - wl / ww, kMinRebound, 1.0);
  if (rms) *rms = std::sqrt(misfit(r) / D.size());
  return r;
}

std::vector<double> breakage_event(const std::vector<double>& P, const std::vector<double>& sieves, double s,
                                   const BreakageParams& b) {
  const std::size_t K = sieves.size();
  if (P.size() != K || K < 2) throw std::invalid_argument("breakage_event: need >= 2 sieves and one passing each");
  std::vector<double> f(K + 1);  // mass fractions per class: pan, between sieves, above the largest
  for (std::size_t c = 0; c <= K; ++c) f[c] = (c < K ? P[c] : 1.0) - (c ? P[c - 1] : 0.0);
  Breakage(sieves, b).apply(s, f.data());
  std::vector<double> cum(K);
  double acc = 0.0;
  for (std::size_t k = 0; k < K; ++k) cum[k] = (acc += f[k]);
  return cum;
}

namespace {

// The fit of one or more pourings together (see piston_die.hpp).
MaterialFit fit_pourings(const std::vector<const PistonDieResult*>& rs, PressureLaw law) {
  // (the law changes E, n and rebound, and through n the size law below the resolved size; the breakage fit is the same)
  if (rs.empty()) throw std::invalid_argument("fit_flow_material: no pouring to fit");
  for (const auto* r : rs)
    if (r->loops.empty()) throw std::invalid_argument("fit_flow_material: a pouring holds no load-unload loop");
  MaterialFit m;
  auto& mat = m.material;
  mat.solid_density = rs.front()->solid_density;
  // loose fraction of the pourings together: their rock mass over their solid density x loose volume (a plain mean
  // where a result has no mass, as a synthetic one)
  double mass = 0.0, volume = 0.0, mean = 0.0;
  for (const auto* r : rs) {
    mass += r->rock_mass, mean += r->loose_solid_fraction / double(rs.size());
    if (r->loose_solid_fraction > 0) volume += r->rock_mass / r->loose_solid_fraction;
  }
  const bool weighed = std::all_of(rs.begin(), rs.end(), [](const PistonDieResult* r) { return r->rock_mass > 0; });
  mat.loose_fraction = weighed && volume > 0 ? mass / volume : mean;
  // Every loop of a pouring starts from the same settled bed (deterministic), so the deepest one's loading branch
  // holds the others': each pouring's deepest loading branch, all of them in one fit.
  std::vector<double> s, p, D, loss;
  for (const auto* r : rs) {
    const PressLoop* deep = &r->loops.front();
    for (const auto& L : r->loops)
      if (L.s_reached > deep->s_reached) deep = &L;
    for (std::size_t k = 0; k < deep->s.size(); ++k)
      if (deep->phase[k] == 0) s.push_back(deep->s[k]), p.push_back(deep->p[k]);
    for (const auto& L : r->loops) D.push_back(L.s_reached), loss.push_back(L.loop_energy);
  }
  // The power law, or the law diverging at the solid's density (bed_compaction.hpp); the power law's fit beside it.
  mat.solid_divergence = law == PressureLaw::solid_divergence;
  const CompactionScale scale = compaction_scale(mat);
  m.pressure_fit = fit_power_law(s, p, kDieBedOnset, scale);
  m.power_fit = fit_power_law(s, p, kDieBedOnset);
  mat.modulus_Pa = m.pressure_fit.modulus, mat.exponent = m.pressure_fit.exponent;
  mat.max_compression = mat.solid_divergence ? diverging_compaction_limit(mat.loose_fraction)
                                             : solid_compaction_limit(mat.loose_fraction);
  mat.rebound = fit_rebound(mat.modulus_Pa, mat.exponent, D, loss, &m.rebound_rms, scale);
  fit_breakage(rs, m);
  return m;
}

}  // namespace

MaterialFit fit_flow_material(const PistonDieResult& r, PressureLaw law) { return fit_pourings({&r}, law); }

MaterialFit fit_flow_material(const std::vector<PistonDieResult>& pourings, PressureLaw law) {
  std::vector<const PistonDieResult*> rs;
  for (const auto& r : pourings) rs.push_back(&r);
  return fit_pourings(rs, law);
}

MaterialFit fit_flow_material(const std::vector<const PistonDieResult*>& pourings, PressureLaw law) {
  return fit_pourings(pourings, law);
}

double loop_peak_pressure(const PressLoop& L) {
  double peak = 0;
  for (double p : L.p) peak = std::max(peak, p);
  return peak;
}

double die_effective_lumps(const PistonDieResult& r) {
  std::vector<double> sieves;
  for (double mm : flow_sieves_mm()) sieves.push_back(mm * 1e-3);
  const Breakage classes(sieves, BreakageParams());
  const std::size_t K = sieves.size();
  if (r.feed_passing.size() != K) throw std::invalid_argument("die_effective_lumps: the feed PSD is not on the flow sieves");
  std::vector<double> kg, lump;
  for (std::size_t j = 0; j <= K; ++j) {
    const double share = (j == K ? 1.0 : r.feed_passing[j]) - (j == 0 ? 0.0 : r.feed_passing[j - 1]);
    kg.push_back(r.rock_mass * share);
    lump.push_back(lump_mass(classes.size(j), r.solid_density));
  }
  return effective_lumps(kg.data(), lump);
}

std::vector<double> common_depth_peaks(const std::vector<PistonDieResult>& pourings, double* s_max) {
  // the deepest s_max every pouring completed (one that blew up deeper kept its shallower loops)
  double common = 1e300;
  for (const auto& r : pourings) {
    if (r.loops.empty()) throw std::invalid_argument("common_depth_peaks: a pouring holds no load-unload loop");
    double deepest = 0.0;
    for (const auto& L : r.loops) deepest = std::max(deepest, L.s_max);
    common = std::min(common, deepest);
  }
  std::vector<double> peaks;
  for (const auto& r : pourings) {
    const PressLoop* deep = nullptr;
    for (const auto& L : r.loops)
      if (L.s_max <= common && (!deep || L.s_max > deep->s_max)) deep = &L;
    if (!deep || deep->s_max != common)
      throw std::invalid_argument("common_depth_peaks: the pourings were not pressed to the same s_max");
    peaks.push_back(loop_peak_pressure(*deep));
  }
  if (s_max) *s_max = pourings.empty() ? 0.0 : common;
  return peaks;
}

double lump_std_of_pourings(const std::vector<PistonDieResult>& pourings) {
  double n_eff = 0;
  for (const auto& r : pourings) n_eff += die_effective_lumps(r) / double(pourings.size());
  return lump_std_from_replicates(common_depth_peaks(pourings), n_eff);
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

MaterialFit fit_flow_material_lab(const std::vector<LabPoint>& pts) {
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
  MaterialFit m;
  auto& mat = m.material;
  std::vector<double> s, p, D, loss;
  bool unloaded = false;
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
    if (has_unload) {
      D.push_back(dmax), loss.push_back(path_integral(ls, lp));
      unloaded = true;
    }
  }
  m.pressure_fit = fit_power_law(s, p, 0.02);
  mat.modulus_Pa = m.pressure_fit.modulus, mat.exponent = m.pressure_fit.exponent;
  if (unloaded) mat.rebound = fit_rebound(mat.modulus_Pa, mat.exponent, D, loss, &m.rebound_rms);
  else m.comments.push_back("no unloading branch in the lab data: rebound default " + fmt("%g", mat.rebound));
  m.comments.push_back("loose_solid_fraction not in the lab data: default " + fmt("%g", mat.loose_fraction) +
                       "; so the power law, which needs no solid limit");
  m.power_fit = m.pressure_fit;
  mat.max_compression = solid_compaction_limit(mat.loose_fraction);
  m.breakage_note = "breakage not fitted (the lab data holds no PSD): defaults";
  return m;
}

void write_flow_material_yaml(const MaterialFit& m, const std::string& file,
                              const std::vector<std::string>& provenance) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("write_flow_material_yaml: cannot write '" + file + "'");
  for (const auto& l : provenance) out << "# " << l << "\n";
  for (const auto& l : m.comments) out << "# " << l << "\n";
  if (m.material.solid_divergence) {
    out << "# pressure fit: p = E u^n, u = s / (1 - s / s_solid), s_solid = 1 - loose = "
        << fmt("%.4f", solid_compaction_limit(m.material.loose_fraction)) << " (diverging at the solid's density), over "
        << m.pressure_fit.points << " loading points (s > " << fmt("%g", m.pressure_fit.s_min) << "), rms of ln p "
        << fmt("%.4f", m.pressure_fit.rms_log)
        << "; the power law p = E s^n over the same points: E " << fmt("%.6g", m.power_fit.modulus * 1e-6) << " MPa, n "
        << fmt("%.4f", m.power_fit.exponent) << ", rms of ln p " << fmt("%.4f", m.power_fit.rms_log) << "\n# rebound fit rms "
        << fmt("%.4g", m.rebound_rms * 1e-6) << " MPa (loop energies)\n";
  } else {
    out << "# pressure fit: p = E s^n over " << m.pressure_fit.points << " loading points (s > "
        << fmt("%g", m.pressure_fit.s_min) << "), rms of ln p "
        << fmt("%.4f", m.pressure_fit.rms_log) << "; rebound fit rms " << fmt("%.4g", m.rebound_rms * 1e-6)
        << " MPa (loop energies)\n";
  }
  out << "# " << m.breakage_note;
  if (!m.fitted.empty()) {
    out << "; fitted:";
    for (const auto& f : m.fitted) out << " " << f;
    out << " (rms " << fmt("%.2f", m.psd_rms_pct) << " % passing)";
  }
  out << "\n";
  const auto& mat = m.material;
  const auto& b = mat.breakage;
  out << "flow_material:\n";
  out << "  solid_density_kg_m3: " << fmt("%g", mat.solid_density) << "\n";
  out << "  loose_solid_fraction: " << fmt("%.4f", mat.loose_fraction) << "\n";
  out << "  pressure: {modulus_MPa: " << fmt("%.6g", mat.modulus_Pa * 1e-6) << ", exponent: " << fmt("%.4f", mat.exponent)
      << ", rebound: " << fmt("%.4f", mat.rebound) << ", max_compression: " << fmt("%.4f", mat.max_compression)
      << (mat.solid_divergence ? ", law: solid_divergence" : "") << "}\n";
  out << "  selection: {s_c: " << fmt("%.4f", b.s_c) << ", exponent: " << fmt("%.4f", b.m)
      << ", size_exponent: " << fmt("%.4f", b.q) << ", x_ref_mm: " << fmt("%g", b.x_ref * 1e3)
      << ", resolved_mm: " << fmt("%g", b.x_resolved * 1e3) << ", size_exponent_below: " << fmt("%g", b.q_below) << "}\n";
  out << "  progeny: {phi: " << fmt("%.4f", b.phi) << ", gamma: " << fmt("%.4f", b.gamma)
      << ", beta: " << fmt("%.4f", b.beta) << "}\n";
  if (!out) throw std::runtime_error("write_flow_material_yaml: writing '" + file + "' failed");
}

}  // namespace chamber
