// dem::World::assemble (world.hpp): the whole charge put back together from the owned parts of a domain
// decomposition's Worlds, for the charge to be cut anew (ghost_domains.hpp).
#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>
#include <utility>
#include <vector>

#include "dem/world.hpp"

namespace dem {

void World::assemble(const std::vector<const World*>& parts, const std::vector<std::vector<char>>& owned,
                     std::vector<uint64_t>* dangling) {
  if (parts.empty() || parts.size() != owned.size())
    throw std::invalid_argument("World::assemble: " + std::to_string(parts.size()) + " parts and " +
                                std::to_string(owned.size()) + " ownership masks (one per part, at least one)");
  const std::size_t nw = walls_.size();
  // (id, part, index) of every owned particle, in id order
  std::vector<std::tuple<uint64_t, std::size_t, uint32_t>> order;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const World& w = *parts[k];
    if (owned[k].size() != w.p_.size())
      throw std::invalid_argument("World::assemble: part " + std::to_string(k) + " has " +
                                  std::to_string(w.p_.size()) + " particles, its mask " +
                                  std::to_string(owned[k].size()));
    bool same = w.walls_.size() == nw && w.interactions_.size() == interactions_.size();
    for (std::size_t a = 0; same && a < interactions_.size(); ++a)
      same = w.interactions_[a]->label() == interactions_[a]->label();
    if (!same)
      throw std::invalid_argument("World::assemble: part " + std::to_string(k) +
                                  " has other walls or interactions than this World");
    for (std::size_t i = 0; i < w.p_.size(); ++i)
      if (owned[k][i]) order.emplace_back(w.p_.id[i], k, static_cast<uint32_t>(i));
  }
  std::sort(order.begin(), order.end());
  std::unordered_map<uint64_t, uint32_t> at;  // id -> index in the assembled World
  for (std::size_t a = 0; a < order.size(); ++a) {
    if (a > 0 && std::get<0>(order[a]) == std::get<0>(order[a - 1]))
      throw std::invalid_argument("World::assemble: particle id " + std::to_string(std::get<0>(order[a])) +
                                  " is owned by two parts");
    at[std::get<0>(order[a])] = static_cast<uint32_t>(a);
  }
  const std::size_t n = order.size();
  // index in the assembled World; -1 (with `dangling`) for a particle no part owns
  auto index = [&](const World& w, uint32_t i, const char* what) -> long {
    const auto it = at.find(w.p_.id[i]);
    if (it != at.end()) return it->second;
    if (dangling) return -1;
    throw std::invalid_argument(std::string("World::assemble: a ") + what + " reaches particle id " +
                                std::to_string(w.p_.id[i]) + ", which no part owns");
  };

  Particles np;
  np.reserve(n);
  {
    auto dst = np.doubles();
    for (auto* v : dst) v->resize(n);
    np.id.resize(n), np.material.resize(n), np.fixed.resize(n);
  }
  SVec<char> wtouch(n, 0);
  SVec<std::array<double, 3>> whist(n * nw, std::array<double, 3>{{0, 0, 0}});
  for (std::size_t a = 0; a < n; ++a) {
    const auto [id, k, i] = order[a];
    const World& w = *parts[k];
    const auto src = w.p_.doubles();
    auto dst = np.doubles();
    for (std::size_t c = 0; c < src.size(); ++c) (*dst[c])[a] = (*src[c])[i];
    np.id[a] = id, np.material[a] = w.p_.material[i], np.fixed[a] = w.p_.fixed[i];
    if (i < w.wtouch_.size()) wtouch[a] = w.wtouch_[i];
    for (std::size_t q = 0; q < nw; ++q)
      if ((i + 1) * nw <= w.whist_.size()) whist[a * nw + q] = w.whist_[i * nw + q];
  }
  for (const World* w : parts) np.next_id = std::max(np.next_id, w->p_.next_id);

