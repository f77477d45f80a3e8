#include "dem/mesh_contact.hpp"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>

#include "dem/hertz_mindlin.hpp"

namespace dem {
namespace {

struct Candidate {
  int tri;
  TriFeature feature;
  int local;          // edge/corner index in the triangle
  Eigen::Vector3d q;  // closest point, body frame
  double d;           // distance centre - q
};

const Candidate* find_tri(const std::vector<Candidate>& c, int tri) {
  for (const auto& k : c)
    if (k.tri == tri) return &k;
  return nullptr;
}

constexpr double kCos45 = 0.70710678118654752;

}  // namespace

MeshContact::MeshContact(TriMesh mesh, const MaterialTable& materials, int wall_material)
    : mesh_(std::move(mesh)), materials_(materials), wall_material_(wall_material) {
  if (wall_material < 0 || wall_material >= materials_.n())
    throw std::invalid_argument("MeshContact '" + mesh_.name() + "': wall material index " +
                                std::to_string(wall_material) + "; accepted: 0.." +
                                std::to_string(materials_.n() - 1));
  if (mesh_.num_triangles() == 0)
    throw std::invalid_argument("MeshContact '" + mesh_.name() + "': mesh has no triangles");
  tri_.resize(mesh_.num_triangles());
  plane_.resize(4 * mesh_.num_triangles());
  for (size_t t = 0; t < tri_.size(); ++t) {
    const auto& tr = mesh_.triangle(static_cast<int>(t));
    tri_[t] = {mesh_.vertex(tr[0]), mesh_.vertex(tr[1]), mesh_.vertex(tr[2]),
               mesh_.normal(static_cast<int>(t))};
    for (int k = 0; k < 3; ++k) plane_[4 * t + k] = tri_[t].n[k];
    plane_[4 * t + 3] = -tri_[t].n.dot(tri_[t].a);
  }
}

void MeshContact::set_regions(RegionMap regions) {
  if (regions.num_triangles() != mesh_.num_triangles())
    throw std::invalid_argument("MeshContact '" + mesh_.name() + "': region map covers " +
                                std::to_string(regions.num_triangles()) + " triangles; accepted: " +
                                std::to_string(mesh_.num_triangles()) + " (the mesh's count)");
  regions_ = std::move(regions);
}

MeshWrench MeshContact::wrench_about(const Eigen::Vector3d& point) const {
  MeshWrench w;
  w.force = force_;
  w.torque = torque_origin_ - point.cross(force_);
  w.point = point;
  return w;
}

void MeshContact::add_forces(Particles& p, double /*t*/, double dt) {
  const long n = static_cast<long>(p.size());
  const int nthreads = threads_ > 0 ? threads_ : omp_get_max_threads();
  // Grid margin must cover the largest particle.
  double rmax = 0.0;
#pragma omp parallel for reduction(max : rmax) schedule(static) num_threads(nthreads)
  for (long i = 0; i < n; ++i) rmax = std::max(rmax, p.r[i]);
  if (n > 0 && (grid_.empty() || rmax + skin_ > grid_.margin())) {
    skin_ = skin_fraction_ * rmax;
    grid_ = TriangleGrid(mesh_, 1.05 * rmax + skin_, grid_cell_);
    far_.assign(n, 0);
  }
  // particles added since the last step are evaluated (removals remap in on_reindex)
  if (far_.size() != static_cast<std::size_t>(n)) far_.resize(n, 0);
  c0_.resize(n);
  const double half_skin2 = 0.25 * skin_ * skin_;
  long evaluated = 0;

  if (static_cast<int>(per_thread_.size()) < nthreads) per_thread_.resize(nthreads);
  for (auto& buf : per_thread_) buf.clear();
  std::atomic<int> bad_material{-1};
  const Eigen::Matrix3d R = mesh_.rotation();
  const Eigen::Matrix3d Rt = R.transpose();
  const Eigen::Vector3d origin = mesh_.pose().position;
  const Eigen::Vector3d omega = mesh_.twist().angular;
  const std::vector<Old>& old = old_;

#pragma omp parallel num_threads(nthreads)
  {
    const int tid = omp_get_thread_num();
    std::vector<MeshContactRecord>& out = per_thread_[tid];
    // Scratch kept per OpenMP worker thread between steps (no allocation in the steady state).
    static thread_local std::vector<Candidate> cand;
    static thread_local std::vector<int> kept;
    static thread_local std::vector<char> claimed;
#pragma omp for schedule(static) reduction(+ : evaluated)
    for (long i = 0; i < n; ++i) {
      if (static_cast<std::size_t>(i) < ghost_.size() && ghost_[i]) continue;  // another rank's particle
      const Eigen::Vector3d xw(p.x[i], p.y[i], p.z[i]);
      const Eigen::Vector3d c = Rt * (xw - origin);
      if (far_[i] && (c - c0_[i]).squaredNorm() < half_skin2) continue;  // no triangle within r + skin / 2
      ++evaluated;
      c0_[i] = c;
      far_[i] = skin_ > 0;
      auto range = grid_.query(c);
      if (range.first == range.second) continue;
      const double r = p.r[i], rs = r + skin_;
      cand.clear();
      for (const int* it = range.first; it != range.second; ++it) {
        const double* pl = &plane_[4 * static_cast<size_t>(*it)];
        const double h = pl[0] * c.x() + pl[1] * c.y() + pl[2] * c.z() + pl[3];
        if (h >= rs || h <= -rs) continue;
        const TriData& T = tri_[*it];
        const ClosestPoint cp = closest_point_on_triangle(c, T.a, T.b, T.c);
        const double d2 = (c - cp.point).squaredNorm();
        if (d2 >= rs * rs) continue;
        far_[i] = 0;
        if (h >= r || h <= -r || d2 >= r * r) continue;
        cand.push_back({*it, cp.feature, cp.index, cp.point, std::sqrt(d2)});
      }
      if (cand.empty()) continue;
      // Keep an edge/vertex contact only if it is the closest point of every triangle sharing the
      // feature: a triangle containing the point but reporting another one has a strictly closer
      // point, so this contact is a shadow of that one. Points are compared (first order in the
      // offset), not distances (second order).
      const double tol = 1e-9 * r;
      kept.clear();
      for (int k = 0; k < static_cast<int>(cand.size()); ++k) {
        const Candidate& ck = cand[k];
        bool valid = true;
        if (ck.feature == TriFeature::Edge) {
          const TriMesh::Edge& e = mesh_.edges()[mesh_.triangle_edges(ck.tri)[ck.local]];
          const int other = e.tri0 == ck.tri ? e.tri1 : e.tri0;
          if (other >= 0) {
            const Candidate* co = find_tri(cand, other);
            if (co && (co->q - ck.q).squaredNorm() > tol * tol) valid = false;
          }
        } else if (ck.feature == TriFeature::Vertex) {
          const int v = mesh_.triangle(ck.tri)[ck.local];
          auto [b, e] = mesh_.vertex_triangles(v);
          for (const int* t2 = b; t2 != e && valid; ++t2) {
            if (*t2 == ck.tri) continue;
            const Candidate* co = find_tri(cand, *t2);
            if (co && (co->q - ck.q).squaredNorm() > tol * tol) valid = false;
          }
        }
        if (!valid) continue;
        for (int j : kept)
          if ((cand[j].q - ck.q).squaredNorm() <= tol * tol) {
            valid = false;
            break;
          }
        if (valid) kept.push_back(k);
      }
      // Pair properties of this particle's material with the wall.
      const int mat = p.material[i];
      if (!materials_.has_pair(mat, wall_material_)) {
        bad_material.store(mat);
        continue;
      }
      const PairProps& props = materials_.pair(mat, wall_material_);
      // Previous contacts of this particle.
      const uint64_t pid = p.id[i];
      auto lo = std::lower_bound(old.begin(), old.end(), pid,
                                 [](const Old& o, uint64_t id) { return o.id < id; });
      auto hi = lo;
      while (hi != old.end() && hi->id == pid) ++hi;
      claimed.assign(hi - lo, 0);
      const size_t first_new = out.size();
      for (int k : kept) {
        const Candidate& ck = cand[k];
        MeshContactRecord rec;
        rec.particle_id = pid;
        rec.particle_index = static_cast<int>(i);
        rec.triangle = ck.tri;
        rec.feature = ck.feature;
        rec.region = regions_ ? regions_->region_of(ck.tri) : -1;
        rec.overlap = r - ck.d;
        const Eigen::Vector3d nb = ck.d > 1e-12 * r ? Eigen::Vector3d((c - ck.q) / ck.d) : tri_[ck.tri].n;
        rec.normal = R * nb;
        rec.point = R * ck.q + origin;
        rec.history.setZero();
        for (auto o = lo; o != hi; ++o)
          if (o->tri == ck.tri) {
            rec.history = o->history;
            claimed[o - lo] = 1;
          }
        out.push_back(rec);
      }
      // Unmatched new contacts take the history of a released contact with a similar normal.
      for (size_t m = first_new; m < out.size(); ++m) {
        MeshContactRecord& rec = out[m];
        bool exact = false;
        for (auto o = lo; o != hi; ++o) exact |= (o->tri == rec.triangle);
        if (exact) continue;
        int best = -1;
        double best_dot = kCos45;
        for (auto o = lo; o != hi; ++o) {
          if (claimed[o - lo]) continue;
          const double dd = o->normal.dot(rec.normal);
          if (dd > best_dot) {
            best_dot = dd;
            best = static_cast<int>(o - lo);
          }
        }
        if (best >= 0) {
          rec.history = (lo + best)->history;
          claimed[best] = 1;
        }
      }
      // Forces (paper Eq. 16-19 via hertz_mindlin, wall of infinite mass and radius).
      const Eigen::Vector3d vi(p.vx[i], p.vy[i], p.vz[i]);
      const Eigen::Vector3d wi(p.wx[i], p.wy[i], p.wz[i]);
      for (size_t m = first_new; m < out.size(); ++m) {
        MeshContactRecord& rec = out[m];
        const double dcen = r - rec.overlap;  // centre to contact point
        const Eigen::Vector3d arm = -dcen * rec.normal;
        const Eigen::Vector3d vrel = vi + wi.cross(arm) - mesh_.velocity_at(rec.point);
        const Eigen::Vector3d wrel = wi - omega;
        ContactForce cf;
        hertz_mindlin(rec.overlap, rec.normal.data(), vrel.data(), wrel.data(), r, p.m[i], props, dt,
                      rec.history.data(), cf);
        rec.force = Eigen::Vector3d(cf.f[0], cf.f[1], cf.f[2]);
        rec.roll_torque = Eigen::Vector3d(cf.troll[0], cf.troll[1], cf.troll[2]);
        rec.normal_force = cf.fn_mag;
        const Eigen::Vector3d tq = arm.cross(rec.force) + rec.roll_torque;
        p.fx[i] += rec.force.x();
        p.fy[i] += rec.force.y();
        p.fz[i] += rec.force.z();
        p.tx[i] += tq.x();
        p.ty[i] += tq.y();
        p.tz[i] += tq.z();
      }
    }
  }
  if (bad_material.load() >= 0)
    throw std::invalid_argument("MeshContact '" + mesh_.name() + "': no contact pair between particle material " +
                                std::to_string(bad_material.load()) + " and wall material " +
                                std::to_string(wall_material_) + "; set it with MaterialTable::set_pair");

  evaluated_ = evaluated;
  // Serial, ordered reduction (thread blocks are contiguous in particle order).
  contacts_.clear();
  for (int t = 0; t < nthreads; ++t)
    contacts_.insert(contacts_.end(), per_thread_[t].begin(), per_thread_[t].end());
  force_.setZero();
  torque_origin_.setZero();
  total_normal_ = 0.0;
  const int nreg = regions_ ? regions_->num_regions() : 0;
  region_normal_.assign(nreg, 0.0);
  region_force_.assign(nreg, Eigen::Vector3d::Zero());
  worst_ratio_ = 0.0;
  worst_index_ = -1;
  for (const auto& rec : contacts_) {
    const double ratio = rec.overlap / p.r[rec.particle_index];
    if (ratio > worst_ratio_) worst_ratio_ = ratio, worst_index_ = rec.particle_index;
    force_ -= rec.force;
    torque_origin_ -= rec.point.cross(rec.force) + rec.roll_torque;
    total_normal_ += rec.normal_force;
    if (rec.region >= 0) {
      region_normal_[rec.region] += rec.normal_force;
      region_force_[rec.region] -= rec.force;
    }
  }
  // History for the next step, sorted by (particle id, triangle).
  old_.clear();
  old_.reserve(contacts_.size());
  for (const auto& rec : contacts_) old_.push_back({rec.particle_id, rec.triangle, rec.normal, rec.history});
  std::sort(old_.begin(), old_.end(), [](const Old& a, const Old& b) {
    return a.id != b.id ? a.id < b.id : a.tri < b.tri;
  });
}

void MeshContact::on_reindex(const std::vector<long>& old_to_new) {
  // the skip state follows its particles; contacts() keep the old indices until the next step
  // survivors of the known particles come first (the map keeps the order); particles added since are evaluated
  std::size_t k = 0;
  for (std::size_t i = 0; i < old_to_new.size() && i < far_.size(); ++i) {
    const long a = old_to_new[i];
    if (a < 0) continue;
    far_[a] = far_[i];
    c0_[a] = c0_[i];
    ++k;
  }
  far_.resize(k);
  c0_.resize(k);
  if (!ghost_.empty()) {  // the ghost mask follows its particles too; particles added since are not ghosts
    std::vector<char> g;
    for (std::size_t i = 0; i < old_to_new.size(); ++i)
      if (old_to_new[i] >= 0) {
        const auto a = static_cast<std::size_t>(old_to_new[i]);
        if (g.size() <= a) g.resize(a + 1, 0);
        g[a] = i < ghost_.size() ? ghost_[i] : 0;
      }
    ghost_.swap(g);
  }
}

void MeshContact::set_ghosts(const Particles& p, const std::vector<char>& ghost) {
  ghost_ = ghost;
  std::vector<uint64_t> owned;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (i >= ghost.size() || !ghost[i]) owned.push_back(p.id[i]);
  std::sort(owned.begin(), owned.end());
  old_.erase(std::remove_if(old_.begin(), old_.end(),
                            [&](const Old& o) { return !std::binary_search(owned.begin(), owned.end(), o.id); }),
             old_.end());
}

void MeshContact::assemble_state(const std::vector<const Interaction*>& parts) {
  std::vector<const MeshContact*> mc;
  for (const Interaction* ia : parts) {
    const auto* m = dynamic_cast<const MeshContact*>(ia);
    if (!m || m->mesh_.num_triangles() != mesh_.num_triangles())
      throw std::invalid_argument(label() + ": a part is not a contact with the same mesh");
    mc.push_back(m);
  }
  if (mc.empty()) return;
  const MeshContact& first = *mc[0];
  std::vector<Old> old;
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
  double total = 0, worst = 0;
  std::vector<double> region_normal(first.region_normal_.size(), 0.0);
  std::vector<Eigen::Vector3d> region_force(first.region_force_.size(), Eigen::Vector3d::Zero());
  for (const MeshContact* m : mc) {
    if (m->region_normal_.size() != region_normal.size())
      throw std::invalid_argument(label() + ": the parts have different region counts");
    old.insert(old.end(), m->old_.begin(), m->old_.end());
    force += m->force_;
    torque += m->torque_origin_;
    total += m->total_normal_;
    worst = std::max(worst, m->worst_ratio_);
    for (std::size_t k = 0; k < region_normal.size(); ++k)
      region_normal[k] += m->region_normal_[k], region_force[k] += m->region_force_[k];
  }
  std::sort(old.begin(), old.end(), [](const Old& a, const Old& b) { return a.id != b.id ? a.id < b.id : a.tri < b.tri; });
  for (std::size_t k = 1; k < old.size(); ++k)
    if (old[k].id == old[k - 1].id && old[k].tri == old[k - 1].tri)
      throw std::invalid_argument(label() + ": particle " + std::to_string(old[k].id) +
                                  " has a contact history in two parts");
  mesh_.set_pose(first.mesh_.pose());
  mesh_.set_twist(first.mesh_.twist());
  grid_cell_ = first.grid_cell_;
  skin_ = first.skin_;
  grid_ = first.grid_.empty() ? TriangleGrid() : TriangleGrid(mesh_, first.grid_.margin(), grid_cell_);
  far_.clear();
  c0_.clear();
  ghost_.clear();
  contacts_.clear();
  old_.swap(old);
  force_ = force, torque_origin_ = torque, total_normal_ = total;
  worst_ratio_ = worst, worst_index_ = -1;
  region_normal_.swap(region_normal);
  region_force_.swap(region_force);
}

void MeshContact::on_radius_change(long i) {
  if (i >= 0 && static_cast<std::size_t>(i) < far_.size()) far_[i] = 0;
}

// ------------------------------------------------------------------ checkpoint

void MeshContact::save_state(core::BinaryWriter& w) const {
  w.tag("MESH");
  w.put<uint64_t>(mesh_.num_triangles());
  const Pose& pose = mesh_.pose();
  w.put_xyz(pose.position);
  for (int k = 0; k < 4; ++k) w.put<double>(pose.orientation.coeffs()[k]);  // x, y, z, w
  w.put_xyz(mesh_.twist().linear);
  w.put_xyz(mesh_.twist().angular);
  // broad phase: built lazily from the largest radius at its first use (candidates come in triangle order in
  // every cell, so results do not depend on it; restored so the loaded object has the same grid and cost)
  w.put<uint8_t>(grid_.empty() ? 0 : 1);
  w.put<double>(grid_.margin());
  w.put<double>(grid_cell_);
  // tangential histories of the last step, sorted by (particle id, triangle)
  w.put<uint64_t>(old_.size());
  for (const Old& o : old_) {
    w.put<uint64_t>(o.id);
    w.put<int32_t>(o.tri);
    w.put_xyz(o.normal);
    w.put_xyz(o.history);
  }
  // the last step's totals (read by the coupling between steps)
  w.put_xyz(force_);
  w.put_xyz(torque_origin_);
  w.put<double>(total_normal_);
  w.put<double>(worst_ratio_);
  w.put<int64_t>(worst_index_);
  w.put_vec(region_normal_);
  w.put<uint64_t>(region_force_.size());
  for (const auto& f : region_force_) w.put_xyz(f);
}

void MeshContact::load_state(core::BinaryReader& r) {
  r.expect("MESH");
  const uint64_t ntri = r.get<uint64_t>();
  if (ntri != mesh_.num_triangles())
    r.fail("mesh '" + mesh_.name() + "' was saved with " + std::to_string(ntri) + " triangles, this one has " +
           std::to_string(mesh_.num_triangles()));
  Pose pose;
  pose.position = r.get_xyz<Eigen::Vector3d>();
  for (int k = 0; k < 4; ++k) pose.orientation.coeffs()[k] = r.get<double>();
  Twist twist;
  twist.linear = r.get_xyz<Eigen::Vector3d>();
  twist.angular = r.get_xyz<Eigen::Vector3d>();
  const bool has_grid = r.get<uint8_t>() != 0;
  const double margin = r.get<double>(), cell = r.get<double>();
  const uint64_t nold = r.get<uint64_t>();
  if (nold > (uint64_t(1) << 32)) r.fail("mesh '" + mesh_.name() + "': implausible history count " + std::to_string(nold));
  std::vector<Old> old(nold);
  for (uint64_t k = 0; k < nold; ++k) {
    Old& o = old[k];
    o.id = r.get<uint64_t>();
    o.tri = r.get<int32_t>();
    o.normal = r.get_xyz<Eigen::Vector3d>();
    o.history = r.get_xyz<Eigen::Vector3d>();
    if (o.tri < 0 || static_cast<uint64_t>(o.tri) >= ntri ||
        (k > 0 && (o.id < old[k - 1].id || (o.id == old[k - 1].id && o.tri <= old[k - 1].tri))))
      r.fail("mesh '" + mesh_.name() + "': contact history out of range or order");
  }
  const Eigen::Vector3d force = r.get_xyz<Eigen::Vector3d>(), torque = r.get_xyz<Eigen::Vector3d>();
  const double total_normal = r.get<double>(), worst_ratio = r.get<double>();
  const int64_t worst_index = r.get<int64_t>();
  std::vector<double> region_normal;
  r.get_vec(region_normal, uint64_t(1) << 24);
  const uint64_t nrf = r.get<uint64_t>();
  const uint64_t nreg = regions_ ? static_cast<uint64_t>(regions_->num_regions()) : 0;
  if (nrf != region_normal.size() || (nrf != 0 && nrf != nreg))
    r.fail("mesh '" + mesh_.name() + "' was saved with " + std::to_string(nrf) + " regions, this one has " +
           std::to_string(nreg));
  std::vector<Eigen::Vector3d> region_force(nrf);
  for (auto& f : region_force) f = r.get_xyz<Eigen::Vector3d>();
  try {
    mesh_.set_pose(pose);
  } catch (const std::invalid_argument& e) {
    r.fail(e.what());
  }
  mesh_.set_twist(twist);
  grid_cell_ = cell;
  grid_ = has_grid ? TriangleGrid(mesh_, margin, grid_cell_) : TriangleGrid();
  skin_ = has_grid ? skin_fraction_ * margin / (1.05 + skin_fraction_) : 0.0;  // margin = 1.05 rmax + skin
  far_.clear();  // every particle is evaluated at the next step
  c0_.clear();
  old_ = std::move(old);
  contacts_.clear();
  force_ = force;
  torque_origin_ = torque;
  total_normal_ = total_normal;
  worst_ratio_ = worst_ratio;
  worst_index_ = worst_index;
  region_normal_ = std::move(region_normal);
  region_force_ = std::move(region_force);
}

}  // namespace dem
