#include "dem/revolution.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace dem {

TriMesh revolve_profile(const std::vector<ProfilePoint>& profile, int sectors, NormalSide side,
                        double phi0, const std::string& name) {
  const int np = static_cast<int>(profile.size());
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument("revolve_profile '" + name + "': " + what);
  };
  if (np < 2) bad("profile has " + std::to_string(np) + " points; accepted: >= 2 (z, r) points");
  if (sectors < 3) bad("sectors = " + std::to_string(sectors) + "; accepted: >= 3");
  for (int i = 0; i < np; ++i) {
    const auto& p = profile[i];
    if (!std::isfinite(p.z) || !std::isfinite(p.r) || p.r < 0.0)
      bad("point " + std::to_string(i) + " (z=" + std::to_string(p.z) + ", r=" + std::to_string(p.r) +
          "); accepted: finite z, r >= 0 (m)");
    if (p.r == 0.0 && i != 0 && i != np - 1)
      bad("interior point " + std::to_string(i) + " lies on the axis; accepted: r = 0 only at the ends");
    if (i > 0 && p.z == profile[i - 1].z && p.r == profile[i - 1].r)
      bad("points " + std::to_string(i - 1) + " and " + std::to_string(i) + " coincide");
  }
  if (np == 2 && profile[0].r == 0.0 && profile[1].r == 0.0) bad("both points on the axis");
  const double two_pi = 2.0 * 3.14159265358979323846;
  std::vector<Eigen::Vector3d> verts;
  std::vector<int> first(np);  // first vertex of ring i; an apex ring has one vertex
  for (int i = 0; i < np; ++i) {
    first[i] = static_cast<int>(verts.size());
    if (profile[i].r == 0.0) {
      verts.emplace_back(0.0, 0.0, profile[i].z);
      continue;
    }
    for (int j = 0; j < sectors; ++j) {
      const double phi = phi0 + two_pi * j / sectors;
      verts.emplace_back(profile[i].r * std::cos(phi), profile[i].r * std::sin(phi), profile[i].z);
    }
  }
  auto vid = [&](int i, int j) { return profile[i].r == 0.0 ? first[i] : first[i] + (j % sectors); };
  std::vector<Triangle> tris;
  tris.reserve(2 * (np - 1) * sectors);
  // Quads a=(i,j), b=(i,j+1), c=(i+1,j+1), d=(i+1,j) split along a-c; the side the normals face
  // is fixed after construction against the (dz, -dr) rule.
  for (int i = 0; i + 1 < np; ++i) {
    for (int j = 0; j < sectors; ++j) {
      const int a = vid(i, j), b = vid(i, j + 1), c = vid(i + 1, j + 1), d = vid(i + 1, j);
      if (a != b) tris.push_back({a, b, c});
      if (c != d) tris.push_back({a, c, d});
    }
  }
  TriMesh mesh(std::move(verts), std::move(tris), name);
  // Orientation check against the (dz, -dr) rule on the first triangle: flip if needed.
  const int t0 = 0;
  const Eigen::Vector3d c = mesh.centroid(t0);
  const Eigen::Vector3d n = mesh.normal(t0);
  // Segment of triangle 0 is segment 0 (a non-degenerate one always exists first).
  const double rising = profile.back().z >= profile.front().z ? 1.0 : -1.0;
  const double dz = rising * (profile[1].z - profile[0].z), dr = rising * (profile[1].r - profile[0].r);
  Eigen::Vector3d radial(c.x(), c.y(), 0.0);
  radial = radial.norm() > 0 ? radial.normalized() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d want = dz * radial + (-dr) * Eigen::Vector3d::UnitZ();
  const bool outward = n.dot(want) > 0.0;
  if (outward != (side == NormalSide::Outward)) mesh.flip_normals();
  return mesh;
}

std::vector<ProfilePoint> profile_points(const core::Profile& profile) {
  if (profile.z.size() != profile.r.size())
    throw std::invalid_argument("profile_points: " + std::to_string(profile.z.size()) + " z values and " +
                                std::to_string(profile.r.size()) + " r values; accepted: equal counts");
  std::vector<ProfilePoint> out;
  for (size_t i = 0; i < profile.z.size(); ++i) out.push_back({profile.z[i], profile.r[i]});
  return out;
}

std::vector<ProfilePoint> refine_profile(const std::vector<ProfilePoint>& profile, double max_len,
                                         const std::vector<double>& z_cuts) {
  if (profile.size() < 2)
    throw std::invalid_argument("refine_profile: " + std::to_string(profile.size()) +
                                " points; accepted: >= 2");
  std::vector<ProfilePoint> out{profile.front()};
  for (size_t i = 0; i + 1 < profile.size(); ++i) {
    const ProfilePoint a = profile[i], b = profile[i + 1];
    // Parameters in (0, 1) where the segment crosses a cut.
    std::vector<double> ts;
    for (double zc : z_cuts) {
      if (a.z == b.z) break;
      const double t = (zc - a.z) / (b.z - a.z);
      if (t > 1e-9 && t < 1.0 - 1e-9) ts.push_back(t);
    }
    ts.push_back(1.0);
    std::sort(ts.begin(), ts.end());
    double t0 = 0.0;
    for (double t1 : ts) {
      const double len = std::hypot((t1 - t0) * (b.z - a.z), (t1 - t0) * (b.r - a.r));
      const int pieces = max_len > 0.0 ? std::max(1, static_cast<int>(std::ceil(len / max_len - 1e-9))) : 1;
      for (int k = 1; k <= pieces; ++k) {
        const double t = t0 + (t1 - t0) * k / pieces;
        if (t1 == 1.0 && k == pieces) out.push_back(b);  // exact end point
        else out.push_back({a.z + t * (b.z - a.z), a.r + t * (b.r - a.r)});
      }
      t0 = t1;
    }
  }
  return out;
}

}  // namespace dem
