#include "dem/world.hpp"

#include <omp.h>

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>
#include <string>

#include "dem/bond_law.hpp"
#include "dem/hertz_mindlin.hpp"

namespace dem {

namespace {
constexpr long kMinParallel = 1024;  // below this many items a loop runs serially (OpenMP start-up costs more)

// Runs body(begin, end, thread) over [0, n) in contiguous static chunks, one per thread: the split depends
// only on n and the thread count, so results are identical run to run for a given thread count.
template <class F>
void chunked(int nt_req, long n, F&& body) {
  const int nt = (nt_req > 1 && n >= kMinParallel) ? nt_req : 1;
  if (nt == 1) {
    body(0L, n, 0);
    return;
  }
#pragma omp parallel num_threads(nt)
  {
    const long T = omp_get_num_threads(), t = omp_get_thread_num();
    body(n * t / T, n * (t + 1) / T, static_cast<int>(t));
  }
}
}  // namespace

World::World(const WorldParams& params) : prm_(params) {
  if (!(prm_.dt > 0)) throw std::invalid_argument("dem::World: dt must be > 0 s, got " + std::to_string(prm_.dt));
  if (prm_.threads < 0) throw std::invalid_argument("dem::World: threads must be >= 0 (0 = all)");
  if (!(prm_.max_rayleigh_fraction > 0) || prm_.max_rayleigh_fraction > 1)
    throw std::invalid_argument("dem::World: max_rayleigh_fraction must be in (0, 1]");
  if (prm_.materials.n() == 0) throw std::invalid_argument("dem::World: the material table is empty");
  for (int i = 0; i < prm_.materials.n(); ++i)
    for (int j = 0; j < prm_.materials.n(); ++j)
      if (!prm_.materials.has_pair(i, j))
        throw std::invalid_argument("dem::World: no pair properties for materials '" +
                                    prm_.materials.material(i).name + "' and '" + prm_.materials.material(j).name +
                                    "' (MaterialTable::set_pair)");
  nt_ = std::min(256, prm_.threads > 0 ? prm_.threads : omp_get_max_threads());
  skin_ = prm_.skin;
}

// ------------------------------------------------------------------ particles
std::size_t World::add_particle(const double x[3], double radius, int material, const double v[3],
                                const double w[3]) {
  return add_particle(x, radius, material, prm_.materials.material(material).density, v, w);
}

std::size_t World::add_particle(const double x[3], double radius, int material, double density, const double v[3],
                                const double w[3]) {
  if (material < 0 || material >= prm_.materials.n())
    throw std::invalid_argument("dem::World::add_particle: material index " + std::to_string(material) +
                                " not in [0, " + std::to_string(prm_.materials.n()) + ")");
  if (!std::isfinite(x[0]) || !std::isfinite(x[1]) || !std::isfinite(x[2]))
    throw std::invalid_argument("dem::World::add_particle: position must be finite");
  const double z3[3] = {0, 0, 0};
  if (!v) v = z3;
  if (!w) w = z3;
  const std::size_t i = p_.add(x[0], x[1], x[2], radius, density, material, v[0], v[1], v[2], w[0], w[1], w[2]);
  if (!ghost_.empty()) ghost_.push_back(0);  // a new particle is this rank's own
  need_rebuild_ = true;
  dt_checked_ = false;
  return i;
}

void World::set_radius(std::size_t i, double radius) {
  if (i >= p_.size())
    throw std::invalid_argument("dem::World::set_radius: index " + std::to_string(i) + " not below the particle count " +
                                std::to_string(p_.size()));
  if (!(radius > 0) || !std::isfinite(radius))
    throw std::invalid_argument("dem::World::set_radius: radius must be finite and > 0 (got " + std::to_string(radius) +
                                " m)");
  // Rayleigh step of this sphere with its mass at the new radius
  const double rho = p_.m[i] / (4.0 / 3.0 * M_PI * radius * radius * radius);
  const double t_r = rayleigh_time_step(radius, rho, prm_.materials.material(p_.material[i]));
  if (prm_.dt > prm_.max_rayleigh_fraction * t_r)
    throw std::invalid_argument("dem::World::set_radius: radius " + std::to_string(radius) + " m at mass " +
                                std::to_string(p_.m[i]) + " kg has a Rayleigh step of " + std::to_string(t_r) +
                                " s; dt " + std::to_string(prm_.dt) + " s accepts only up to " +
                                std::to_string(prm_.max_rayleigh_fraction) + " of it");
  step_growth_ = std::max(step_growth_, std::abs(radius - p_.r[i]));
  p_.r[i] = radius;
  p_.inv_I[i] = 1.0 / (0.4 * p_.m[i] * radius * radius);
  for (auto& ia : interactions_) ia->on_radius_change(static_cast<long>(i));
}

long World::index_of(uint64_t id) const {
  // ids are increasing with index: insertion appends a new id, removal keeps the order
  auto it = std::lower_bound(p_.id.begin(), p_.id.end(), id);
  if (it == p_.id.end() || *it != id) return -1;
  return static_cast<long>(it - p_.id.begin());
}

void World::remove_particles(const std::vector<char>& remove) {
  if (remove.size() != p_.size())
    throw std::invalid_argument("dem::World::remove_particles: mask size " + std::to_string(remove.size()) +
                                " != particle count " + std::to_string(p_.size()));
  resize_per_particle();
  // A valid neighbour list stays valid without the removed particles (it lists a superset of the pairs within
  // reach): it is compacted with them instead of rebuilt.
  const bool keep_list = !need_rebuild_ && skin_ >= 0 && slab_of_.size() == p_.size() && x0_.size() == p_.size();
  std::vector<char> keep(remove.size());
  for (std::size_t i = 0; i < remove.size(); ++i) keep[i] = remove[i] ? 0 : 1;
  const std::size_t nw = walls_.size(), nold = p_.size();
  // wall histories follow their particles
  std::size_t k = 0;
  for (std::size_t i = 0; i < nold; ++i) {
    if (!keep[i]) continue;
    for (std::size_t w = 0; w < nw; ++w) whist_[k * nw + w] = whist_[i * nw + w];
    ++k;
  }
  if (!ghost_.empty()) {
    std::size_t g = 0;
    for (std::size_t i = 0; i < nold; ++i)
      if (keep[i]) ghost_[g++] = ghost_[i];
    ghost_.resize(g);
  }
  const std::vector<long> map = p_.compact(keep);
  whist_.resize(p_.size() * nw);
  wtouch_.assign(p_.size(), 1);
  // bonds: drop those touching removed particles, renumber the rest
  sync_bonds();
  std::size_t nb = 0;
  for (std::size_t b = 0; b < bonds_.size(); ++b) {
    Bond bd = bonds_[b];
    if (!bd.alive || map[bd.i] < 0 || map[bd.j] < 0) continue;
    bd.i = static_cast<uint32_t>(map[bd.i]);
    bd.j = static_cast<uint32_t>(map[bd.j]);
    bonds_[nb++] = bd;
  }
  bonds_.resize(nb);
  bonds_dirty_ = true;
  // neighbour pairs: keep histories of surviving pairs (order by owner is preserved by the compaction)
  std::size_t np = 0;
  for (std::size_t q = 0; q < npairs_; ++q) {
    const long a = map[pi_[q]], b = map[pj_[q]];
    if (a < 0 || b < 0) continue;
    pi_[np] = static_cast<uint32_t>(a);
    pj_[np] = static_cast<uint32_t>(b);
    hist_[np] = hist_[q];
    touch_[np] = touch_[q];
    ++np;
  }
  npairs_ = np;
  istart_.assign(p_.size() + 1, 0);
  for (std::size_t q = 0; q < npairs_; ++q) ++istart_[pi_[q] + 1];
  for (std::size_t i = 0; i < p_.size(); ++i) istart_[i + 1] += istart_[i];
  if (keep_list) {
    // displacement reference and slabs follow their particles (a slab keeps its owners in index order)
    for (std::size_t i = 0; i < nold; ++i) {
      const long a = map[i];
      if (a < 0) continue;
      x0_[a] = x0_[i];
      y0_[a] = y0_[i];
      z0_[a] = z0_[i];
      slab_of_[a] = slab_of_[i];
    }
    std::size_t m = 0;
    for (std::size_t s = 0; s + 1 < sstart_.size(); ++s) {
      const uint32_t b = sstart_[s], e = sstart_[s + 1];
      sstart_[s] = static_cast<uint32_t>(m);
      for (uint32_t k = b; k < e; ++k)
        if (map[sorder_[k]] >= 0) sorder_[m++] = static_cast<uint32_t>(map[sorder_[k]]);
    }
    sstart_.back() = static_cast<uint32_t>(m);
    sorder_.resize(m);
    slab_of_.resize(p_.size());
  } else {
    need_rebuild_ = true;
  }
  // (removing particles cannot shorten the stable time step: dt stays checked)
  x0_.resize(p_.size());
  y0_.resize(p_.size());
  z0_.resize(p_.size());
  n_known_ = p_.size();
  for (auto& ia : interactions_) ia->on_reindex(map);
}

void World::remove_particles_by_id(const std::vector<uint64_t>& ids) {
  std::vector<char> rm(p_.size(), 0);
  for (uint64_t id : ids) {
    const long i = index_of(id);
    if (i < 0) throw std::invalid_argument("dem::World::remove_particles_by_id: no particle with id " + std::to_string(id));
    rm[i] = 1;
  }
  remove_particles(rm);
}

// Grows the per-particle arrays after particles were appended (new pairs/histories start empty).
void World::resize_per_particle() {
  const std::size_t n = p_.size(), nw = walls_.size();
  if (n == n_known_ && whist_.size() == n * nw) return;
  if (whist_.size() != n_known_ * nw) {
    // walls were added: re-lay the wall histories out as [particle][wall]
    const std::size_t nw_old = n_known_ > 0 ? whist_.size() / n_known_ : 0;
    SVec<std::array<double, 3>> h(n * nw, std::array<double, 3>{{0, 0, 0}});
    for (std::size_t i = 0; i < n_known_; ++i)
      for (std::size_t w = 0; w < nw_old && w < nw; ++w) h[i * nw + w] = whist_[i * nw_old + w];
    whist_.swap(h);
  } else {
    whist_.resize(n * nw, std::array<double, 3>{{0, 0, 0}});
  }
  if (istart_.size() < n + 1) istart_.resize(n + 1, npairs_);
  if (istart_.empty()) istart_.assign(n + 1, 0);
  const std::size_t last = istart_.size() > n_known_ ? istart_[n_known_] : 0;
  istart_.resize(n + 1);
  for (std::size_t i = n_known_ + 1; i <= n; ++i) istart_[i] = static_cast<uint32_t>(last);
  x0_.resize(n);
  y0_.resize(n);
  z0_.resize(n);
  wtouch_.assign(n, 1);
  n_known_ = n;
  bonds_dirty_ = true;
  need_rebuild_ = true;
}

// ------------------------------------------------------------------ walls
int World::add_plane(const double point[3], const double normal[3], int material) {
  if (material < 0 || material >= prm_.materials.n())
    throw std::invalid_argument("dem::World::add_plane: material index " + std::to_string(material) +
                                " not in [0, " + std::to_string(prm_.materials.n()) + ")");
  resize_per_particle();
  const std::size_t n = p_.size(), nw = walls_.size();
  walls_.push_back(PlanarWall::make(point, normal, material));
  SVec<std::array<double, 3>> h(n * (nw + 1), std::array<double, 3>{{0, 0, 0}});
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t w = 0; w < nw; ++w) h[i * (nw + 1) + w] = whist_[i * nw + w];
  whist_.swap(h);
  wtouch_.assign(n, 1);
  return static_cast<int>(walls_.size()) - 1;
}

