#include "dem/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>
#include <unordered_map>

namespace dem {

TriMesh::TriMesh(std::vector<Eigen::Vector3d> vertices, std::vector<Triangle> triangles,
                 std::string name)
    : name_(std::move(name)), verts_(std::move(vertices)), tris_(std::move(triangles)) {
  const int nv = static_cast<int>(verts_.size());
  for (int v = 0; v < nv; ++v) {
    if (!verts_[v].allFinite())
      throw std::invalid_argument("TriMesh '" + name_ + "': vertex " + std::to_string(v) +
                                  " has a non-finite coordinate; accepted: finite numbers (m)");
  }
  for (size_t t = 0; t < tris_.size(); ++t) {
    const Triangle& tr = tris_[t];
    for (int k = 0; k < 3; ++k) {
      if (tr[k] < 0 || tr[k] >= nv)
        throw std::invalid_argument("TriMesh '" + name_ + "': triangle " + std::to_string(t) +
                                    " has vertex index " + std::to_string(tr[k]) +
                                    "; accepted: 0.." + std::to_string(nv - 1));
    }
    if (tr[0] == tr[1] || tr[1] == tr[2] || tr[0] == tr[2])
      throw std::invalid_argument("TriMesh '" + name_ + "': triangle " + std::to_string(t) +
                                  " repeats a vertex; accepted: three distinct vertices");
  }
  build_derived();
}

TriMesh TriMesh::from_soup(const std::vector<std::array<Eigen::Vector3d, 3>>& soup, double weld_tol,
                           std::string name) {
  if (!(weld_tol >= 0.0))
    throw std::invalid_argument("TriMesh::from_soup: weld_tol = " + std::to_string(weld_tol) +
                                "; accepted: >= 0 (m)");
  std::vector<Eigen::Vector3d> verts;
  std::vector<Triangle> tris;
  tris.reserve(soup.size());
  // Key: coordinates quantised to weld_tol (or exact bits). Neighbouring cells are searched so two
  // points closer than weld_tol but on both sides of a cell border still merge.
  using Key = std::tuple<long long, long long, long long>;
  std::map<Key, std::vector<int>> cells;
  auto key_of = [&](const Eigen::Vector3d& p) -> Key {
    if (weld_tol == 0.0) {
      long long k[3];
      for (int i = 0; i < 3; ++i) {
        double c = p[i] == 0.0 ? 0.0 : p[i];  // -0 == +0
        std::memcpy(&k[i], &c, sizeof(double));
      }
      return Key{k[0], k[1], k[2]};
    }
    return Key{static_cast<long long>(std::floor(p.x() / weld_tol)),
               static_cast<long long>(std::floor(p.y() / weld_tol)),
               static_cast<long long>(std::floor(p.z() / weld_tol))};
  };
  auto find_or_add = [&](const Eigen::Vector3d& p) -> int {
    if (!p.allFinite())
      throw std::invalid_argument("TriMesh::from_soup '" + name +
                                  "': non-finite vertex coordinate; accepted: finite numbers (m)");
    Key k = key_of(p);
    if (weld_tol == 0.0) {
      auto it = cells.find(k);
      if (it != cells.end()) return it->second.front();
    } else {
      auto [kx, ky, kz] = k;
      for (long long dx = -1; dx <= 1; ++dx)
        for (long long dy = -1; dy <= 1; ++dy)
          for (long long dz = -1; dz <= 1; ++dz) {
            auto it = cells.find(Key{kx + dx, ky + dy, kz + dz});
            if (it == cells.end()) continue;
            for (int v : it->second)
              if ((verts[v] - p).norm() <= weld_tol) return v;
          }
    }
    int id = static_cast<int>(verts.size());
    verts.push_back(p);
    cells[k].push_back(id);
    return id;
  };
  for (const auto& tri : soup) {
    Triangle t{find_or_add(tri[0]), find_or_add(tri[1]), find_or_add(tri[2])};
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) continue;
    const Eigen::Vector3d n = (verts[t[1]] - verts[t[0]]).cross(verts[t[2]] - verts[t[0]]);
    if (n.norm() == 0.0) continue;
    tris.push_back(t);
  }
  return TriMesh(std::move(verts), std::move(tris), std::move(name));
}

