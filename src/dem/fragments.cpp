#include "dem/fragments.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace dem {

double square_sieve_size(const std::vector<Eigen::Vector3d>& centres, const std::vector<double>& radii,
                         const std::vector<double>& masses) {
  const size_t n = centres.size();
  if (n == 0 || radii.size() != n || masses.size() != n)
    throw std::invalid_argument("square_sieve_size: need as many radii and masses as centres (>= 1), got " +
                                std::to_string(n) + ", " + std::to_string(radii.size()) + ", " +
                                std::to_string(masses.size()));
  double M = 0.0;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    if (!(radii[i] > 0.0) || !(masses[i] > 0.0))
      throw std::invalid_argument("square_sieve_size: sphere " + std::to_string(i) +
                                  " needs radius > 0 and mass > 0");
    M += masses[i];
    c += masses[i] * centres[i];
  }
  c /= M;
  // Second moment of the mass distribution (a solid sphere adds r^2/5 in every direction).
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = centres[i] - c;
    C += masses[i] * (d * d.transpose() + 0.2 * radii[i] * radii[i] * Eigen::Matrix3d::Identity());
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C / M);
  const Eigen::Matrix3d axes = es.eigenvectors();
  double ext[3];
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d a = axes.col(k);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (size_t i = 0; i < n; ++i) {
      const double s = a.dot(centres[i]);
      lo = std::min(lo, s - radii[i]);
      hi = std::max(hi, s + radii[i]);
    }
    ext[k] = hi - lo;
  }
  std::sort(ext, ext + 3);  // S, I, L
  const double S = ext[0], I = ext[1];
  return std::min(I, (I + S) / std::sqrt(2.0));
}

Fragments::Fragments(const std::vector<uint64_t>& particle_ids,
                     const std::vector<std::pair<uint64_t, uint64_t>>& bonds) {
  for (uint64_t id : particle_ids) {
    if (node_.count(id))
      throw std::invalid_argument("Fragments: particle id " + std::to_string(id) + " listed twice");
    node_[id] = static_cast<int>(id_.size());
    id_.push_back(id);
    alive_.push_back(1);
    adj_.emplace_back();
    comp_.push_back(-1);
  }
  for (const auto& [a, b] : bonds) {
    const int na = node_of(a), nb = node_of(b);
    if (na == nb) throw std::invalid_argument("Fragments: bond of particle " + std::to_string(a) + " with itself");
    if (std::find(adj_[na].begin(), adj_[na].end(), nb) != adj_[na].end()) continue;  // duplicate bond
    adj_[na].push_back(nb);
    adj_[nb].push_back(na);
    ++bonds_;
  }
  // Components by breadth-first search, labelled in order of their first particle.
  std::vector<int> queue;
  for (int s = 0; s < static_cast<int>(id_.size()); ++s) {
    if (comp_[s] >= 0) continue;
    const int label = new_label();
    queue.assign(1, s);
    comp_[s] = label;
    for (size_t q = 0; q < queue.size(); ++q)
      for (int nb : adj_[queue[q]])
        if (comp_[nb] < 0) {
          comp_[nb] = label;
          queue.push_back(nb);
        }
    members_[label] = queue;
  }
}

Fragments Fragments::from_particles(const Particles& p, const std::vector<std::pair<int, int>>& bonds) {
  std::vector<std::pair<uint64_t, uint64_t>> b;
  b.reserve(bonds.size());
  const int n = static_cast<int>(p.size());
  for (const auto& [i, j] : bonds) {
    if (i < 0 || j < 0 || i >= n || j >= n)
      throw std::invalid_argument("Fragments::from_particles: bond (" + std::to_string(i) + ", " +
                                  std::to_string(j) + ") out of range 0.." + std::to_string(n - 1));
    b.emplace_back(p.id[i], p.id[j]);
  }
  return Fragments(p.id, b);
}

Fragments Fragments::from_bonds(const Particles& p, const std::vector<Bond>& bonds) {
  std::vector<std::pair<int, int>> b;
  for (const auto& bd : bonds)
    if (bd.alive) b.emplace_back(static_cast<int>(bd.i), static_cast<int>(bd.j));
  return from_particles(p, b);
}

int Fragments::node_of(uint64_t id) const {
  auto it = node_.find(id);
  if (it == node_.end())
    throw std::invalid_argument("Fragments: unknown particle id " + std::to_string(id));
  return it->second;
}

int Fragments::new_label() {
  ++live_;
  if (!free_labels_.empty()) {
    const int l = free_labels_.back();
    free_labels_.pop_back();
    return l;
  }
  members_.emplace_back();
  return static_cast<int>(members_.size()) - 1;
}

int Fragments::fragment_of(uint64_t id) const { return comp_[node_of(id)]; }

bool Fragments::bonded(uint64_t a, uint64_t b) const {
  const int na = node_of(a), nb = node_of(b);
  return std::find(adj_[na].begin(), adj_[na].end(), nb) != adj_[na].end();
}

std::vector<int> Fragments::labels() const {
  std::vector<int> l;
  for (int i = 0; i < static_cast<int>(members_.size()); ++i)
    if (!members_[i].empty()) l.push_back(i);
  return l;
}