int World::add_box(const double lo[3], const double hi[3], int material, bool with_top) {
  for (int k = 0; k < 3; ++k)
    if (!(hi[k] > lo[k])) throw std::invalid_argument("dem::World::add_box: need hi > lo in every axis");
  const int first = static_cast<int>(walls_.size());
  for (int k = 0; k < 3; ++k) {
    double nlo[3] = {0, 0, 0}, nhi[3] = {0, 0, 0};
    nlo[k] = 1;
    nhi[k] = -1;
    add_plane(lo, nlo, material);
    if (k < 2 || with_top) add_plane(hi, nhi, material);
  }
  return first;
}

void World::set_wall_velocity(int k, const double v[3]) {
  PlanarWall& w = walls_.at(k);
  for (int a = 0; a < 3; ++a) w.v[a] = v[a];
}

void World::set_wall_position(int k, const double point[3]) {
  PlanarWall& w = walls_.at(k);
  for (int a = 0; a < 3; ++a) w.p[a] = point[a];
}

// ------------------------------------------------------------------ bonds
std::size_t World::n_bonds_intact() const {
  sync_bonds();
  std::size_t n = 0;
  for (const Bond& b : bonds_) n += b.alive ? 1 : 0;
  return n;
}

std::size_t World::bond_pairs(const std::vector<std::pair<std::size_t, std::size_t>>& pairs, const BondParams& bp) {
  bp.validate();
  resize_per_particle();
  if (bonds_dirty_) rebuild_bond_csr();
  std::size_t added = 0;
  std::set<std::pair<std::size_t, std::size_t>> seen;
  for (const auto& pr : pairs) {
    std::size_t i = pr.first, j = pr.second;
    if (i >= p_.size() || j >= p_.size() || i == j)
      throw std::invalid_argument("dem::World::bond_pairs: invalid pair (" + std::to_string(i) + ", " +
                                  std::to_string(j) + ") for " + std::to_string(p_.size()) + " particles");
    if (i > j) std::swap(i, j);
    if (bonded(static_cast<uint32_t>(i), static_cast<uint32_t>(j)) || !seen.insert({i, j}).second) continue;
    Bond b;
    b.i = static_cast<uint32_t>(i);
    b.j = static_cast<uint32_t>(j);
    b.rb = bp.radius > 0 ? bp.radius : bp.radius_multiplier * std::min(p_.r[i], p_.r[j]);  // Eq. 20
    b.A = M_PI * b.rb * b.rb;                                                                // Eq. 23
    b.J = 0.5 * M_PI * b.rb * b.rb * b.rb * b.rb;
    b.kn = bp.kn;
    b.kt = bp.kt;
    b.sigma_c = bp.sigma_c;
    b.tau_c = bp.tau_c;
    b.damping = bp.damping;
    bonds_.push_back(b);
    ++added;
  }
  bonds_dirty_ = true;
  need_rebuild_ = true;  // bonded pairs leave the contact list
  dt_checked_ = false;
  return added;
}

std::size_t World::bond_within(double gap_tolerance, const BondParams& bp, std::size_t first, std::size_t last) {
  bp.validate();
  if (!std::isfinite(gap_tolerance))
    throw std::invalid_argument("dem::World::bond_within: gap tolerance must be finite");
  if (last > p_.size()) last = p_.size();
  if (first >= last) return 0;
  double rmax = 0;
  for (std::size_t i = first; i < last; ++i) rmax = std::max(rmax, p_.r[i]);
  CellGrid g;
  g.build(p_, first, last, 2 * rmax + std::max(gap_tolerance, 0.0));
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = first; i < last; ++i) {
    int cx, cy, cz;
    g.coords(g.cell_of[i - first], cx, cy, cz);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const int ax = cx + dx, ay = cy + dy, az = cz + dz;
          if (ax < 0 || ay < 0 || az < 0 || ax >= g.nx || ay >= g.ny || az >= g.nz) continue;
          const int c = g.cell_index(ax, ay, az);
          for (uint32_t s = g.start[c]; s < g.start[c + 1]; ++s) {
            const std::size_t j = g.items[s];
            if (j <= i) continue;
            const double ddx = p_.x[j] - p_.x[i], ddy = p_.y[j] - p_.y[i], ddz = p_.z[j] - p_.z[i];
            const double gap = std::sqrt(ddx * ddx + ddy * ddy + ddz * ddz) - p_.r[i] - p_.r[j];
            if (gap < gap_tolerance) pairs.emplace_back(i, j);
          }
        }
  }
  std::sort(pairs.begin(), pairs.end());
  return bond_pairs(pairs, bp);
}

uint32_t World::bond_prm_index(const Bond& b) {
  const double v[8] = {b.kn, b.kt, b.A, b.J, b.rb, b.damping, b.sigma_c, b.tau_c};
  std::array<uint64_t, 8> key;
  std::memcpy(key.data(), v, sizeof v);
  const auto it = bprm_index_.find(key);
  if (it != bprm_index_.end()) return it->second;
  const uint32_t k = static_cast<uint32_t>(bprm_.size());
  bprm_.push_back(BondPrm{b.kn, b.kt, b.A, b.J, b.rb, b.damping, b.sigma_c, b.tau_c});
  bprm_index_.emplace(key, k);
  return k;
}

void World::sync_bonds() const {
  if (!bhot_ahead_) return;
  for (std::size_t b = 0; b < bhot_.size(); ++b) {
    const BondHot& h = bhot_[b];
    Bond& bd = bonds_[b];
    bd.fn = h.fn;
    bd.tn = h.tn;
    for (int k = 0; k < 3; ++k) {
      bd.ft[k] = h.ft[k];
      bd.tt[k] = h.tt[k];
    }
    bd.alive = static_cast<char>(h.alive);
  }
  bhot_ahead_ = false;
}

void World::rebuild_bond_csr() {
  sync_bonds();
  // drop broken bonds, then index bonds per particle
  std::size_t nb = 0;
  for (std::size_t b = 0; b < bonds_.size(); ++b)
    if (bonds_[b].alive) bonds_[nb++] = bonds_[b];
  bonds_.resize(nb);
  dead_bonds_ = 0;
  const std::size_t n = p_.size();
  bstart_.assign(n + 1, 0);
  for (const Bond& b : bonds_) {
    ++bstart_[b.i + 1];
    ++bstart_[b.j + 1];
  }
  for (std::size_t i = 0; i < n; ++i) bstart_[i + 1] += bstart_[i];
  bref_.resize(2 * nb);
  cnt_.assign(bstart_.begin(), bstart_.end() - 1);
  for (std::size_t b = 0; b < nb; ++b) {
    bref_[cnt_[bonds_[b].i]++] = static_cast<uint32_t>(2 * b);
    bref_[cnt_[bonds_[b].j]++] = static_cast<uint32_t>(2 * b + 1);
  }
  bcode_.resize(nb);
  bonds_damped_ = false;
  for (const Bond& b : bonds_) bonds_damped_ = bonds_damped_ || b.damping > 0.0;
  bonds_dirty_ = false;
  bhot_stale_ = true;  // built when the bond loop next runs (not per bond_pairs call of a filling chamber)
}