void TriMesh::build_derived() {
  const int nt = static_cast<int>(tris_.size());
  const int nv = static_cast<int>(verts_.size());
  normals_.resize(nt);
  for (int t = 0; t < nt; ++t) {
    const Eigen::Vector3d n = (verts_[tris_[t][1]] - verts_[tris_[t][0]])
                                  .cross(verts_[tris_[t][2]] - verts_[tris_[t][0]]);
    const double len = n.norm();
    if (!(len > 0.0))
      throw std::invalid_argument("TriMesh '" + name_ + "': triangle " + std::to_string(t) +
                                  " has zero area; accepted: non-degenerate triangles");
    normals_[t] = n / len;
  }
  // Edges: sort (min, max, tri) records.
  struct Rec { int a, b, t, k; };
  std::vector<Rec> recs;
  recs.reserve(3 * nt);
  for (int t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      int a = tris_[t][k], b = tris_[t][(k + 1) % 3];
      recs.push_back({std::min(a, b), std::max(a, b), t, k});
    }
  std::sort(recs.begin(), recs.end(), [](const Rec& x, const Rec& y) {
    return std::tie(x.a, x.b, x.t, x.k) < std::tie(y.a, y.b, y.t, y.k);
  });
  edges_.clear();
  tri_edges_.assign(nt, {-1, -1, -1});
  for (size_t i = 0; i < recs.size();) {
    size_t j = i;
    while (j < recs.size() && recs[j].a == recs[i].a && recs[j].b == recs[i].b) ++j;
    const int id = static_cast<int>(edges_.size());
    // A non-manifold edge (more than two triangles) keeps the first two as its neighbours.
    edges_.push_back({recs[i].a, recs[i].b, recs[i].t, j - i > 1 ? recs[i + 1].t : -1});
    for (size_t m = i; m < j; ++m) tri_edges_[recs[m].t][recs[m].k] = id;
    i = j;
  }
  // Vertex -> triangles (CSR).
  vt_off_.assign(nv + 1, 0);
  for (const auto& tr : tris_)
    for (int v : tr) ++vt_off_[v + 1];
  for (int v = 0; v < nv; ++v) vt_off_[v + 1] += vt_off_[v];
  vt_idx_.resize(vt_off_[nv]);
  std::vector<int> fill(vt_off_.begin(), vt_off_.end() - 1);
  for (int t = 0; t < nt; ++t)
    for (int v : tris_[t]) vt_idx_[fill[v]++] = t;
  set_pose(pose_);
}

Eigen::Vector3d TriMesh::centroid(int t) const {
  return (verts_[tris_[t][0]] + verts_[tris_[t][1]] + verts_[tris_[t][2]]) / 3.0;
}

double TriMesh::triangle_area(int t) const {
  return 0.5 * (verts_[tris_[t][1]] - verts_[tris_[t][0]])
                   .cross(verts_[tris_[t][2]] - verts_[tris_[t][0]])
                   .norm();
}

double TriMesh::area() const {
  double a = 0.0;
  for (int t = 0; t < static_cast<int>(tris_.size()); ++t) a += triangle_area(t);
  return a;
}

double TriMesh::signed_volume() const {
  double v6 = 0.0;
  for (const auto& tr : tris_) v6 += verts_[tr[0]].dot(verts_[tr[1]].cross(verts_[tr[2]]));
  return v6 / 6.0;
}

void TriMesh::flip_normals() {
  for (auto& tr : tris_) std::swap(tr[1], tr[2]);
  build_derived();
}

bool TriMesh::triangles_share_vertex(int a, int b) const {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (tris_[a][i] == tris_[b][j]) return true;
  return false;
}

void TriMesh::set_pose(const Pose& pose) {
  if (!pose.position.allFinite() || !pose.orientation.coeffs().allFinite() ||
      pose.orientation.norm() < 1e-12)
    throw std::invalid_argument("TriMesh '" + name_ +
                                "': pose must be finite with a non-zero quaternion");
  pose_ = pose;
  pose_.orientation.normalize();
  rot_ = pose_.orientation.toRotationMatrix();
  world_verts_.resize(verts_.size());
  for (size_t v = 0; v < verts_.size(); ++v) world_verts_[v] = rot_ * verts_[v] + pose_.position;
}

Eigen::Vector3d TriMesh::bbox_min() const {
  Eigen::Vector3d m = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  for (const auto& v : verts_) m = m.cwiseMin(v);
  return m;
}

Eigen::Vector3d TriMesh::bbox_max() const {
  Eigen::Vector3d m = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());
  for (const auto& v : verts_) m = m.cwiseMax(v);
  return m;
}

}  // namespace dem