std::vector<uint64_t> Fragments::members(int label) const {
  if (label < 0 || label >= static_cast<int>(members_.size()) || members_[label].empty())
    throw std::invalid_argument("Fragments: no fragment with label " + std::to_string(label));
  std::vector<uint64_t> ids;
  for (int nd : members_[label]) ids.push_back(id_[nd]);
  std::sort(ids.begin(), ids.end());
  return ids;
}

bool Fragments::break_bond(uint64_t a, uint64_t b) {
  const int na = node_of(a), nb = node_of(b);
  auto ia = std::find(adj_[na].begin(), adj_[na].end(), nb);
  if (ia == adj_[na].end())
    throw std::invalid_argument("Fragments::break_bond: no intact bond between particles " +
                                std::to_string(a) + " and " + std::to_string(b));
  adj_[na].erase(ia);
  adj_[nb].erase(std::find(adj_[nb].begin(), adj_[nb].end(), na));
  --bonds_;
  // Search from a; stop as soon as b is reached (no split).
  const int label = comp_[na];
  std::vector<int> queue{na};
  // Mark visited with a temporary label (-2) and restore afterwards.
  comp_[na] = -2;
  bool reached = false;
  for (size_t q = 0; q < queue.size() && !reached; ++q)
    for (int nd : adj_[queue[q]]) {
      if (nd == nb) { reached = true; break; }
      if (comp_[nd] != -2) {
        comp_[nd] = -2;
        queue.push_back(nd);
      }
    }
  if (reached) {
    for (int nd : queue) comp_[nd] = label;
    return false;
  }
  const int fresh = new_label();
  for (int nd : queue) comp_[nd] = fresh;
  members_[fresh] = queue;
  auto& old = members_[label];
  old.erase(std::remove_if(old.begin(), old.end(), [&](int nd) { return comp_[nd] != label; }), old.end());
  return true;
}

int Fragments::apply_breaks(const std::vector<BondBreak>& breaks) {
  int splits = 0;
  for (const auto& b : breaks) splits += break_bond(b.id_i, b.id_j) ? 1 : 0;
  return splits;
}

void Fragments::add_particle(uint64_t id) {
  if (node_.count(id))
    throw std::invalid_argument("Fragments::add_particle: particle id " + std::to_string(id) + " already tracked");
  const int nd = static_cast<int>(id_.size());
  node_[id] = nd;
  id_.push_back(id);
  alive_.push_back(1);
  adj_.emplace_back();
  const int l = new_label();
  comp_.push_back(l);
  members_[l] = {nd};
}

void Fragments::remove_particle(uint64_t id) {
  const int nd = node_of(id);
  const int label = comp_[nd];
  for (int nb : adj_[nd]) adj_[nb].erase(std::find(adj_[nb].begin(), adj_[nb].end(), nd));
  bonds_ -= adj_[nd].size();
  adj_[nd].clear();
  alive_[nd] = 0;
  comp_[nd] = -1;
  node_.erase(id);
  // Re-split the rest of the old fragment: first piece keeps the label.
  std::vector<int> rest;
  for (int m : members_[label])
    if (m != nd) rest.push_back(m);
  members_[label].clear();
  for (int m : rest) comp_[m] = -3;  // unvisited
  bool first = true;
  for (int s : rest) {
    if (comp_[s] != -3) continue;
    const int l = first ? label : new_label();
    first = false;
    std::vector<int> queue{s};
    comp_[s] = l;
    for (size_t q = 0; q < queue.size(); ++q)
      for (int x : adj_[queue[q]])
        if (comp_[x] == -3) {
          comp_[x] = l;
          queue.push_back(x);
        }
    members_[l] = queue;
  }
  if (first) {  // the fragment was this particle alone
    --live_;
    free_labels_.push_back(label);
  }
}

std::vector<FragmentInfo> Fragments::info(const Particles& p) const {
  std::unordered_map<uint64_t, size_t> index;
  index.reserve(p.size());
  for (size_t i = 0; i < p.size(); ++i) index[p.id[i]] = i;
  std::vector<FragmentInfo> out;
  std::vector<Eigen::Vector3d> c;
  std::vector<double> r, m;
  for (int l : labels()) {
    c.clear(); r.clear(); m.clear();
    for (int nd : members_[l]) {
      auto it = index.find(id_[nd]);
      if (it == index.end())
        throw std::invalid_argument("Fragments::info: tracked particle id " + std::to_string(id_[nd]) +
                                    " is not in the particle set");
      const size_t i = it->second;
      c.emplace_back(p.x[i], p.y[i], p.z[i]);
      r.push_back(p.r[i]);
      m.push_back(p.m[i]);
    }
    FragmentInfo f;
    f.label = l;
    f.count = static_cast<int>(c.size());
    f.mass = 0.0;
    f.centre.setZero();
    for (size_t k = 0; k < c.size(); ++k) {
      f.mass += m[k];
      f.centre += m[k] * c[k];
    }
    f.centre /= f.mass;
    f.sieve_size = square_sieve_size(c, r, m);
    out.push_back(f);
  }
  return out;
}

}  // namespace dem