void World::build_bond_hot() {
  const std::size_t nb = bonds_.size(), n = p_.size();
  bhot_.resize(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    const Bond& bd = bonds_[b];
    BondHot& h = bhot_[b];
    h.i = bd.i;
    h.j = bd.j;
    h.prm = bond_prm_index(bd);
    h.alive = 1;
    h.fn = bd.fn;
    h.tn = bd.tn;
    for (int k = 0; k < 3; ++k) {
      h.ft[k] = bd.ft[k];
      h.tt[k] = bd.tt[k];
    }
  }
  // bond_forces adds a bond's force straight to a particle whose bonds all fall in one of its T contiguous chunks;
  // a particle with bonds in two chunks gets them after the loop, in bond order
  const long nbl = static_cast<long>(nb);
  const long T = (nt_ > 1 && nbl >= kMinParallel) ? std::min(nt_, 256) : 1;
  bchunks_ = static_cast<int>(T);
  std::vector<int> chunk_of(n, -1);
  std::vector<char> shared(n, 0);
  for (long t = 0; t < T; ++t)
    for (long b = nbl * t / T; b < nbl * (t + 1) / T; ++b)
      for (uint32_t p : {bonds_[b].i, bonds_[b].j}) {
        if (chunk_of[p] >= 0 && chunk_of[p] != t) shared[p] = 1;
        chunk_of[p] = static_cast<int>(t);
      }
  bdefer_.clear();
  for (std::size_t b = 0; b < nb; ++b) {
    BondHot& h = bhot_[b];
    h.defer_i = static_cast<uint8_t>(shared[h.i]);
    h.defer_j = static_cast<uint8_t>(shared[h.j]);
    if (h.defer_i || h.defer_j) bdefer_.push_back(static_cast<uint32_t>(b));
  }
  bout_.resize(bdefer_.size());
  bhot_stale_ = false;
}

bool World::bonded(uint32_t i, uint32_t j) const {
  auto joins = [j](const auto& b) { return b.alive && (b.i == j || b.j == j); };  // a Bond or a BondHot
  for (uint32_t s = bstart_[i]; s < bstart_[i + 1]; ++s) {
    const uint32_t b = bref_[s] >> 1;
    if (bhot_ahead_ ? joins(bhot_[b]) : joins(bonds_[b])) return true;
  }
  return false;
}

// ------------------------------------------------------------------ time step
TimeStepCheck World::time_step_check() const {
  sync_bonds();
  return check_time_step(prm_.dt, p_, prm_.materials, bonds_, prm_.max_rayleigh_fraction);
}

void World::require_stable_time_step() const {
  const TimeStepCheck c = time_step_check();
  if (!c.ok) throw std::invalid_argument(c.message);
}

void World::set_dt(double dt) {
  if (!(dt > 0)) throw std::invalid_argument("dem::World::set_dt: dt must be > 0 s, got " + std::to_string(dt));
  prm_.dt = dt;
  dt_checked_ = false;
}

// ------------------------------------------------------------------ neighbour list
void World::rebuild() {
  if (bonds_dirty_) rebuild_bond_csr();
  const std::size_t n = p_.size();
  double rmax = 0;
  for (std::size_t i = 0; i < n; ++i) rmax = std::max(rmax, p_.r[i]);
  if (skin_ < 0) skin_ = 0.2 * rmax;
  grid_.build(p_, 0, n, 2 * rmax + skin_);
  const double skin = skin_;
  const CellGrid& g = grid_;
  cnt_.resize(n + 1);
  // pass 1: count pairs per owner (i < j) ; pass 2: fill. Both in the same fixed order.
  for (int pass = 0; pass < 2; ++pass) {
    if (pass == 1) {
      // prefix sum -> new istart (kept in cnt_), sized buffers
      uint32_t acc = 0;
      for (std::size_t i = 0; i < n; ++i) {
        const uint32_t c = cnt_[i];
        cnt_[i] = acc;
        acc += c;
      }
      cnt_[n] = acc;
      if (pj2_.size() < acc) {
        const std::size_t cap = acc + acc / 4 + 16;
        pj2_.resize(cap);
        pi2_.resize(cap);
        hist2_.resize(cap);
        touch2_.resize(cap);
      }
    }
    const char* gh = ghost_.size() == n ? ghost_.data() : nullptr;
    chunked(nt_, static_cast<long>(n), [&](long ib, long ie, int) {
    for (long i = ib; i < ie; ++i) {
      const double xi = p_.x[i], yi = p_.y[i], zi = p_.z[i], ri = p_.r[i];
      int cx, cy, cz;
      g.coords(g.cell_of[i], cx, cy, cz);
      uint32_t count = 0;
      uint32_t out = pass == 1 ? cnt_[i] : 0;
      const uint32_t os = istart_[i], oe = istart_[i + 1];
      for (int dz = -1; dz <= 1; ++dz) {
        const int az = cz + dz;
        if (az < 0 || az >= g.nz) continue;
        for (int dy = -1; dy <= 1; ++dy) {
          const int ay = cy + dy;
          if (ay < 0 || ay >= g.ny) continue;
          for (int dx = -1; dx <= 1; ++dx) {
            const int ax = cx + dx;
            if (ax < 0 || ax >= g.nx) continue;
            const int c = g.cell_index(ax, ay, az);
            for (uint32_t s = g.start[c]; s < g.start[c + 1]; ++s) {
              const uint32_t j = g.items[s];
              if (j <= i || (gh && gh[i] && gh[j])) continue;  // two ghosts: no rank needs their contact here
              const double ddx = p_.x[j] - xi, ddy = p_.y[j] - yi, ddz = p_.z[j] - zi;
              const double cut = ri + p_.r[j] + skin;
              if (ddx * ddx + ddy * ddy + ddz * ddz >= cut * cut) continue;
              if (bstart_[i] != bstart_[i + 1] && bonded(static_cast<uint32_t>(i), j)) continue;
              if (pass == 0) {
                ++count;
              } else {
                pi2_[out] = static_cast<uint32_t>(i);
                pj2_[out] = j;
                std::array<double, 3> h{{0, 0, 0}};
                uint8_t tc = 0;
                for (uint32_t q = os; q < oe; ++q)
                  if (pj_[q] == j) {
                    h = hist_[q];
                    tc = touch_[q];
                    break;
                  }
                hist2_[out] = h;
                touch2_[out] = tc;
                ++out;
              }
            }
          }
        }
      }
      if (pass == 0) cnt_[i] = count;
    }
    });
  }
  // the new list is ordered by owner, but within an owner by cell order; sort each owner's pairs by j so
  // the lookup above and the gather order do not depend on the grid
  npairs_ = cnt_[n];
  chunked(nt_, static_cast<long>(n), [&](long ib, long ie, int) {
  for (long i = ib; i < ie; ++i) {
    const uint32_t s = cnt_[i], e = cnt_[i + 1];
    for (uint32_t a = s + 1; a < e; ++a) {  // insertion sort (few entries)
      const uint32_t j = pj2_[a];
      const std::array<double, 3> h = hist2_[a];
      const uint8_t tc = touch2_[a];
      uint32_t b = a;
      while (b > s && pj2_[b - 1] > j) {
        pj2_[b] = pj2_[b - 1];
        hist2_[b] = hist2_[b - 1];
        touch2_[b] = touch2_[b - 1];
        --b;
      }
      pj2_[b] = j;
      hist2_[b] = h;
      touch2_[b] = tc;
    }
  }
  });
  pj_.swap(pj2_);
  pi_.swap(pi2_);
  hist_.swap(hist2_);
  touch_.swap(touch2_);
  istart_.assign(cnt_.begin(), cnt_.begin() + n + 1);
  build_slabs();
  chunked(nt_, static_cast<long>(n), [&](long ib, long ie, int) {
    for (long i = ib; i < ie; ++i) {
      x0_[i] = p_.x[i];
      y0_[i] = p_.y[i];
      z0_[i] = p_.z[i];
    }
  });
  need_rebuild_ = false;
  growth_since_build_ = 0;
  ++nrebuild_;
}