  std::vector<Bond> bonds;
  std::vector<std::tuple<uint32_t, uint32_t, std::array<double, 3>, uint8_t>> pairs;
  std::vector<BondBreak> breaks;
  for (std::size_t k = 0; k < parts.size(); ++k) {
    const World& w = *parts[k];
    w.sync_bonds();
    for (const Bond& b : w.bonds_) {
      if (!owned[k][b.i]) continue;
      const long ci = index(w, b.i, "bond"), cj = index(w, b.j, "bond");
      if (cj < 0) {  // its second particle is in no part: dropped, its first one named
        if (b.alive) dangling->push_back(w.p_.id[b.i]);
        continue;
      }
      Bond c = b;
      c.i = static_cast<uint32_t>(ci);
      c.j = static_cast<uint32_t>(cj);
      bonds.push_back(c);
    }
    for (std::size_t q = 0; q < w.npairs_; ++q) {
      const uint32_t i = w.pi_[q], j = w.pj_[q];
      const auto& h = w.hist_[q];
      static const std::array<double, 3> zero{{0.0, 0.0, 0.0}};  // any bit set: -0.0 is kept too, as save_state does
      if (!owned[k][i] || !(w.touch_[q] || std::memcmp(h.data(), zero.data(), sizeof zero) != 0)) continue;
      const long la = index(w, i, "neighbour pair"), lb = index(w, j, "neighbour pair");
      if (lb < 0) {
        dangling->push_back(w.p_.id[i]);
        continue;
      }
      const auto a = static_cast<uint32_t>(la), b = static_cast<uint32_t>(lb);
      pairs.emplace_back(std::min(a, b), std::max(a, b), h, w.touch_[q]);
    }
    for (const BondBreak& e : w.breaks_) {
      const long i = w.index_of(e.id_i);
      if (i >= 0 && owned[k][static_cast<std::size_t>(i)]) breaks.push_back(e);
    }
  }
  std::sort(bonds.begin(), bonds.end(), [](const Bond& a, const Bond& b) { return std::tie(a.i, a.j) < std::tie(b.i, b.j); });
  std::sort(pairs.begin(), pairs.end(), [](const auto& a, const auto& b) {
    return std::tie(std::get<0>(a), std::get<1>(a)) < std::tie(std::get<0>(b), std::get<1>(b));
  });
  std::stable_sort(breaks.begin(), breaks.end(), [](const BondBreak& a, const BondBreak& b) { return a.t < b.t; });

  for (std::size_t a = 0; a < interactions_.size(); ++a) {  // after every check on the particles, before the commit
    std::vector<const Interaction*> ia;
    for (const World* w : parts) ia.push_back(w->interactions_[a].get());
    interactions_[a]->assemble_state(ia);
  }

  // commit (as load_state does)
  const World& p0 = *parts[0];
  p_ = std::move(np);
  walls_ = p0.walls_;
  wtouch_.swap(wtouch);
  whist_.swap(whist);
  bonds_ = std::move(bonds);
  bhot_ahead_ = false;  // bhot_ is rebuilt from bonds_ before the next step (bonds_dirty_)
  breaks_ = std::move(breaks);
  npairs_ = pairs.size();
  pi_.assign(npairs_, 0), pj_.assign(npairs_, 0), hist_.assign(npairs_, std::array<double, 3>{{0, 0, 0}});
  touch_.assign(npairs_, 0);
  istart_.assign(n + 1, 0);
  for (std::size_t q = 0; q < npairs_; ++q) {
    std::tie(pi_[q], pj_[q], hist_[q], touch_[q]) = pairs[q];
    ++istart_[pi_[q] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) istart_[i + 1] += istart_[i];
  x0_.assign(p_.x.begin(), p_.x.end());
  y0_.assign(p_.y.begin(), p_.y.end());
  z0_.assign(p_.z.begin(), p_.z.end());
  n_known_ = n;
  t_ = p0.t_;
  nstep_ = p0.nstep_;
  nrebuild_ = p0.nrebuild_;
  skin_ = p0.skin_;
  prm_.dt = p0.prm_.dt;
  dt_checked_ = p0.dt_checked_;
  bonds_dirty_ = true;
  need_rebuild_ = true;
  ghost_.clear();
}

}  // namespace dem

namespace dem {

void World::set_ghosts(const std::vector<char>& ghost) {
  if (ghost.size() != p_.size())
    throw std::invalid_argument("World::set_ghosts: mask of " + std::to_string(ghost.size()) + " for " +
                                std::to_string(p_.size()) + " particles");
  ghost_ = ghost;
  sync_bonds();
  std::size_t nb = 0;  // bonds between two ghosts: their owners compute them
  for (const Bond& b : bonds_)
    if (!(ghost[b.i] && ghost[b.j])) bonds_[nb++] = b;
  if (nb != bonds_.size()) {
    bonds_.resize(nb);
    bonds_dirty_ = true;
  }
  need_rebuild_ = true;  // the neighbour list leaves out pairs of two ghosts
  for (auto& ia : interactions_) ia->set_ghosts(p_, ghost);
}

}  // namespace dem
