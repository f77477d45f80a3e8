#include "core/chamber_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "core/chamber_geometry_schema.hpp"
#include "core/units.hpp"

namespace core {

double Profile::radius_at(double zq) const {
  const std::size_t n = z.size();
  if (n == 0) return 0.0;
  if (n == 1) return r[0];
  const bool up = z[n - 1] > z[0];
  const double zlo = up ? z[0] : z[n - 1], zhi = up ? z[n - 1] : z[0];
  if (zq <= zlo) return up ? r[0] : r[n - 1];
  if (zq >= zhi) return up ? r[n - 1] : r[0];
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double a = z[i], b = z[i + 1];
    if ((zq - a) * (zq - b) <= 0.0) {
      const double t = (zq - a) / (b - a);
      return r[i] + t * (r[i + 1] - r[i]);
    }
  }
  return r[n - 1];
}

double Profile::length() const {
  double s = 0;
  for (std::size_t i = 0; i + 1 < z.size(); ++i) s += std::hypot(z[i + 1] - z[i], r[i + 1] - r[i]);
  return s;
}

Eigen::Vector2d Profile::point_at(double s, Eigen::Vector2d* tangent) const {
  const std::size_t n = z.size();
  double acc = 0;
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const double L = std::hypot(z[i + 1] - z[i], r[i + 1] - r[i]);
    if (s <= acc + L || i + 2 == n) {
      const double t = L > 0 ? std::clamp((s - acc) / L, 0.0, 1.0) : 0.0;
      if (tangent) *tangent = Eigen::Vector2d(z[i + 1] - z[i], r[i + 1] - r[i]) / (L > 0 ? L : 1.0);
      return {z[i] + t * (z[i + 1] - z[i]), r[i] + t * (r[i + 1] - r[i])};
    }
    acc += L;
  }
  if (tangent) *tangent = Eigen::Vector2d(1, 0);
  return {z[0], r[0]};
}