// Groups the grid's cell layers along its longest axis into slabs of about n / kSlabs particles. The pair list
// only joins particles of the same or adjacent cells, hence of the same or adjacent slabs.
void World::build_slabs() {
  constexpr std::size_t kSlabs = 64;
  const CellGrid& g = grid_;
  const std::size_t n = p_.size();
  const int axis = (g.nx >= g.ny && g.nx >= g.nz) ? 0 : (g.ny >= g.nz ? 1 : 2);
  const int nl = axis == 0 ? g.nx : (axis == 1 ? g.ny : g.nz);
  auto layer = [&](std::size_t i) {
    int c[3];
    g.coords(g.cell_of[i], c[0], c[1], c[2]);
    return c[axis];
  };
  cnt_.assign(static_cast<std::size_t>(nl) + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++cnt_[layer(i)];
  const std::size_t target = std::max<std::size_t>(1, n / kSlabs);
  slab_of_layer_.resize(nl);
  uint32_t ns = 0;
  std::size_t acc = 0;
  for (int l = 0; l < nl; ++l) {
    slab_of_layer_[l] = ns;
    acc += cnt_[l];
    if (acc >= target && l + 1 < nl) {
      ++ns;
      acc = 0;
    }
  }
  ++ns;
  sstart_.assign(ns + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++sstart_[slab_of_layer_[layer(i)] + 1];
  for (uint32_t s = 0; s < ns; ++s) sstart_[s + 1] += sstart_[s];
  sorder_.resize(n);
  cnt_.assign(sstart_.begin(), sstart_.end() - 1);
  slab_of_.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    slab_of_[i] = slab_of_layer_[layer(i)];
    sorder_[cnt_[slab_of_[i]]++] = static_cast<uint32_t>(i);
  }
}

bool World::insert_pairs(std::vector<std::pair<uint32_t, uint32_t>>& add) {
  if (need_rebuild_ || skin_ < 0 || slab_of_.size() != p_.size() || istart_.size() != p_.size() + 1) return false;
  std::sort(add.begin(), add.end());
  add.erase(std::unique(add.begin(), add.end()), add.end());
  std::size_t k = 0;
  for (const auto& [i, j] : add) {
    if (i >= j || j >= p_.size()) return false;
    const uint32_t si = slab_of_[i], sj = slab_of_[j];
    if ((si > sj ? si - sj : sj - si) > 1) return false;  // pair_forces' blocks rely on adjacent slabs
    if (!std::binary_search(pj_.begin() + istart_[i], pj_.begin() + istart_[i + 1], j)) add[k++] = {i, j};
  }
  add.resize(k);
  if (add.empty()) return true;
  // merge from the back: entries after an insertion point move up by the insertions still ahead of them
  const std::size_t n_old = npairs_, n_new = n_old + add.size();
  for (auto* v : {&pi_, &pj_}) v->resize(std::max(v->size(), n_new));
  hist_.resize(std::max(hist_.size(), n_new));
  touch_.resize(std::max(touch_.size(), n_new));
  long src = static_cast<long>(n_old) - 1, dst = static_cast<long>(n_new) - 1, a = static_cast<long>(add.size()) - 1;
  while (a >= 0) {
    if (src >= 0 && std::make_pair(pi_[src], pj_[src]) > add[a]) {
      pi_[dst] = pi_[src];
      pj_[dst] = pj_[src];
      hist_[dst] = hist_[src];
      touch_[dst] = touch_[src];
      --src;
    } else {
      pi_[dst] = add[a].first;
      pj_[dst] = add[a].second;
      hist_[dst] = {{0, 0, 0}};
      touch_[dst] = 0;
      --a;
    }
    --dst;
  }
  npairs_ = n_new;
  std::size_t q = 0;
  uint32_t shift = 0;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    while (q < add.size() && add[q].first == i) ++shift, ++q;
    istart_[i + 1] += shift;
  }
  return true;
}

// ------------------------------------------------------------------ forces
// Pair forces, added straight into f, t (which hold gravity at this point). A slab's pairs only write to
// particles of slabs s-1..s+1, so blocks of >= 2 slabs of one parity run in parallel without conflicts (even
// blocks, then odd ones), and each particle receives its terms in the same order whatever the thread count
// or the schedule. Non-touching pairs cost a distance test (and a history reset
// when they just separated).
void World::pair_forces() {
  if (npairs_ == 0) return;
  const double ovf = prm_.max_overlap_fraction > 0 ? prm_.max_overlap_fraction
                                                     : std::numeric_limits<double>::infinity();
  bad_thr_.assign(static_cast<std::size_t>(nt_), 0);
  constexpr uint32_t kBlock = 32;
  constexpr long kSlabsPerBlock = 4;  // >= 2
  auto slab = [this, ovf](long s, int th) {
    // local copies: the byte stores below (touch flags) may alias anything, members would be reloaded
    const double dt = prm_.dt;
    const PairProps* PP = &prm_.materials.pair(0, 0);  // row-major n x n table
    const int nm = prm_.materials.n();
    const double* x = p_.x.data(); const double* y = p_.y.data(); const double* z = p_.z.data();
    const double* vx = p_.vx.data(); const double* vy = p_.vy.data(); const double* vz = p_.vz.data();
    const double* wx = p_.wx.data(); const double* wy = p_.wy.data(); const double* wz = p_.wz.data();
    const double* r = p_.r.data(); const double* im = p_.inv_m.data();
    const int* mat = p_.material.data();
    double* fx = p_.fx.data(); double* fy = p_.fy.data(); double* fz = p_.fz.data();
    double* tx = p_.tx.data(); double* ty = p_.ty.data(); double* tz = p_.tz.data();
    const uint32_t* PJ = pj_.data();
    const uint32_t* IS = istart_.data();
    const uint32_t* SO = sorder_.data();
    const uint32_t* SS = sstart_.data();
    std::array<double, 3>* H = hist_.data();
    uint8_t* TC = touch_.data();
    int last_pidx = -1;
    Lanes4 E{}, G{}, be{}, skk{}, fr{}, mur{};
    char seen = 0;
    for (uint32_t k = SS[s]; k < SS[s + 1]; ++k) {
      const uint32_t i = SO[k];
      const uint32_t qb = IS[i], qe = IS[i + 1];
      if (qb == qe) continue;
      const double xi = x[i], yi = y[i], zi = z[i], ri = r[i], imi = im[i];
      const double vxi = vx[i], vyi = vy[i], vzi = vz[i], wxi = wx[i], wyi = wy[i], wzi = wz[i];
      const int mati = mat[i];
      double f0 = 0, f1 = 0, f2 = 0, t0 = 0, t1 = 0, t2 = 0;
      // blocks of pairs: a branch-free distance pass lists the touching ones, then their forces (touching
      // or not is close to random in a dense packing: no mispredicted branch per pair)
      for (uint32_t q0 = qb; q0 < qe; q0 += kBlock) {
        const uint32_t q1 = std::min(qe, q0 + kBlock);
        uint32_t tq[kBlock + 4];
        alignas(32) double td2[kBlock + 4], tdx[kBlock + 4], tdy[kBlock + 4], tdz[kBlock + 4], trj[kBlock + 4];
        uint32_t nb = 0;
        for (uint32_t q = q0; q < q1; ++q) {
          const uint32_t j = PJ[q];
          const double dx = xi - x[j], dy = yi - y[j], dz = zi - z[j];
          const double rj = r[j], rs = ri + rj;
          const double d2 = dx * dx + dy * dy + dz * dz;
          const uint8_t now = d2 < rs * rs, before = TC[q];
          TC[q] = now;
          tq[nb] = q;
          td2[nb] = d2; tdx[nb] = dx; tdy[nb] = dy; tdz[nb] = dz; trj[nb] = rj;
          nb += now;
          if (before > now) H[q][0] = H[q][1] = H[q][2] = 0.0;  // separated: history reset
        }
        if (nb == 0) continue;
        // touching pairs 4 at a time (Lanes4); spare lanes of the last group repeat the first pair, their
        // results are dropped
        for (uint32_t k = nb; k % 4; ++k) {
          tq[k] = tq[0];
          td2[k] = td2[0]; tdx[k] = tdx[0]; tdy[k] = tdy[0]; tdz[k] = tdz[0]; trj[k] = trj[0];
        }
      for (uint32_t k0 = 0; k0 < nb; k0 += 4) {
        uint32_t qs[4], js[4];
        Lanes4 dx, dy, dz, d2, rj, imj, vxj, vyj, vzj, wxj, wyj, wzj, hx, hy, hz;
        std::memcpy(&dx, tdx + k0, sizeof dx);
        std::memcpy(&dy, tdy + k0, sizeof dy);
        std::memcpy(&dz, tdz + k0, sizeof dz);
        std::memcpy(&d2, td2 + k0, sizeof d2);
        std::memcpy(&rj, trj + k0, sizeof rj);
        int pidx[4];
        for (int l = 0; l < 4; ++l) {
          const uint32_t q = tq[k0 + l], j = PJ[q];
          qs[l] = q;
          js[l] = j;
          imj[l] = im[j];
          vxj[l] = vx[j]; vyj[l] = vy[j]; vzj[l] = vz[j];
          wxj[l] = wx[j]; wyj[l] = wy[j]; wzj[l] = wz[j];
          hx[l] = H[q][0]; hy[l] = H[q][1]; hz[l] = H[q][2];
          pidx[l] = mati * nm + mat[j];
        }
        // pair properties: broadcast when the 4 lanes share a material pair (kept from the last group)
        if (pidx[0] == pidx[1] && pidx[0] == pidx[2] && pidx[0] == pidx[3]) {
          if (pidx[0] != last_pidx) {
            const PairProps& pp = PP[pidx[0]];
            const Lanes4 o{};
            E = o + pp.E_star; G = o + pp.G_star; be = o + pp.beta; fr = o + pp.friction;
            mur = o + pp.rolling_friction;
            skk = o + (pp.sqrt_kt_kn > 0 ? pp.sqrt_kt_kn : std::sqrt(4.0 * pp.G_star / pp.E_star));
            last_pidx = pidx[0];
          }
        } else {
          for (int l = 0; l < 4; ++l) {
            const PairProps& pp = PP[pidx[l]];
            E[l] = pp.E_star; G[l] = pp.G_star; be[l] = pp.beta; fr[l] = pp.friction;
            mur[l] = pp.rolling_friction;
            skk[l] = pp.sqrt_kt_kn > 0 ? pp.sqrt_kt_kn : std::sqrt(4.0 * pp.G_star / pp.E_star);
          }
          last_pidx = -1;
        }
        const Lanes4 rs = ri + rj;
        const Lanes4 d = lanes::sqrt(d2), id = 1.0 / d, irs = 1.0 / rs;
        const Lanes4 n[3] = {dx * id, dy * id, dz * id};  // from j to i
        const Lanes4 ai = d * ri * irs, aj = d - ai;       // centre-to-contact distances
        // v_i + w_i x (-ai n) - v_j - w_j x (aj n)
        const Lanes4 vrel[3] = {vxi - vxj - ai * (wyi * n[2] - wzi * n[1]) - aj * (wyj * n[2] - wzj * n[1]),
                                vyi - vyj - ai * (wzi * n[0] - wxi * n[2]) - aj * (wzj * n[0] - wxj * n[2]),
                                vzi - vzj - ai * (wxi * n[1] - wyi * n[0]) - aj * (wxj * n[1] - wyj * n[0])};
        const Lanes4 wrel[3] = {wxi - wxj, wyi - wyj, wzi - wzj};
        const Lanes4 reff = ri * rj * irs, meff = 1.0 / (imi + imj);
        const Lanes4 delta = rs - d;
        Lanes4 h[3] = {hx, hy, hz}, fn, f[3], ft[3], tr[3];
        hertz_mindlin_lanes<Lanes4>(delta, n, vrel, wrel, reff, meff, E, G, be, skk, fr, mur, dt, h, fn, f, ft, tr);
        // torques: -ai n x f + T_r on i ; (aj n) x (-f) - T_r on j
        const Lanes4 cx = n[1] * f[2] - n[2] * f[1], cy = n[2] * f[0] - n[0] * f[2], cz = n[0] * f[1] - n[1] * f[0];
        const Lanes4 ti0 = -ai * cx + tr[0], ti1 = -ai * cy + tr[1], ti2 = -ai * cz + tr[2];
        const Lanes4 tj0 = -aj * cx - tr[0], tj1 = -aj * cy - tr[1], tj2 = -aj * cz - tr[2];
        const uint32_t nl = std::min<uint32_t>(4, nb - k0);
        for (uint32_t l = 0; l < nl; ++l) {
          const uint32_t q = qs[l], j = js[l];
          if (delta[l] > ovf * std::min(ri, rj[l])) seen = 1;
          H[q][0] = h[0][l]; H[q][1] = h[1][l]; H[q][2] = h[2][l];
          f0 += f[0][l]; f1 += f[1][l]; f2 += f[2][l];
          t0 += ti0[l]; t1 += ti1[l]; t2 += ti2[l];
          fx[j] -= f[0][l]; fy[j] -= f[1][l]; fz[j] -= f[2][l];
          tx[j] += tj0[l]; ty[j] += tj1[l]; tz[j] += tj2[l];
        }
      }
      }
      fx[i] += f0; fy[i] += f1; fz[i] += f2;
      tx[i] += t0; ty[i] += t1; tz[i] += t2;
    }
    if (seen) bad_thr_[th] = 1;
  };
  // blocks of kSlabsPerBlock consecutive slabs, even blocks then odd ones; a block writes to its slabs and
  // the one on each side, which belong to blocks of the other parity
  const long ns = static_cast<long>(sstart_.size()) - 1;
  const long nblk = (ns + kSlabsPerBlock - 1) / kSlabsPerBlock;
  auto block = [&](long b, int th) {
    for (long s = b * kSlabsPerBlock; s < std::min(ns, (b + 1) * kSlabsPerBlock); ++s) slab(s, th);
  };
  if (nt_ > 1 && npairs_ >= static_cast<std::size_t>(kMinParallel) && nblk > 2) {
#pragma omp parallel num_threads(nt_)
    {
      const int th = omp_get_thread_num();
      for (long c = 0; c < 2; ++c) {
#pragma omp for schedule(dynamic, 1)
        for (long b = c; b < nblk; b += 2) block(b, th);
      }
    }
  } else {
    for (long c = 0; c < 2; ++c)
      for (long b = c; b < nblk; b += 2) block(b, 0);
  }
  for (char b : bad_thr_)
    if (b) {  // the first pair (in list order) beyond the bound
      const double* x = p_.x.data(); const double* y = p_.y.data(); const double* z = p_.z.data();
      const double* r = p_.r.data();
      for (std::size_t q = 0; q < npairs_; ++q) {
        const uint32_t i = pi_[q], j = pj_[q];
        const double dx = x[i] - x[j], dy = y[i] - y[j], dz = z[i] - z[j];
        const double ov = (r[i] + r[j] - std::sqrt(dx * dx + dy * dy + dz * dz)) / std::min(r[i], r[j]);
        if (ov > ovf)
          blow_up(i, ov, "overlap with particle id " + std::to_string(p_.id[j]) + " is " + std::to_string(ov) +
                             " of the smaller radius (bound max_overlap_fraction = " +
                             std::to_string(prm_.max_overlap_fraction) + ")");
      }
    }
}

