#include "mbd/chamber_forces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

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

ChamberForces::ChamberForces(const MechanismParams& p) : concave_(p.chamber.concave), p_(p) {
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
  contact_k_.assign(m.size(), 0);
  const auto& c = p.chamber.concave;
  for (int k = 0; k < na; ++k) cos_.push_back(std::cos(2.0 * kPi * k / na)), sin_.push_back(std::sin(2.0 * kPi * k / na));
  contact_rest_gap_ = std::numeric_limits<double>::infinity();
  contact_reach_ = 0;
  for (std::size_t i = 0; i < m.size(); ++i) {
    contact_rest_gap_ = std::min(contact_rest_gap_, core::signed_distance_inside(c, Eigen::Vector2d(m.z[i], m.r[i]), nullptr));
    contact_reach_ = std::max(contact_reach_, std::hypot(m.z[i], m.r[i]));
  }
}

void ChamberForces::set_contact_search_state(const std::vector<int>& k) {
  if (k.size() != contact_k_.size())
    throw std::invalid_argument("ChamberForces: contact search state has " + std::to_string(k.size()) +
                                " entries, the mantle profile " + std::to_string(contact_k_.size()) + " vertices");
  for (int v : k)
    if (v < 0 || v >= p_.sampling.azimuth)
      throw std::invalid_argument("ChamberForces: contact search sample " + std::to_string(v) + " outside [0, " +
                                  std::to_string(p_.sampling.azimuth) + ")");
  contact_k_ = k;
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
                                          double dt, const BedState* state, BedState* next) const {
  ChamberForceResult out;
  out.min_gap = std::numeric_limits<double>::infinity();
  // Mantle liner frame -> concave liner frame: q = A l + b.
  const Eigen::Matrix3d A = C.R.transpose() * M.R;
  const Eigen::Vector3d b = C.R.transpose() * (M.x + M.R * M.liner_origin - C.x) - C.liner_origin;
  auto fast_gap = [&](const Eigen::Vector3d& l, Eigen::Vector3d* q_out, Eigen::Vector2d* nzr) {
    const Eigen::Vector3d q = A * l + b;
    if (q_out) *q_out = q;
    const double rc = std::sqrt(q.x() * q.x() + q.y() * q.y());
    return concave_.signed_distance(q.z(), rc, nzr);
  };
  auto world_of = [&](const Eigen::Vector3d& q, const Eigen::Vector2d& nzr, Eigen::Vector3d* P, Eigen::Vector3d* n) {
    *P = C.x + C.R * (q + C.liner_origin);
    const double rc = std::sqrt(q.x() * q.x() + q.y() * q.y());
    const double cx = rc > 1e-12 ? q.x() / rc : 1.0, cy = rc > 1e-12 ? q.y() / rc : 0.0;
    *n = C.R * Eigen::Vector3d(nzr.y() * cx, nzr.y() * cy, nzr.x());
  };

  // ---- Cone contact at the closest approach (Eq. 11, 13-15) ----
  // Any mantle point l moves (relative to the concave, from the untilted rest) by at most
  // |A - I| |l| + |b|; where that is below the rest gap of the profile vertices the cones cannot touch.
  const double rot_bound = (A - Eigen::Matrix3d::Identity()).norm();  // Frobenius >= spectral norm
  const double disp_bound = rot_bound * contact_reach_ + b.norm();
  out.min_gap = contact_rest_gap_ - disp_bound;  // lower bound, refined below when the cones may touch
  const int na = p_.sampling.azimuth;
  if (disp_bound >= contact_rest_gap_) {
    out.min_gap = std::numeric_limits<double>::infinity();
    for (std::size_t iv = 0; iv < contact_z_.size(); ++iv) {
      const double z = contact_z_[iv], r = contact_r_[iv];
      auto local_at = [&](double phi) { return Eigen::Vector3d(r * std::cos(phi), r * std::sin(phi), z); };
      // The gap of a tilted circle against a cone of revolution has one minimum in azimuth: walk downhill
      // from the last step's best sample (a few evaluations instead of all `na`).
      auto g_at = [&](int k) { return fast_gap(Eigen::Vector3d(r * cos_[k], r * sin_[k], z), nullptr, nullptr); };
      int kbest = contact_k_[iv];
      double g0 = g_at(kbest);
      double gm = g_at((kbest + na - 1) % na), gp = g_at((kbest + 1) % na);
      for (int walk = 0; walk < na && (gm < g0 || gp < g0); ++walk) {
        if (gm < gp) {
          kbest = (kbest + na - 1) % na;
          gp = g0, g0 = gm, gm = g_at((kbest + na - 1) % na);
        } else {
          kbest = (kbest + 1) % na;
          gm = g0, g0 = gp, gp = g_at((kbest + 1) % na);
        }
      }
      contact_k_[iv] = kbest;
      // Parabola through the best sample and its neighbours: refined closest azimuth.
      const double den = gm - 2.0 * g0 + gp;
      double off = den > 1e-15 ? 0.5 * (gm - gp) / den : 0.0;
      off = std::clamp(off, -0.5, 0.5);
      const double phi = 2.0 * kPi * (kbest + off) / na;
      Eigen::Vector3d q, P, n;
      Eigen::Vector2d nzr;
      const double g = fast_gap(local_at(phi), &q, &nzr);
      out.min_gap = std::min(out.min_gap, std::min(g, g0));
      if (g < 0.0) {
        world_of(q, nzr, &P, &n);
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
        // Normal force pushes the mantle toward the axis (-n); the elastic part is conservative.
        const Eigen::Vector3d f_el = -fel * n;
        const Eigen::Vector3d f_d = -(fn - fel) * n + ft;  // Eq. 11 damping (and the clip at 0) + friction
        out.contact_on_mantle.add(r2, f_el, f_d);
        out.contact_on_concave.add(r1, -f_el, -f_d);
        out.contact_normal_force += fn;
        out.contact_potential += cp.k * std::pow(d, cp.h1 + 1.0) / (cp.h1 + 1.0);
      }
    }
  }

  // ---- Equivalent material bed ----
  if (bed) {
    const auto& bp = p_.bed;
    const bool hyst = bp.law == BedLaw::Hysteretic;
    if (hyst && (!state || state->size() != bed_samples_.size()))
      throw std::logic_error("ChamberForces: the hysteretic bed needs its state (initial_bed_state())");
    if (hyst && next) next->resize(bed_samples_.size());
    auto& hits = hits_;
    hits.clear();
    for (std::size_t k = 0; k < bed_samples_.size(); ++k) {
      const Sample& s = bed_samples_[k];
      Eigen::Vector3d q, P, n;
      Eigen::Vector2d nzr;
      const double g = fast_gap(s.local, &q, &nzr);
      if (g >= s.g_ref) {
        if (hyst && next) (*next)[k] = BedCell{};  // open beyond the reference gap: loose bed
        continue;
      }
      world_of(q, nzr, &P, &n);
      const Eigen::Vector3d v2 = M.v + M.w.cross(P - M.x), v1 = C.v + C.w.cross(P - C.x);
      const double g_dot = (v1 - v2).dot(n);
      hits.push_back({P, n, 1.0 - std::max(g, 0.0) / s.g_ref, -g_dot / s.g_ref, &s, k});
    }
    const int active = static_cast<int>(hits.size());
    const double inv_I2 = M.inv_inertia_world.norm(), inv_I1 = C.inv_inertia_world.norm();  // >= largest eigenvalue
    for (int i = 0; i < active; ++i) {
      const Hit& h = hits[i];
      const double A = h.s->area;
      BedPressure bpr;
      if (hyst) {
        BedCell c = (*state)[h.k];
        bpr = bed_hysteretic(c, h.e, bp.modulus_Pa, bp.exponent, bp.rebound);
        if (next) (*next)[h.k] = c;
      } else {
        bpr = bed_elastic(h.e, bp.modulus_Pa, bp.exponent);
      }
      const double p_el = bpr.p;
      const double fade = std::min(1.0, h.e / 0.05);
      const double p_v = h.e_dot > 0 ? bp.viscosity_Pa_s * h.e_dot * fade : 0.0;
      const double fn_el = A * p_el, fn_v = A * p_v;
      const Eigen::Vector3d r2 = h.P - M.x, r1 = h.P - C.x;
      const Eigen::Vector3d vrel = (M.v + M.w.cross(r2)) - (C.v + C.w.cross(r1));
      const Eigen::Vector3d vt = vrel - vrel.dot(h.n) * h.n;
      const double vtn = vt.norm();
      Eigen::Vector3d ft = Eigen::Vector3d::Zero();
      if (vtn > 1e-12 && bp.friction > 0) {
        const Eigen::Vector3d t = vt / vtn;
        double mag = friction_coefficient_eq14(vtn, bp.friction, bp.friction, bp.v_s, bp.v_d) * (fn_el + fn_v);
        // Cheap lower bound of the pair's effective mass (largest inverse inertias): stick regime.
        const double inv = M.inv_mass + r2.squaredNorm() * inv_I2 + C.inv_mass + r1.squaredNorm() * inv_I1;
        const double cap = vtn / (inv * dt * active);
        mag = std::max(mag, -cap);
        ft = mag * t;
      }
      // The hysteretic force is path dependent: booked as dissipative, its stored part via bed_potential.
      const Eigen::Vector3d f_el = hyst ? Eigen::Vector3d::Zero() : Eigen::Vector3d(-fn_el * h.n);
      const Eigen::Vector3d f_d = -(fn_v + (hyst ? fn_el : 0.0)) * h.n + ft;
      out.bed_on_mantle.add(r2, f_el, f_d);
      out.bed_on_concave.add(r1, -f_el, -f_d);
      out.bed_normal_force += fn_el + fn_v;
      out.bed_potential += A * h.s->g_ref * bpr.stored;
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