double signed_distance_inside(const Profile& p, const Eigen::Vector2d& q, Eigen::Vector2d* normal_zr) {
  double best = std::numeric_limits<double>::infinity();
  Eigen::Vector2d best_n(0, 1);
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    const Eigen::Vector2d a(p.z[i], p.r[i]), b(p.z[i + 1], p.r[i + 1]);
    const Eigen::Vector2d ab = b - a;
    const double t = std::clamp((q - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
    const double d = (a + t * ab - q).norm();
    if (d < best) {
      best = d;
      // Outward (away from the axis) unit normal of the segment in the (z, r) plane.
      Eigen::Vector2d n(-ab.y(), ab.x());
      if (n.y() < 0) n = -n;
      best_n = n.normalized();
    }
  }
  if (normal_zr) *normal_zr = best_n;
  const bool inside = q.y() < p.radius_at(q.x());
  return inside ? best : -best;
}

ProfileDistance::ProfileDistance(const Profile& c) {
  for (std::size_t i = 0; i + 1 < c.size(); ++i) {
    Seg sg;
    sg.az = c.z[i];
    sg.ar = c.r[i];
    sg.dz = c.z[i + 1] - c.z[i];
    sg.dr = c.r[i + 1] - c.r[i];
    sg.inv_len2 = 1.0 / (sg.dz * sg.dz + sg.dr * sg.dr);
    Eigen::Vector2d n(-sg.dr, sg.dz);
    if (n.y() < 0) n = -n;
    n.normalize();
    sg.nz = n.x();
    sg.nr = n.y();
    segs_.push_back(sg);
  }
}

double ProfileDistance::signed_distance(double z, double r, Eigen::Vector2d* nzr) const {
  double best = std::numeric_limits<double>::infinity(), side = 0;
  int ib = 0;
  bool at_end = false;
  for (std::size_t i = 0; i < segs_.size(); ++i) {
    const Seg& s = segs_[i];
    const double t = ((z - s.az) * s.dz + (r - s.ar) * s.dr) * s.inv_len2;
    double d2, sd;
    bool end = false;
    if (t > 0.0 && t < 1.0) {
      sd = (s.az - z) * s.nz + (s.ar - r) * s.nr;
      d2 = sd * sd;
    } else {
      const double tc = t <= 0.0 ? 0.0 : 1.0;
      const double ez = s.az + tc * s.dz - z, er = s.ar + tc * s.dr - r;
      d2 = ez * ez + er * er;
      sd = ez * s.nz + er * s.nr;
      end = true;
    }
    if (d2 < best) best = d2, ib = static_cast<int>(i), side = sd, at_end = end;
  }
  if (nzr) *nzr = Eigen::Vector2d(segs_[ib].nz, segs_[ib].nr);
  const double d = at_end ? std::sqrt(best) : std::fabs(side);
  return side >= 0 ? d : -d;
}

void ProfileDistance::signed_distances(std::size_t n, const double* z, const double* r, double* d, int* seg) const {
  constexpr std::size_t kBlock = 64;  // points per block: the best so far stays on the stack
  double best[kBlock], side[kBlock], end[kBlock], root[kBlock], ib[kBlock];
  for (std::size_t k0 = 0; k0 < n; k0 += kBlock) {
    const std::size_t m = std::min(kBlock, n - k0);
    const double *zk = z + k0, *rk = r + k0;
    for (std::size_t j = 0; j < m; ++j) best[j] = std::numeric_limits<double>::infinity(), side[j] = end[j] = ib[j] = 0;
    for (std::size_t i = 0; i < segs_.size(); ++i) {  // as signed_distance, without branches (& not &&: no jumps)
      const Seg s = segs_[i];
      const double si = static_cast<double>(i);
      for (std::size_t j = 0; j < m; ++j) {
        const double t = ((zk[j] - s.az) * s.dz + (rk[j] - s.ar) * s.dr) * s.inv_len2;
        const bool inner = (t > 0.0) & (t < 1.0);
        const double tc = t <= 0.0 ? 0.0 : 1.0;
        const double ez = s.az + tc * s.dz - zk[j], er = s.ar + tc * s.dr - rk[j];
        const double sd_in = (s.az - zk[j]) * s.nz + (s.ar - rk[j]) * s.nr, sd_end = ez * s.nz + er * s.nr;
        const double d2_in = sd_in * sd_in, d2_end = ez * ez + er * er;  // both, then a select: no jumps
        const double d2 = inner ? d2_in : d2_end, sd = inner ? sd_in : sd_end;
        const bool closer = d2 < best[j];
        best[j] = closer ? d2 : best[j];
        side[j] = closer ? sd : side[j];
        end[j] = closer ? (inner ? 0.0 : 1.0) : end[j];
        ib[j] = closer ? si : ib[j];
      }
    }
    for (std::size_t j = 0; j < m; ++j) root[j] = std::sqrt(best[j]);  // vectorises (-fno-math-errno, CMakeLists.txt)
    for (std::size_t j = 0; j < m; ++j) {
      const double dist = end[j] != 0.0 ? root[j] : std::fabs(side[j]);
      d[k0 + j] = side[j] >= 0 ? dist : -dist;
      seg[k0 + j] = static_cast<int>(ib[j]);
    }
  }
}

ConcaveCells concave_cells(const Profile& concave, double z_lo, double z_hi, int bands, int sectors) {
  constexpr double kPi = 3.14159265358979323846;
  ConcaveCells c;
  c.z_lo = z_lo;
  c.dz = (z_hi - z_lo) / bands;
  for (int b = 0; b < bands; ++b) {
    const double z0 = z_lo + b * c.dz, z1 = z0 + c.dz, r0 = concave.radius_at(z0), r1 = concave.radius_at(z1);
    c.z_mid.push_back(0.5 * (z0 + z1));
    c.r_mid.push_back(concave.radius_at(c.z_mid.back()));
    c.area.push_back(2 * kPi * 0.5 * (r0 + r1) * std::hypot(c.dz, r1 - r0) / sectors);
  }
  for (int s = 0; s < sectors; ++s) {
    const double a = (s + 0.5) * 2 * kPi / sectors;
    c.cos.push_back(std::cos(a));
    c.sin.push_back(std::sin(a));
  }
  return c;
}

static void check_profile(const Profile& p, const std::string& name, const std::string& zkey,
                          const std::string& rkey, const ConfigNode* node) {
  auto bad = [&](const std::string& key, const std::string& what) {
    if (node) node->fail(key, what);
    throw std::invalid_argument("chamber " + name + " (" + key + "): " + what);
  };
  if (p.z.size() != p.r.size()) bad(rkey, "must have as many values as " + zkey);
  if (p.z.size() < 2) bad(zkey, "needs at least 2 points");
  const double dir = p.z[1] - p.z[0];
  for (std::size_t i = 0; i + 1 < p.z.size(); ++i) {
    if ((p.z[i + 1] - p.z[i]) * dir <= 0) bad(zkey, "must be strictly monotonic (top to bottom or bottom to top)");
  }
  for (double r : p.r)
    if (!(r > 0)) bad(rkey, "radii must be > 0");
}

static void check_gap(const ChamberGeometry& g, const ConfigNode* node) {
  // Mantle must lie inside the concave over the common height (untilted assembly).
  for (std::size_t i = 0; i < g.mantle.size(); ++i) {
    const double zq = g.mantle.z[i];
    const double rc = g.concave.radius_at(zq);
    if (!(g.mantle.r[i] < rc)) {
      std::ostringstream s;
      s << "mantle point z=" << zq * 1e3 << " mm r=" << g.mantle.r[i] * 1e3
        << " mm is not inside the concave (r=" << rc * 1e3 << " mm there); the gap must be > 0";
      if (node) node->fail("mantle_r_mm", s.str());
      throw std::invalid_argument("chamber: " + s.str());
    }
  }
}

void validate_chamber_geometry(const ChamberGeometry& g) {
  check_profile(g.mantle, "mantle", "mantle_z_mm", "mantle_r_mm", nullptr);
  check_profile(g.concave, "concave", "concave_z_mm", "concave_r_mm", nullptr);
  check_gap(g, nullptr);
}

const Schema<ChamberGeometry>& chamber_geometry_schema() {
  using G = ChamberGeometry;
  static const Schema<ChamberGeometry> s = [] {
    Schema<ChamberGeometry> k;
    k.numbers("mantle_z_mm", "mm", units::mm, -5000, 5000, [](G& g) -> std::vector<double>& { return g.mantle.z; },
              "mantle profile heights (liner frame, origin O1), strictly monotonic", true)
        .numbers("mantle_r_mm", "mm", units::mm, 1, 5000, [](G& g) -> std::vector<double>& { return g.mantle.r; },
                 "mantle radii at those heights", true)
        .numbers("concave_z_mm", "mm", units::mm, -5000, 5000, [](G& g) -> std::vector<double>& { return g.concave.z; },
                 "concave profile heights, strictly monotonic", true)
        .numbers("concave_r_mm", "mm", units::mm, 1, 5000, [](G& g) -> std::vector<double>& { return g.concave.r; },
                 "concave radii at those heights; the concave encloses the mantle", true,
                 [](const ConfigNode& node, const std::string&, G& g) {
                   check_profile(g.mantle, "mantle", "mantle_z_mm", "mantle_r_mm", &node);
                   check_profile(g.concave, "concave", "concave_z_mm", "concave_r_mm", &node);
                   check_gap(g, &node);
                 });
    return k;
  }();
  return s;
}

ChamberGeometry load_chamber_geometry(const ConfigNode& node) {
  ChamberGeometry g;
  chamber_geometry_schema().read(node, g);
  return g;
}

}  // namespace core