void World::bond_forces() {
  if (bhot_stale_) build_bond_hot();
  const long nb = static_cast<long>(bhot_.size());
  if (nb == 0) return;
  bhot_ahead_ = true;
  const double dt = prm_.dt;
  std::array<long, 256> nbr{};
  const Particles& P = p_;
  const bool damped = bonds_damped_;
  // 4 bonds at a time (Lanes4; a short last group repeats its first bond in the spare lanes). The forces go straight
  // into the particles (which hold gravity and the pair forces), bond by bond: each particle gets its bonds' terms
  // in bond order, whatever the thread count. The chunks are build_bond_hot's: a particle with bonds in two of
  // them (defer_i, defer_j) gets those terms from bout_ after the loop, still in bond order.
  const long T = bchunks_;
  auto chunk = [&](long bb, long be, int th) {
    BondHot* B = bhot_.data();
    const BondPrm* PR = bprm_.data();
    uint8_t* C = bcode_.data();
    double* fx = p_.fx.data(); double* fy = p_.fy.data(); double* fz = p_.fz.data();
    double* tx = p_.tx.data(); double* ty = p_.ty.data(); double* tz = p_.tz.data();
    const double* x = P.x.data(); const double* y = P.y.data(); const double* z = P.z.data();
    const double* vx = P.vx.data(); const double* vy = P.vy.data(); const double* vz = P.vz.data();
    const double* wx = P.wx.data(); const double* wy = P.wy.data(); const double* wz = P.wz.data();
    const double* r = P.r.data(); const double* im = P.inv_m.data(); const double* iI = P.inv_I.data();
    long broken = 0;
    for (long b0 = bb; b0 < be; b0 += 4) {
      // the lanes are built in registers from four scalars each (element stores into a vector in memory, read
      // back whole, stall on store forwarding)
      const BondHot& b_0 = B[b0];
      const BondHot& b_1 = B[b0 + 1 < be ? b0 + 1 : b0];
      const BondHot& b_2 = B[b0 + 2 < be ? b0 + 2 : b0];
      const BondHot& b_3 = B[b0 + 3 < be ? b0 + 3 : b0];
      const BondPrm &p_0 = PR[b_0.prm], &p_1 = PR[b_1.prm], &p_2 = PR[b_2.prm], &p_3 = PR[b_3.prm];
      const uint32_t i0 = b_0.i, i1 = b_1.i, i2 = b_2.i, i3 = b_3.i, j0 = b_0.j, j1 = b_1.j, j2 = b_2.j, j3 = b_3.j;
      auto at_i = [&](const double* a) { return Lanes4{a[i0], a[i1], a[i2], a[i3]}; };
      auto at_j = [&](const double* a) { return Lanes4{a[j0], a[j1], a[j2], a[j3]}; };
      auto of = [&](double BondPrm::*m) { return Lanes4{p_0.*m, p_1.*m, p_2.*m, p_3.*m}; };
      auto st = [&](double BondHot::*m) { return Lanes4{b_0.*m, b_1.*m, b_2.*m, b_3.*m}; };
      auto of3 = [&](double (BondHot::*m)[3], int k) {
        return Lanes4{(b_0.*m)[k], (b_1.*m)[k], (b_2.*m)[k], (b_3.*m)[k]};
      };
      Lanes4 xi[3] = {at_i(x), at_i(y), at_i(z)}, xj[3] = {at_j(x), at_j(y), at_j(z)};
      Lanes4 vi[3] = {at_i(vx), at_i(vy), at_i(vz)}, vj[3] = {at_j(vx), at_j(vy), at_j(vz)};
      Lanes4 wi[3] = {at_i(wx), at_i(wy), at_i(wz)}, wj[3] = {at_j(wx), at_j(wy), at_j(wz)};
      const Lanes4 ri = at_i(r), rj = at_j(r);
      const Lanes4 zero{};
      const Lanes4 imi = damped ? at_i(im) : zero, imj = damped ? at_j(im) : zero;  // damping only
      const Lanes4 iIi = damped ? at_i(iI) : zero, iIj = damped ? at_j(iI) : zero;
      const Lanes4 kn = of(&BondPrm::kn), kt = of(&BondPrm::kt), A = of(&BondPrm::A), J = of(&BondPrm::J);
      const Lanes4 rb = of(&BondPrm::rb), zeta = of(&BondPrm::damping);
      Lanes4 fn = st(&BondHot::fn), tn = st(&BondHot::tn);
      Lanes4 ft[3] = {of3(&BondHot::ft, 0), of3(&BondHot::ft, 1), of3(&BondHot::ft, 2)};
      Lanes4 tt[3] = {of3(&BondHot::tt, 0), of3(&BondHot::tt, 1), of3(&BondHot::tt, 2)};
      Lanes4 sigma, tau, f[3], ti[3], tj[3];
      bond_law_lanes<Lanes4>(xi, xj, vi, vj, wi, wj, ri, rj, imi, imj, iIi, iIj, kn, kt, A, J, rb, zeta, damped, dt,
                             fn, ft, tn, tt, sigma, tau, f, ti, tj);
      const long nl = std::min<long>(4, be - b0);
      for (long l = 0; l < nl; ++l) {
        BondHot& bd = B[b0 + l];
        const BondPrm& bp = PR[bd.prm];
        const int code = bd.alive ? bond_break_code(bp.sigma_c, bp.tau_c, sigma[l], tau[l]) : 0;
        C[b0 + l] = static_cast<uint8_t>(code);
        if (!bd.alive || code) {  // no force; a breaking bond keeps its spring state
          broken += code != 0;
          continue;
        }
        bd.fn = fn[l];
        bd.tn = tn[l];
        for (int k = 0; k < 3; ++k) {
          bd.ft[k] = ft[k][l];
          bd.tt[k] = tt[k][l];
        }
        const uint32_t i = bd.i, j = bd.j;
        if (bd.defer_i | bd.defer_j) {
          const long s = std::lower_bound(bdefer_.begin(), bdefer_.end(), static_cast<uint32_t>(b0 + l)) -
                         bdefer_.begin();
          BondOutSlot& o = bout_[s];
          for (int k = 0; k < 3; ++k) {
            o.f[k] = f[k][l];
            o.ti[k] = ti[k][l];
            o.tj[k] = tj[k][l];
          }
        }
        if (!bd.defer_i) {
          fx[i] -= f[0][l]; fy[i] -= f[1][l]; fz[i] -= f[2][l];
          tx[i] += ti[0][l]; ty[i] += ti[1][l]; tz[i] += ti[2][l];
        }
        if (!bd.defer_j) {
          fx[j] += f[0][l]; fy[j] += f[1][l]; fz[j] += f[2][l];
          tx[j] += tj[0][l]; ty[j] += tj[1][l]; tz[j] += tj[2][l];
        }
      }
    }
    nbr[th] = broken;
  };
  if (T == 1) {
    chunk(0, nb, 0);
  } else {
#pragma omp parallel for num_threads(T) schedule(static, 1)
    for (long t = 0; t < T; ++t) chunk(nb * t / T, nb * (t + 1) / T, static_cast<int>(t));
  }
  // the deferred sides, in bond order
  for (std::size_t s = 0; s < bdefer_.size(); ++s) {
    const uint32_t b = bdefer_[s];
    const BondHot& bd = bhot_[b];
    if (!bd.alive || bcode_[b]) continue;
    const BondOutSlot& o = bout_[s];
    const uint32_t i = bd.i, j = bd.j;
    if (bd.defer_i) {
      p_.fx[i] -= o.f[0]; p_.fy[i] -= o.f[1]; p_.fz[i] -= o.f[2];
      p_.tx[i] += o.ti[0]; p_.ty[i] += o.ti[1]; p_.tz[i] += o.ti[2];
    }
    if (bd.defer_j) {
      p_.fx[j] += o.f[0]; p_.fy[j] += o.f[1]; p_.fz[j] += o.f[2];
      p_.tx[j] += o.tj[0]; p_.ty[j] += o.tj[1]; p_.tz[j] += o.tj[2];
    }
  }
  long nbroken = 0;
  for (long c : nbr) nbroken += c;
  if (nbroken == 0) return;
  std::vector<std::pair<uint32_t, uint32_t>> freed;
  for (long b = 0; b < nb; ++b) {  // serial, in bond order: deterministic log
    if (!bcode_[b]) continue;
    BondHot& bd = bhot_[b];
    const BondPrm& bp = bprm_[bd.prm];
    freed.emplace_back(std::min(bd.i, bd.j), std::max(bd.i, bd.j));
    // a breaking bond kept its spring state: the same evaluation again gives its stresses
    Lanes4 xi[3], xj[3], vi[3], vj[3], wi[3], wj[3], fn, ft[3], tn, tt[3], sigma, tau, f[3], ti[3], tj[3];
    const uint32_t i = bd.i, j = bd.j;
    const double* ps[9] = {P.x.data(), P.y.data(), P.z.data(), P.vx.data(), P.vy.data(), P.vz.data(),
                           P.wx.data(), P.wy.data(), P.wz.data()};
    for (int k = 0; k < 3; ++k) {
      xi[k] = Lanes4{} + ps[k][i]; xj[k] = Lanes4{} + ps[k][j];
      vi[k] = Lanes4{} + ps[3 + k][i]; vj[k] = Lanes4{} + ps[3 + k][j];
      wi[k] = Lanes4{} + ps[6 + k][i]; wj[k] = Lanes4{} + ps[6 + k][j];
      ft[k] = Lanes4{} + bd.ft[k]; tt[k] = Lanes4{} + bd.tt[k];
    }
    fn = Lanes4{} + bd.fn;
    tn = Lanes4{} + bd.tn;
    const Lanes4 o = Lanes4{};
    bond_law_lanes<Lanes4>(xi, xj, vi, vj, wi, wj, o + P.r[i], o + P.r[j], o + P.inv_m[i], o + P.inv_m[j],
                           o + P.inv_I[i], o + P.inv_I[j], o + bp.kn, o + bp.kt, o + bp.A, o + bp.J, o + bp.rb,
                           o + bp.damping, damped, dt, fn, ft, tn, tt, sigma, tau, f, ti, tj);
    bd.alive = 0;
    BondBreak e;
    e.t = t_;  // already the end of this step
    const double ri = p_.r[bd.i], rj = p_.r[bd.j], s = ri / (ri + rj);
    e.x[0] = p_.x[bd.i] + s * (p_.x[bd.j] - p_.x[bd.i]);
    e.x[1] = p_.y[bd.i] + s * (p_.y[bd.j] - p_.y[bd.i]);
    e.x[2] = p_.z[bd.i] + s * (p_.z[bd.j] - p_.z[bd.i]);
    e.id_i = p_.id[bd.i];
    e.id_j = p_.id[bd.j];
    e.tensile = bcode_[b] == 1;
    e.sigma = sigma[0];
    e.tau = tau[0];
    breaks_.push_back(e);
  }
  // the broken pairs take part in Hertz-Mindlin contact from the next step on: they join the neighbour list
  // (a rebuild only when they cannot); the bond index drops them once they are 1/32 of the bonds (until then they
  // add a zero force, the alive ones keep their order: the same sums bit for bit)
  dead_bonds_ += static_cast<std::size_t>(nbroken);
  if (32 * dead_bonds_ > bonds_.size()) bonds_dirty_ = true;
  if (!insert_pairs(freed)) need_rebuild_ = true;
}

