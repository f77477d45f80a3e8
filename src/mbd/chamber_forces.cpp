#include "mbd/chamber_forces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mbd/contact_law.hpp"

namespace mbd {

namespace {
constexpr double kPi = 3.14159265358979323846;

// Effective mass of the free pair for a relative motion along unit t at arms r2 (mantle) and r1.
double effective_mass(const RigidKinematics& a, const Eigen::Vector3d& ra, const RigidKinematics& b,
                      const Eigen::Vector3d& rb, const Eigen::Vector3d& t) {
  const Eigen::Vector3d ca = ra.cross(t), cb = rb.cross(t);
  const double inv = a.inv_mass + ca.dot(a.inv_inertia_world * ca) + b.inv_mass + cb.dot(b.inv_inertia_world * cb);
  return inv > 0 ? 1.0 / inv : 0.0;
}
}  // namespace

ChamberForces::ChamberForces(const MechanismParams& p) : p_(p) {
  const auto& m = p.chamber.mantle;
  const double L = m.length();
  const int na = p.sampling.azimuth, ng = p.sampling.generator;
  for (int j = 0; j < ng; ++j) {
    const double s = (j + 0.5) * L / ng;
    const Eigen::Vector2d q = m.point_at(s);  // (z, r)
    Eigen::Vector2d n;
    const double grest = core::signed_distance_inside(p.chamber.concave, q, &n);
    for (int k = 0; k < na; ++k) {
      const double phi = 2.0 * kPi * k / na;
      Sample smp;
      smp.local = Eigen::Vector3d(q.y() * std::cos(phi), q.y() * std::sin(phi), q.x());
      smp.area = 2.0 * kPi * q.y() * (L / ng) / na;
      smp.g_ref = p.bed.engage_ratio * std::max(grest, 1e-6);
      bed_samples_.push_back(smp);
    }
  }
  contact_z_ = m.z;
  contact_r_ = m.r;
}

double ChamberForces::gap(const RigidKinematics& mantle, const RigidKinematics& concave,
                          const Eigen::Vector3d& local, Eigen::Vector3d* world_point,
                          Eigen::Vector3d* normal) const {
  const Eigen::Vector3d P = mantle.x + mantle.R * (mantle.liner_origin + local);
  const Eigen::Vector3d q = concave.R.transpose() * (P - concave.x) - concave.liner_origin;
  const double rc = std::hypot(q.x(), q.y());
  Eigen::Vector2d nzr;
  const double g = core::signed_distance_inside(p_.chamber.concave, Eigen::Vector2d(q.z(), rc), &nzr);
  if (world_point) *world_point = P;
  if (normal) {
    const double cx = rc > 1e-12 ? q.x() / rc : 1.0, cy = rc > 1e-12 ? q.y() / rc : 0.0;
    *normal = concave.R * Eigen::Vector3d(nzr.y() * cx, nzr.y() * cy, nzr.x());
  }
  return g;
}

ChamberForceResult ChamberForces::compute(const RigidKinematics& M, const RigidKinematics& C, bool bed,
                                          double dt) const {
  ChamberForceResult out;
  out.min_gap = std::numeric_limits<double>::infinity();

  // ---- Cone contact at the closest approach (Eq. 11, 13-15) ----
  const int na = p_.sampling.azimuth;
  for (std::size_t iv = 0; iv < contact_z_.size(); ++iv) {
    const double z = contact_z_[iv], r = contact_r_[iv];
    auto local_at = [&](double phi) { return Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z); };
    int kbest = 0;
    double gbest = std::numeric_limits<double>::infinity();
    auto& gs = gs_;
    gs.resize(na);
    for (int k = 0; k < na; ++k) {
      gs[k] = gap(M, C, local_at(2.0 * kPi * k / na), nullptr, nullptr);
      if (gs[k] < gbest) gbest = gs[k], kbest = k;
    }
    // Parabola through the best sample and its neighbours: refined closest azimuth.
    const double gm = gs[(kbest + na - 1) % na], g0 = gs[kbest], gp = gs[(kbest + 1) % na];
    const double den = gm - 2.0 * g0 + gp;
    double off = den > 1e-15 ? 0.5 * (gm - gp) / den : 0.0;
    off = std::clamp(off, -0.5, 0.5);
    const double phi = 2.0 * kPi * (kbest + off) / na;
    Eigen::Vector3d P, n;
    const double g = gap(M, C, local_at(phi), &P, &n);
    const double gmin = std::min(g, g0);
    out.min_gap = std::min(out.min_gap, gmin);
    if (g < 0.0) {
      const Eigen::Vector3d r2 = P - M.x, r1 = P - C.x;
      const Eigen::Vector3d v2 = M.v + M.w.cross(r2), v1 = C.v + C.w.cross(r1);
      const Eigen::Vector3d vrel = v2 - v1;   // mantle w.r.t. concave
      const double d = -g, d_dot = vrel.dot(n);  // indentation grows when the mantle moves outward
      const auto& cp = p_.contact;
      const double fel = cp.k * std::pow(d, cp.h1);
      const double fn = normal_force_eq11(cp, d, d_dot);
      const Eigen::Vector3d vt = vrel - vrel.dot(n) * n;
      const double vtn = vt.norm();
      Eigen::Vector3d ft = Eigen::Vector3d::Zero();
      if (vtn > 1e-12) {
        const Eigen::Vector3d t = vt / vtn;
        double mag = friction_coefficient_eq14(vtn, cp.mu_s, cp.mu_d, cp.v_s, cp.v_d) * fn;  // <= 0
        const double cap = effective_mass(M, r2, C, r1, t) * vtn / dt;  // stick: stop within one step
        mag = std::max(mag, -cap);
        ft = mag * t;
      }
      // Normal force pushes the mantle toward the axis (-n); elastic part conservative.
      const Eigen::Vector3d f_el = -fel * n;
      const Eigen::Vector3d f_d = -(fn - fel) * n + ft;  // Eq. 11 damping (and the clip at 0) + friction
      out.contact_on_mantle.add(r2, f_el, f_d);
      out.contact_on_concave.add(r1, -f_el, -f_d);
      out.contact_normal_force += fn;
      out.contact_potential += cp.k * std::pow(d, cp.h1 + 1.0) / (cp.h1 + 1.0);
    }
  }

