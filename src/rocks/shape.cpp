#include "rocks/shape.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "core/units.hpp"
#include "rocks/rng.hpp"

namespace rocks {

using core::units::kPi;

double TriMesh::volume() const {
  double v = 0.0;
  for (const auto& t : triangles)
    v += vertices[t[0]].dot(vertices[t[1]].cross(vertices[t[2]]));
  return v / 6.0;
}

double TriMesh::area() const {
  double a = 0.0;
  for (const auto& t : triangles)
    a += 0.5 * (vertices[t[1]] - vertices[t[0]]).cross(vertices[t[2]] - vertices[t[0]]).norm();
  return a;
}

Vec3 TriMesh::min_corner() const {
  Vec3 m = Vec3::Constant(1e300);
  for (const auto& v : vertices) m = m.cwiseMin(v);
  return m;
}

Vec3 TriMesh::max_corner() const {
  Vec3 m = Vec3::Constant(-1e300);
  for (const auto& v : vertices) m = m.cwiseMax(v);
  return m;
}

// ---------------------------------------------------------------- cylinder
CylinderShape::CylinderShape(double diameter, double length, int segments)
    : radius_(0.5 * diameter), length_(length), segments_(segments) {
  if (!(diameter > 0.0) || !(length > 0.0))
    throw std::invalid_argument("CylinderShape: diameter and length must be > 0");
  if (segments < 8) throw std::invalid_argument("CylinderShape: segments must be >= 8");
  name_ = "cylinder_" + std::to_string(static_cast<int>(std::lround(diameter * 1e3))) + "x" +
          std::to_string(static_cast<int>(std::lround(length * 1e3)));
}

double CylinderShape::clearance(const Vec3& p) const {
  const double radial = radius_ - std::hypot(p.x(), p.z());
  const double axial = 0.5 * length_ - std::abs(p.y());
  return std::min(radial, axial);
}

Vec3 CylinderShape::push_inside(const Vec3& p, double r) const {
  Vec3 q = p;
  const double lim = std::max(0.0, 0.5 * length_ - r);
  q.y() = std::clamp(q.y(), -lim, lim);
  const double rho = std::hypot(q.x(), q.z());
  const double rmax = std::max(0.0, radius_ - r);
  if (rho > rmax && rho > 0.0) {
    q.x() *= rmax / rho;
    q.z() *= rmax / rho;
  }
  return q;
}

double CylinderShape::volume() const { return kPi * radius_ * radius_ * length_; }
Vec3 CylinderShape::min_corner() const { return Vec3(-radius_, -0.5 * length_, -radius_); }
Vec3 CylinderShape::max_corner() const { return Vec3(radius_, 0.5 * length_, radius_); }

TriMesh CylinderShape::mesh() const {
  TriMesh m;
  const int n = segments_;
  const double h = 0.5 * length_;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    m.vertices.emplace_back(radius_ * std::cos(a), -h, radius_ * std::sin(a));
    m.vertices.emplace_back(radius_ * std::cos(a), h, radius_ * std::sin(a));
  }
  const int c0 = static_cast<int>(m.vertices.size());
  m.vertices.emplace_back(0.0, -h, 0.0);
  m.vertices.emplace_back(0.0, h, 0.0);
  for (int k = 0; k < n; ++k) {
    const int a0 = 2 * k, a1 = 2 * k + 1, b0 = 2 * ((k + 1) % n), b1 = b0 + 1;
    // side: outward normal is radial; (x,z) circle with y axis: orientation checked by volume()
    m.triangles.emplace_back(a0, a1, b1);
    m.triangles.emplace_back(a0, b1, b0);
    m.triangles.emplace_back(c0, a0, b0);      // bottom (y = -h)
    m.triangles.emplace_back(c0 + 1, b1, a1);  // top (y = +h)
  }
  if (m.volume() < 0.0)
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

// ---------------------------------------------------------------- polyhedron
namespace {
// Vertices of the polytope (all feasible triple-plane intersections), faces fan-triangulated.
TriMesh polytope_mesh(const std::vector<Vec3>& n, const std::vector<double>& d) {
  const int k = static_cast<int>(n.size());
  double scale = 0.0;
  for (double x : d) scale = std::max(scale, x);
  const double eps = 1e-9 * scale;
  TriMesh m;
  std::vector<std::vector<int>> on_face(k);
  for (int a = 0; a < k; ++a)
    for (int b = a + 1; b < k; ++b)
      for (int c = b + 1; c < k; ++c) {
        Eigen::Matrix3d A;
        A.row(0) = n[a];
        A.row(1) = n[b];
        A.row(2) = n[c];
        if (std::abs(A.determinant()) < 1e-10) continue;
        const Vec3 p = A.partialPivLu().solve(Vec3(d[a], d[b], d[c]));
        bool ok = true;
        for (int f = 0; f < k && ok; ++f) ok = n[f].dot(p) <= d[f] + eps;
        if (!ok) continue;
        int id = -1;
        for (std::size_t v = 0; v < m.vertices.size(); ++v)
          if ((m.vertices[v] - p).norm() < 1e3 * eps) id = static_cast<int>(v);
        if (id < 0) {
          id = static_cast<int>(m.vertices.size());
          m.vertices.push_back(p);
        }
        for (int f : {a, b, c})
          if (std::find(on_face[f].begin(), on_face[f].end(), id) == on_face[f].end()) on_face[f].push_back(id);
      }
  for (int f = 0; f < k; ++f) {
    auto& ids = on_face[f];
    if (ids.size() < 3) continue;  // redundant plane
    Vec3 c = Vec3::Zero();
    for (int id : ids) c += m.vertices[id];
    c /= static_cast<double>(ids.size());
    const Vec3 u = (m.vertices[ids[0]] - c).normalized();
    const Vec3 w = n[f].cross(u);
    std::sort(ids.begin(), ids.end(), [&](int i, int j) {
      const Vec3 pi = m.vertices[i] - c, pj = m.vertices[j] - c;
      return std::atan2(pi.dot(w), pi.dot(u)) < std::atan2(pj.dot(w), pj.dot(u));
    });
    for (std::size_t t = 1; t + 1 < ids.size(); ++t) m.triangles.emplace_back(ids[0], ids[t], ids[t + 1]);
  }
  return m;
}
}  // namespace

PolyhedronShape::PolyhedronShape(std::vector<Vec3> normals, std::vector<double> offsets, std::string name)
    : normals_(std::move(normals)), offsets_(std::move(offsets)), name_(std::move(name)) {
  if (normals_.size() != offsets_.size() || normals_.size() < 4)
    throw std::invalid_argument("PolyhedronShape: needs >= 4 planes, one offset per normal");
  for (std::size_t i = 0; i < normals_.size(); ++i) {
    if (!(offsets_[i] > 0.0)) throw std::invalid_argument("PolyhedronShape: plane offsets must be > 0");
    normals_[i].normalize();
  }
  mesh_ = polytope_mesh(normals_, offsets_);
  volume_ = mesh_.volume();
  if (!(volume_ > 0.0) || mesh_.triangles.size() < 4)
    throw std::invalid_argument("PolyhedronShape: planes do not enclose a bounded solid");
}

double PolyhedronShape::clearance(const Vec3& p) const {
  double c = 1e300;
  for (std::size_t i = 0; i < normals_.size(); ++i) c = std::min(c, offsets_[i] - normals_[i].dot(p));
  return c;
}

Vec3 PolyhedronShape::push_inside(const Vec3& p, double r) const {
  Vec3 q = p;
  for (int it = 0; it < 4; ++it) {
    bool moved = false;
    for (std::size_t i = 0; i < normals_.size(); ++i) {
      const double excess = normals_[i].dot(q) - (offsets_[i] - r);
      if (excess > 0.0) {
        q -= excess * normals_[i];
        moved = true;
      }
    }
    if (!moved) break;
  }
  return q;
}

std::unique_ptr<PolyhedronShape> make_irregular_rock(unsigned long long seed, double size, int facets,
                                                     const std::string& name) {
  if (!(size > 0.0)) throw std::invalid_argument("make_irregular_rock: size must be > 0");
  if (facets < 0 || facets > 200) throw std::invalid_argument("make_irregular_rock: facets must be in [0, 200]");
  Rng rng(seed * 0x9E3779B97F4A7C15ULL + 12345ULL);
  // Ellipsoid semi-axes: x = a (long), y = b (intermediate), z = c (short).
  const double a = 1.0, b = rng.uniform(0.65, 0.9), c = b * rng.uniform(0.6, 0.9);
  const Vec3 semi(a, b, c);
  auto support = [&](const Vec3& nrm) {  // support function of the ellipsoid
    return std::sqrt(std::pow(semi.x() * nrm.x(), 2) + std::pow(semi.y() * nrm.y(), 2) +
                     std::pow(semi.z() * nrm.z(), 2));
  };
  std::vector<Vec3> normals;
  std::vector<double> offsets;
  // Bounding box of the ellipsoid keeps the solid bounded whatever the random planes do.
  for (int axis = 0; axis < 3; ++axis)
    for (double s : {-1.0, 1.0}) {
      Vec3 nrm = Vec3::Zero();
      nrm[axis] = s;
      normals.push_back(nrm);
      offsets.push_back(semi[axis]);
    }
  for (int f = 0; f < facets; ++f) {
    Vec3 nrm(rng.normal(), rng.normal(), rng.normal());
    nrm.normalize();
    normals.push_back(nrm);
    offsets.push_back(support(nrm) * (1.0 - rng.uniform(0.0, 0.25)));
  }
  PolyhedronShape unit(normals, offsets, name);
  const double extent_y = unit.max_corner().y() - unit.min_corner().y();
  const double k = size / extent_y;
  // Centre the solid's bounding box on the origin so the rock sits between platens symmetrically.
  const Vec3 mid = 0.5 * (unit.max_corner() + unit.min_corner());
  for (std::size_t i = 0; i < normals.size(); ++i) offsets[i] = k * (offsets[i] - normals[i].dot(mid));
  return std::make_unique<PolyhedronShape>(normals, offsets, name);
}

void write_stl(const TriMesh& mesh, const std::string& file, const std::string& solid_name, double scale) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("write_stl: cannot write '" + file + "'");
  out.precision(9);
  out << "solid " << solid_name << "\n";
  for (const auto& t : mesh.triangles) {
    const Vec3 &p0 = mesh.vertices[t[0]], &p1 = mesh.vertices[t[1]], &p2 = mesh.vertices[t[2]];
    const Vec3 nrm = (p1 - p0).cross(p2 - p0).normalized();
    out << " facet normal " << nrm.x() << " " << nrm.y() << " " << nrm.z() << "\n  outer loop\n";
    for (const Vec3* p : {&p0, &p1, &p2})
      out << "   vertex " << scale * p->x() << " " << scale * p->y() << " " << scale * p->z() << "\n";
    out << "  endloop\n endfacet\n";
  }
  out << "endsolid " << solid_name << "\n";
  if (!out) throw std::runtime_error("write_stl: error writing '" + file + "'");
}

}  // namespace rocks