namespace {
// Raw arrays of the particle state, copied into locals in the hot loops (no reloads after stores).
struct State {
  double *x, *y, *z, *vx, *vy, *vz, *wx, *wy, *wz, *fx, *fy, *fz, *tx, *ty, *tz;
  const double *m, *im, *iI, *r, *x0, *y0, *z0;
  const char* fixed;
};

// Half kick with the forces in f, t (not for fixed particles), drift, and f, t reset to gravity for the force
// evaluation that follows. Returns the squared displacement since the last build (infinity if not finite: the
// rebuild then reports the particle).
inline double kick_drift_reset(const State& s, long i, double dt, const double g[3]) {
  const double hdt = 0.5 * dt;
  if (!s.fixed[i]) {
    const double im = s.im[i], iI = s.iI[i];
    s.vx[i] += hdt * s.fx[i] * im; s.vy[i] += hdt * s.fy[i] * im; s.vz[i] += hdt * s.fz[i] * im;
    s.wx[i] += hdt * s.tx[i] * iI; s.wy[i] += hdt * s.ty[i] * iI; s.wz[i] += hdt * s.tz[i] * iI;
  }
  s.x[i] += dt * s.vx[i]; s.y[i] += dt * s.vy[i]; s.z[i] += dt * s.vz[i];
  const double mi = s.m[i];
  s.fx[i] = mi * g[0]; s.fy[i] = mi * g[1]; s.fz[i] = mi * g[2];
  s.tx[i] = s.ty[i] = s.tz[i] = 0.0;
  const double ddx = s.x[i] - s.x0[i], ddy = s.y[i] - s.y0[i], ddz = s.z[i] - s.z0[i];
  const double d2 = ddx * ddx + ddy * ddy + ddz * ddz;
  return d2 == d2 ? d2 : std::numeric_limits<double>::infinity();
}

// Non-finite position or velocity (NaN and infinities survive the sum).
inline bool state_bad(const State& s, long i) {
  const double a = s.x[i] + s.y[i] + s.z[i] + s.vx[i] + s.vy[i] + s.vz[i] + s.wx[i] + s.wy[i] + s.wz[i];
  return !std::isfinite(a);
}

State state_of(Particles& p, const SVec<double>& x0, const SVec<double>& y0, const SVec<double>& z0) {
  return State{p.x.data(),  p.y.data(),  p.z.data(),  p.vx.data(),    p.vy.data(),    p.vz.data(),
               p.wx.data(), p.wy.data(), p.wz.data(), p.fx.data(),    p.fy.data(),    p.fz.data(),
               p.tx.data(), p.ty.data(), p.tz.data(), p.m.data(),     p.inv_m.data(), p.inv_I.data(),
               p.r.data(),  x0.data(),   y0.data(),   z0.data(),      p.fixed.data()};
}
}  // namespace