  // ---- Equivalent material bed ----
  if (bed) {
    const auto& b = p_.bed;
    auto& hits = hits_;
    hits.clear();
    for (const auto& s : bed_samples_) {
      Eigen::Vector3d P, n;
      const double g = gap(M, C, s.local, &P, &n);
      if (g >= s.g_ref) continue;
      const Eigen::Vector3d v2 = M.v + M.w.cross(P - M.x), v1 = C.v + C.w.cross(P - C.x);
      const double g_dot = (v1 - v2).dot(n);
      hits.push_back({P, n, 1.0 - std::max(g, 0.0) / s.g_ref, -g_dot / s.g_ref, &s});
    }
    const int active = static_cast<int>(hits.size());
    for (int i = 0; i < active; ++i) {
      const Hit& h = hits[i];
      const double A = h.s->area;
      const double p_el = b.modulus_Pa * std::pow(h.e, b.exponent);
      const double p_v = h.e_dot > 0 ? b.viscosity_Pa_s * h.e_dot : 0.0;  // crushing: closing only
      const double fn_el = A * p_el, fn_v = A * p_v;
      const Eigen::Vector3d r2 = h.P - M.x, r1 = h.P - C.x;
      const Eigen::Vector3d vrel = (M.v + M.w.cross(r2)) - (C.v + C.w.cross(r1));
      const Eigen::Vector3d vt = vrel - vrel.dot(h.n) * h.n;
      const double vtn = vt.norm();
      Eigen::Vector3d ft = Eigen::Vector3d::Zero();
      if (vtn > 1e-12 && b.friction > 0) {
        const Eigen::Vector3d t = vt / vtn;
        double mag = friction_coefficient_eq14(vtn, b.friction, b.friction, b.v_s, b.v_d) * (fn_el + fn_v);
        const double cap = effective_mass(M, r2, C, r1, t) * vtn / dt / active;
        mag = std::max(mag, -cap);
        ft = mag * t;
      }
      const Eigen::Vector3d f_el = -fn_el * h.n, f_d = -fn_v * h.n + ft;
      out.bed_on_mantle.add(r2, f_el, f_d);
      out.bed_on_concave.add(r1, -f_el, -f_d);
      out.bed_normal_force += fn_el + fn_v;
      out.bed_potential += A * h.s->g_ref * b.modulus_Pa * std::pow(h.e, b.exponent + 1.0) / (b.exponent + 1.0);
    }
  }
  auto sum = [](const Wrench& a, const Wrench& b) {
    Wrench w;
    w.f_cons = a.f_cons + b.f_cons;
    w.t_cons = a.t_cons + b.t_cons;
    w.f_diss = a.f_diss + b.f_diss;
    w.t_diss = a.t_diss + b.t_diss;
    return w;
  };
  out.on_mantle = sum(out.contact_on_mantle, out.bed_on_mantle);
  out.on_concave = sum(out.contact_on_concave, out.bed_on_concave);
  return out;
}

}  // namespace mbd