// Per particle, in fixed order: wall contacts are added to gravity + pair and bond forces. With kick,
// the velocity half-step that ends this step follows (and the finiteness check); with drift also the half
// kick and drift that begin the next step (the arithmetic is the same as in separate loops).
void World::gather_forces(bool kick, bool drift) {
  const long n = static_cast<long>(p_.size());
  const std::size_t nw = walls_.size();
  if (nw == 0 && !kick && !drift) return;  // nothing to add (the liners of a chamber are meshes: no planes)
  const double dt = prm_.dt, hdt = 0.5 * dt;
  const double g[3] = {prm_.gravity[0], prm_.gravity[1], prm_.gravity[2]};
  const MaterialTable& mt = prm_.materials;
  const double ovf = prm_.max_overlap_fraction > 0 ? prm_.max_overlap_fraction
                                                     : std::numeric_limits<double>::infinity();
  std::fill(wforce_thr_.begin(), wforce_thr_.end(), 0.0);
  std::fill(maxd_thr_.begin(), maxd_thr_.end(), 0.0);
  bad_thr_.assign(static_cast<std::size_t>(nt_), 0);
  wplane_.resize(4 * nw);
  for (std::size_t k = 0; k < nw; ++k) {
    const PlanarWall& w = walls_[k];
    for (int a = 0; a < 3; ++a) wplane_[4 * k + a] = w.n[a];
    wplane_[4 * k + 3] = w.n[0] * w.p[0] + w.n[1] * w.p[1] + w.n[2] * w.p[2];
  }
  const double* wplane = wplane_.data();
  const State S0 = state_of(p_, x0_, y0_, z0_);
  chunked(nt_, n, [&](long ib, long ie, int th) {
    const State S = S0;
    double* wf = wforce_thr_.data() + static_cast<std::size_t>(th) * nw * 3;
    char* wt = wtouch_.data();
    std::array<double, 3>* WH = whist_.data();
    double maxd2 = 0;
    char bad = 0;
    for (long i = ib; i < ie; ++i) {
      double f[3] = {S.fx[i], S.fy[i], S.fz[i]}, t[3] = {S.tx[i], S.ty[i], S.tz[i]};
      const char touched = wt[i];
      char touching = 0;
      const double xi = S.x[i], yi = S.y[i], zi = S.z[i], ri = S.r[i];
      for (std::size_t k = 0; k < nw; ++k) {
        const double* wp = wplane + 4 * k;  // n, n . p
        const double dist = xi * wp[0] + yi * wp[1] + zi * wp[2] - wp[3];
        if (dist >= ri) {  // no contact: clear the history (only read when the particle had wall contacts)
          if (touched) {
            std::array<double, 3>& h0 = WH[i * nw + k];
            h0[0] = h0[1] = h0[2] = 0.0;
          }
          continue;
        }
        touching = 1;
        if (ri - dist > ovf * ri) bad = 1;
        const PlanarWall& w = walls_[k];
        std::array<double, 3>& h = WH[i * nw + k];
        const double* nn = w.n;
        const double wxi = S.wx[i], wyi = S.wy[i], wzi = S.wz[i];
        // v_i + w_i x (-dist n) - v_wall
        const double vrel[3] = {S.vx[i] - dist * (wyi * nn[2] - wzi * nn[1]) - w.v[0],
                                S.vy[i] - dist * (wzi * nn[0] - wxi * nn[2]) - w.v[1],
                                S.vz[i] - dist * (wxi * nn[1] - wyi * nn[0]) - w.v[2]};
        const double wrel[3] = {wxi, wyi, wzi};
        ContactForce c;
        hertz_mindlin(ri - dist, nn, vrel, wrel, ri, S.m[i], mt.pair(p_.material[i], w.material), dt, h.data(), c);
        f[0] += c.f[0]; f[1] += c.f[1]; f[2] += c.f[2];
        t[0] += -dist * (nn[1] * c.f[2] - nn[2] * c.f[1]) + c.troll[0];
        t[1] += -dist * (nn[2] * c.f[0] - nn[0] * c.f[2]) + c.troll[1];
        t[2] += -dist * (nn[0] * c.f[1] - nn[1] * c.f[0]) + c.troll[2];
        wf[3 * k] -= c.f[0]; wf[3 * k + 1] -= c.f[1]; wf[3 * k + 2] -= c.f[2];
      }
      if (touched != touching) wt[i] = touching;
      S.fx[i] = f[0]; S.fy[i] = f[1]; S.fz[i] = f[2];
      S.tx[i] = t[0]; S.ty[i] = t[1]; S.tz[i] = t[2];
      if (kick) {
        if (!S.fixed[i]) {
          const double im = S.im[i], iI = S.iI[i];
          S.vx[i] += hdt * f[0] * im; S.vy[i] += hdt * f[1] * im; S.vz[i] += hdt * f[2] * im;
          S.wx[i] += hdt * t[0] * iI; S.wy[i] += hdt * t[1] * iI; S.wz[i] += hdt * t[2] * iI;
        }
        if (state_bad(S, i)) bad = 1;
      }
      if (drift) maxd2 = std::max(maxd2, kick_drift_reset(S, i, dt, g));
    }
    if (drift) maxd_thr_[th] = maxd2;
    if (bad) bad_thr_[th] = 1;
  });
  for (std::size_t k = 0; k < nw; ++k) {
    double s[3] = {0, 0, 0};
    for (int th = 0; th < nt_; ++th)
      for (int a = 0; a < 3; ++a) s[a] += wforce_thr_[(static_cast<std::size_t>(th) * nw + k) * 3 + a];
    for (int a = 0; a < 3; ++a) walls_[k].force[a] = s[a];
  }
  check_blow_up(true);
}

// After a loop that flagged bad_thr_: finds the first particle (in index order) with a non-finite state or a
// wall overlap beyond the bound and stops the run.
void World::check_blow_up(bool walls) {
  bool any = false;
  for (char b : bad_thr_) any = any || b;
  if (!any) return;
  const long n = static_cast<long>(p_.size());
  const State S = state_of(p_, x0_, y0_, z0_);
  const double ovf = prm_.max_overlap_fraction;
  for (long i = 0; i < n; ++i) {
    if (state_bad(S, i)) blow_up(i, std::numeric_limits<double>::quiet_NaN(), "non-finite position or velocity");
    if (!walls || !(ovf > 0)) continue;
    for (std::size_t k = 0; k < walls_.size(); ++k) {
      const double* wp = wplane_.data() + 4 * k;
      const double ov = (p_.r[i] - (S.x[i] * wp[0] + S.y[i] * wp[1] + S.z[i] * wp[2] - wp[3])) / p_.r[i];
      if (ov > ovf)
        blow_up(i, ov, "overlap with wall " + std::to_string(k) + " is " + std::to_string(ov) +
                           " of the radius (bound max_overlap_fraction = " + std::to_string(ovf) + ")");
    }
  }
}

namespace {
// The blow-up dump's rows; false if a write failed. Closes f.
bool write_state_rows(FILE* f, const Particles& p) {
  std::fprintf(f, "id,x,y,z,vx,vy,vz,wx,wy,wz,fx,fy,fz,r,m,material,fixed\n");
  for (std::size_t i = 0; i < p.size(); ++i)
    std::fprintf(f, "%llu,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%d,%d\n",
                 static_cast<unsigned long long>(p.id[i]), p.x[i], p.y[i], p.z[i], p.vx[i], p.vy[i], p.vz[i], p.wx[i],
                 p.wy[i], p.wz[i], p.fx[i], p.fy[i], p.fz[i], p.r[i], p.m[i], p.material[i], int(p.fixed[i]));
  const bool ok = !std::ferror(f);
  return std::fclose(f) == 0 && ok;
}
}  // namespace

void World::write_state_csv(const std::string& path) const {
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f || !write_state_rows(f, p_)) throw std::runtime_error("cannot write " + path);
}

// Writes the state dump and throws BlowUp naming the step, the particle and the dump. Without a dump path the dump is
// a new file of a name nobody can guess (mkstemps) in the temporary folder: a fixed name there could be a link,
// planted by someone else, to a file the run would overwrite.
void World::blow_up(long i, double overlap, const std::string& what) {
  std::string path = prm_.blowup_dump_path;
  std::string dump;
  try {
    if (path.empty()) {
      std::string tmpl = (std::filesystem::temp_directory_path() / "dem_blowup_XXXXXX.csv").string();
      const int fd = ::mkstemps(tmpl.data(), 4);
      if (fd < 0) throw std::runtime_error("cannot create " + tmpl + ": " + std::strerror(errno));
      path = tmpl;
      FILE* f = ::fdopen(fd, "w");
      if (!f) {
        ::close(fd);
        throw std::runtime_error("cannot write " + path);
      }
      if (!write_state_rows(f, p_)) throw std::runtime_error("cannot write " + path);
    } else {
      write_state_csv(path);
    }
    dump = "state dump " + path;
  } catch (const std::exception& e) {
    dump = "state dump failed: " + std::string(e.what());
    path.clear();
  }
  char buf[512];
  std::snprintf(buf, sizeof buf, "DEM blow-up at step %ld (t = %.9g s): particle id %llu (index %ld) at (%.6g, %.6g, %.6g) m, "
                "v (%.6g, %.6g, %.6g) m/s, radius %.6g m: ",
                nstep_ + 1, t_, static_cast<unsigned long long>(p_.id[i]), i, p_.x[i], p_.y[i], p_.z[i], p_.vx[i],
                p_.vy[i], p_.vz[i], p_.r[i]);
  throw BlowUp(std::string(buf) + what + "; " + dump + " (reduce the time step or check the input)", nstep_ + 1,
               p_.id[i], overlap, path);
}

// ------------------------------------------------------------------ stepping
void World::prepare() {
  resize_per_particle();
  if (bonds_dirty_) rebuild_bond_csr();
  if (prm_.check_time_step && !dt_checked_ && p_.size() > 0) require_stable_time_step();
  dt_checked_ = true;
  wforce_thr_.resize(static_cast<std::size_t>(nt_) * walls_.size() * 3);
  maxd_thr_.resize(static_cast<std::size_t>(nt_));
  bad_thr_.resize(static_cast<std::size_t>(nt_));
}

void World::move_walls() {
  for (PlanarWall& w : walls_)
    for (int a = 0; a < 3; ++a) w.p[a] += prm_.dt * w.v[a];
}

// Velocity Verlet. Between two steps of one call the closing half kick of a step, the opening half kick and
// the drift of the next are done in the same particle loop as the force gather.
void World::step(long nsteps) {
  if (nsteps < 0) throw std::invalid_argument("dem::World::step: negative step count");
  if (nsteps == 0) return;
  if (opened_) throw std::logic_error("dem::World::step: called between step_begin() and step_end()");
  open_step();
  run_steps(nsteps);
}

void World::step_begin() {
  if (opened_) throw std::logic_error("dem::World::step_begin: called twice without step_end()");
  open_step();
  opened_ = true;
}

void World::step_end() {
  if (!opened_) throw std::logic_error("dem::World::step_end: no step_begin() before it");
  opened_ = false;
  // the caller may have moved particles (ghosts) since the drift: their displacement since the build is re-measured
  const long n = static_cast<long>(p_.size());
  double m2 = 0;
  for (long i = 0; i < n; ++i) {
    const double dx = p_.x[i] - x0_[i], dy = p_.y[i] - y0_[i], dz = p_.z[i] - z0_[i];
    const double d2 = dx * dx + dy * dy + dz * dz;
    m2 = std::max(m2, d2 == d2 ? d2 : std::numeric_limits<double>::infinity());
  }
  std::fill(maxd_thr_.begin(), maxd_thr_.end(), 0.0);
  if (!maxd_thr_.empty()) maxd_thr_[0] = m2;
  run_steps(1);
}

// The opening half kick and drift of a call's first step (later steps' are fused with the force gather).
void World::open_step() {
  prepare();
  const auto t0 = std::chrono::steady_clock::now();
  const long n = static_cast<long>(p_.size());
  std::fill(maxd_thr_.begin(), maxd_thr_.end(), 0.0);
  const double g[3] = {prm_.gravity[0], prm_.gravity[1], prm_.gravity[2]};
  chunked(nt_, n, [&](long ib, long ie, int th) {
    const State S = state_of(p_, x0_, y0_, z0_);
    double maxd2 = 0;
    for (long i = ib; i < ie; ++i) maxd2 = std::max(maxd2, kick_drift_reset(S, i, prm_.dt, g));
    maxd_thr_[th] = maxd2;
  });
  move_walls();
  phase_s_[0] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void World::run_steps(long nsteps) {
  const long n = static_cast<long>(p_.size());
  const double g[3] = {prm_.gravity[0], prm_.gravity[1], prm_.gravity[2]};
  using clk = std::chrono::steady_clock;
  auto t1 = clk::now();
  auto lap = [this, &t1](int k) {
    const auto now = clk::now();
    phase_s_[k] += std::chrono::duration<double>(now - t1).count();
    t1 = now;
  };
  for (long s = 0; s < nsteps; ++s) {
    const bool last = s == nsteps - 1;
    double maxd2 = 0;
    for (double v : maxd_thr_) maxd2 = std::max(maxd2, v);
    if (maxd2 == std::numeric_limits<double>::infinity()) {  // a non-finite position after the drift
      std::fill(bad_thr_.begin(), bad_thr_.end(), 1);
      check_blow_up(false);
    }
    // a radius change counts like a displacement of the particle's surface (set_radius)
    growth_since_build_ += step_growth_;
    step_growth_ = 0;
    const bool moved_out = 2.0 * (std::sqrt(maxd2) + growth_since_build_) > skin_;
    if (need_rebuild_ || skin_ < 0 || moved_out)
      rebuild();
    else if (bonds_dirty_)
      rebuild_bond_csr();  // broken bonds reached 1/32 (their pairs were inserted into the list)
    lap(1);
    t_ += prm_.dt;
    pair_forces();
    lap(2);
    bond_forces();
    lap(3);
    if (interactions_.empty()) {
      gather_forces(true, !last);
      lap(4);
    } else {
      gather_forces(false, false);
      lap(4);
      for (auto& ia : interactions_) {
        ia->add_forces(p_, t_, prm_.dt);
        const auto [ov, i] = ia->worst_overlap();
        if (prm_.max_mesh_overlap_fraction > 0 && ov > prm_.max_mesh_overlap_fraction && i >= 0)
          blow_up(i, ov, "overlap with " + ia->label() + " is " + std::to_string(ov) +
                             " of the radius (bound max_mesh_overlap_fraction = " +
                             std::to_string(prm_.max_mesh_overlap_fraction) + ")");
      }
      lap(5);
      const double hdt = 0.5 * prm_.dt;
      std::fill(maxd_thr_.begin(), maxd_thr_.end(), 0.0);
      bad_thr_.assign(static_cast<std::size_t>(nt_), 0);
      chunked(nt_, n, [&](long ib, long ie, int th) {
        const State S = state_of(p_, x0_, y0_, z0_);
        double m2 = 0;
        char bad = 0;
        for (long i = ib; i < ie; ++i) {
          if (!S.fixed[i]) {
            const double im = S.im[i], iI = S.iI[i];
            S.vx[i] += hdt * S.fx[i] * im; S.vy[i] += hdt * S.fy[i] * im; S.vz[i] += hdt * S.fz[i] * im;
            S.wx[i] += hdt * S.tx[i] * iI; S.wy[i] += hdt * S.ty[i] * iI; S.wz[i] += hdt * S.tz[i] * iI;
          }
          if (state_bad(S, i)) bad = 1;
          if (!last) m2 = std::max(m2, kick_drift_reset(S, i, prm_.dt, g));
        }
        maxd_thr_[th] = m2;
        if (bad) bad_thr_[th] = 1;
      });
      check_blow_up(false);
      lap(6);
    }
    if (!last) move_walls();
    ++nstep_;
  }
}

// ------------------------------------------------------------------ observables
double World::kinetic_energy() const {
  double e = 0;
  for (std::size_t i = 0; i < p_.size(); ++i) {
    e += 0.5 * p_.m[i] * (p_.vx[i] * p_.vx[i] + p_.vy[i] * p_.vy[i] + p_.vz[i] * p_.vz[i]);
    e += 0.5 / p_.inv_I[i] * (p_.wx[i] * p_.wx[i] + p_.wy[i] * p_.wy[i] + p_.wz[i] * p_.wz[i]);
  }
  return e;
}

std::size_t World::n_contacts() const {
  std::size_t c = 0;
  for (std::size_t q = 0; q < npairs_; ++q) {
    const uint32_t i = pi_[q], j = pj_[q];
    const double dx = p_.x[i] - p_.x[j], dy = p_.y[i] - p_.y[j], dz = p_.z[i] - p_.z[j];
    const double rs = p_.r[i] + p_.r[j];
    if (dx * dx + dy * dy + dz * dz < rs * rs) ++c;
  }
  return c;
}

std::size_t World::n_wall_contacts() const {
  std::size_t c = 0;
  for (const PlanarWall& w : walls_)
    for (std::size_t i = 0; i < p_.size(); ++i) {
      const double dist = (p_.x[i] - w.p[0]) * w.n[0] + (p_.y[i] - w.p[1]) * w.n[1] + (p_.z[i] - w.p[2]) * w.n[2];
      if (dist < p_.r[i]) ++c;
    }
  return c;
}

double World::bytes_per_particle() const {
  const double n = std::max<std::size_t>(p_.size(), 1);
  double b = 19.0 * 8 * p_.x.capacity() + 8.0 * p_.id.capacity() + 4.0 * p_.material.capacity();
  b += 3.0 * 8 * x0_.capacity() + 4.0 * (istart_.capacity() + sorder_.capacity() + bstart_.capacity());
  b += 24.0 * whist_.capacity();
  b += 4.0 * (grid_.items.capacity() + grid_.cell_of.capacity() + grid_.start.capacity());
  // neighbour pairs belong to the particles (contacts)
  b += (4.0 + 4.0 + 24.0 + 1.0) * (pj_.capacity() + pj2_.capacity()) + 4.0 * cnt_.capacity();
  return b / n;
}

double World::bytes_per_bond() const {
  const double nb = std::max<std::size_t>(bonds_.size(), 1);
  return (sizeof(Bond) * bonds_.capacity() + sizeof(BondHot) * bhot_.capacity() + sizeof(BondPrm) * bprm_.capacity() +
          sizeof(BondOutSlot) * bout_.capacity() + bcode_.capacity() + 4.0 * bref_.capacity()) / nb;
}

}  // namespace dem
