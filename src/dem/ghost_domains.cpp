#include "dem/ghost_domains.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "core/binary_io.hpp"

namespace dem {

GhostPlan cut_domain(World& w, const RankLayout& layout, int rank) {
  const std::size_t n = w.particles().size();
  const int P = static_cast<int>(layout.owned.size());
  if (layout.owner.size() != n)
    throw std::invalid_argument("cut_domain: the layout has " + std::to_string(layout.owner.size()) +
                                " particles, the World " + std::to_string(n));
  if (rank < 0 || rank >= P)
    throw std::invalid_argument("cut_domain: rank " + std::to_string(rank) + " of " + std::to_string(P));
  // new index of each kept particle (the World keeps the order of those it keeps)
  std::vector<long> at(n, -1);
  std::vector<char> remove(n, 1);
  for (uint32_t i : layout.owned[rank]) remove[i] = 0;
  for (uint32_t i : layout.ghosts[rank]) remove[i] = 0;
  long k = 0;
  for (std::size_t i = 0; i < n; ++i)
    if (!remove[i]) at[i] = k++;
  for (const Bond& b : w.bonds()) {
    if (!b.alive) continue;
    const bool own_i = layout.owner[b.i] == rank, own_j = layout.owner[b.j] == rank;
    if ((own_i && at[b.j] < 0) || (own_j && at[b.i] < 0))
      throw std::invalid_argument("cut_domain: the bond of particles " + std::to_string(w.particles().id[b.i]) +
                                  " and " + std::to_string(w.particles().id[b.j]) + " crosses rank " +
                                  std::to_string(rank) + "'s ghost layer: the reach is shorter than the bond");
  }
  GhostPlan plan;
  plan.rank = rank;
  plan.send.resize(P);
  plan.recv.resize(P);
  for (int q = 0; q < P; ++q) {
    if (q == rank) continue;
    for (uint32_t i : layout.ghosts[q])  // ascending whole-charge index
      if (layout.owner[i] == rank) plan.send[q].push_back(static_cast<uint32_t>(at[i]));
    for (uint32_t i : layout.ghosts[rank])
      if (layout.owner[i] == q) plan.recv[q].push_back(static_cast<uint32_t>(at[i]));
  }
  plan.owned.assign(static_cast<std::size_t>(k), 0);
  for (uint32_t i : layout.owned[rank]) plan.owned[at[i]] = 1;
  w.remove_particles(remove);
  std::vector<char> ghost(plan.owned.size());
  for (std::size_t i = 0; i < ghost.size(); ++i) ghost[i] = plan.owned[i] ? 0 : 1;
  w.set_ghosts(ghost);
  return plan;
}

void pack_ghosts(const Particles& p, const std::vector<uint32_t>& idx, std::vector<double>& buf) {
  buf.resize(idx.size() * kGhostDoubles);
  double* b = buf.data();
  for (uint32_t i : idx) {
    *b++ = p.x[i], *b++ = p.y[i], *b++ = p.z[i];
    *b++ = p.vx[i], *b++ = p.vy[i], *b++ = p.vz[i];
    *b++ = p.wx[i], *b++ = p.wy[i], *b++ = p.wz[i];
  }
}

void unpack_ghosts(Particles& p, const std::vector<uint32_t>& idx, const double* b) {
  for (uint32_t i : idx) {
    p.x[i] = *b++, p.y[i] = *b++, p.z[i] = *b++;
    p.vx[i] = *b++, p.vy[i] = *b++, p.vz[i] = *b++;
    p.wx[i] = *b++, p.wy[i] = *b++, p.wz[i] = *b++;
  }
}

std::unique_ptr<World> new_world(const WorldParams& params, const std::function<void(World&)>& setup) {
  auto w = std::make_unique<World>(params);
  if (setup) setup(*w);
  return w;
}

std::unique_ptr<World> load_world(core::BinaryReader& r, const WorldParams& params,
                                  const std::function<void(World&)>& setup) {
  auto w = new_world(params, setup);
  w->load_state(r);
  return w;
}

namespace {
std::unique_ptr<World> load(const std::string& checkpoint, const WorldParams& params,
                            const std::function<void(World&)>& setup) {
  std::istringstream is(checkpoint);
  core::BinaryReader r(is, "whole-charge state");
  return load_world(r, params, setup);
}
}  // namespace

namespace {
// Rank `rank`'s part of the charge in w (all of it, or all a migration needs): sectors `keep` or, when null,
// equal-count sectors of w's particles.
Domain cut_world(std::unique_ptr<World> w, int ranks, int rank, double reach, const SectorDecomposition* keep) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("cut_charge: rank " + std::to_string(rank) + " of " + std::to_string(ranks) +
                                " ranks (accepted: 0 <= rank < ranks)");
  Domain d;
  d.world = std::move(w);
  const Particles& p = d.world->particles();
  const double r_max = p.size() ? *std::max_element(p.r.begin(), p.r.end()) : 0.0;
  d.margin = 0.5 * (reach - 2 * r_max);
  if (!(d.margin > 0))
    throw std::invalid_argument("cut_charge: the reach " + std::to_string(reach) +
                                " m must exceed the largest contact distance 2 r_max = " + std::to_string(2 * r_max) +
                                " m");
  d.sectors = keep ? *keep : balanced_sectors(p.x.data(), p.y.data(), p.size(), ranks);
  const RankLayout layout = rank_layout(d.sectors, p.x.data(), p.y.data(), p.size(), reach);
  d.plan = cut_domain(*d.world, layout, rank);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (d.plan.owned[i]) d.x_cut.insert(d.x_cut.end(), {p.x[i], p.y[i], p.z[i]});
  return d;
}
}  // namespace

Domain cut_charge(const std::string& checkpoint, const WorldParams& params, const std::function<void(World&)>& setup,
                  int ranks, int rank, double reach) {
  return cut_world(load(checkpoint, params, setup), ranks, rank, reach, nullptr);
}

std::vector<long> owner_counts(const Domain& d) {
  const Particles& p = d.world->particles();
  std::vector<long> n(static_cast<std::size_t>(d.sectors.ranks()), 0);
  for (std::size_t i = 0; i < p.size(); ++i)
    if (d.plan.owned[i]) ++n[static_cast<std::size_t>(d.sectors.owner(p.x[i], p.y[i]))];
  return n;
}

bool needs_rebalance(const std::vector<long>& counts, double tolerance) {
  long all = 0, most = 0;
  for (long c : counts) all += c, most = std::max(most, c);
  return counts.empty() || static_cast<double>(most) > (1.0 + tolerance) * static_cast<double>(all) /
                                                           static_cast<double>(counts.size());
}

std::vector<char> migration_peers(const Domain& d, double reach) {
  const Particles& p = d.world->particles();
  const int P = d.sectors.ranks(), me = d.plan.rank;
  std::vector<char> to(static_cast<std::size_t>(P), 0);
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!d.plan.owned[i]) continue;
    const int o = d.sectors.owner(p.x[i], p.y[i]);
    to[o] = 1;
    for (int q = 0; q < P; ++q)
      if (q != o && !to[q] && d.sectors.boundary_distance(q, p.x[i], p.y[i]) < reach) to[q] = 1;
  }
  to[me] = 0;
  return to;
}

Domain migrate_domain(const std::vector<const World*>& parts, const std::vector<std::vector<char>>& owned,
                      const Domain& mine, const WorldParams& params, const std::function<void(World&)>& setup,
                      double reach) {
  auto w = new_world(params, setup);
  std::vector<uint64_t> dangling;
  w->assemble(parts, owned, &dangling);
  const int P = mine.sectors.ranks(), rank = mine.plan.rank;
  Domain d = cut_world(std::move(w), P, rank, reach, &mine.sectors);
  std::sort(dangling.begin(), dangling.end());
  const Particles& p = d.world->particles();
  for (std::size_t i = 0; i < p.size(); ++i)
    if (d.plan.owned[i] && std::binary_search(dangling.begin(), dangling.end(), p.id[i]))
      throw std::runtime_error("migration on rank " + std::to_string(rank) + ": particle " + std::to_string(p.id[i]) +
                               " lost a bond or contact whose other particle no peer sent");
  return d;
}

double Domain::max_displacement() const {
  const Particles& p = world->particles();
  double d2 = 0;
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!plan.owned[i]) continue;
    const double* c = &x_cut[3 * k++];
    const double dx = p.x[i] - c[0], dy = p.y[i] - c[1], dz = p.z[i] - c[2];
    d2 = std::max(d2, dx * dx + dy * dy + dz * dz);
  }
  return std::sqrt(d2);
}

void save_domain(Domain& d, core::BinaryWriter& w) {
  w.tag("DOMN");
  const int64_t P = static_cast<int64_t>(d.plan.send.size());
  w.put<int64_t>(P);
  w.put<int64_t>(d.plan.rank);
  w.put<double>(d.margin);
  w.put_vec(d.sectors.bounds());
  for (int64_t q = 0; q < P; ++q) {
    w.put_vec(d.plan.send[q]);
    w.put_vec(d.plan.recv[q]);
  }
  w.put_vec(d.plan.owned);
  w.put_vec(d.x_cut);
  d.world->save_state(w);
}

Domain load_domain(core::BinaryReader& r, const WorldParams& params, const std::function<void(World&)>& setup,
                   int ranks, int rank) {
  r.expect("DOMN");
  const int64_t P = r.get<int64_t>(), R = r.get<int64_t>();
  if (P != ranks || R != rank)
    r.fail("written by rank " + std::to_string(R) + " of " + std::to_string(P) + ", read by rank " +
           std::to_string(rank) + " of " + std::to_string(ranks) + " (resume with " + std::to_string(P) + " ranks)");
  Domain d;
  d.margin = r.get<double>();
  std::vector<double> bounds;
  r.get_vec(bounds, 1u << 20);
  if (bounds.size() != static_cast<std::size_t>(P) + 1) r.fail("sector bounds do not match the rank count");
  d.sectors = SectorDecomposition(bounds);
  d.plan.rank = rank;
  d.plan.send.resize(P);
  d.plan.recv.resize(P);
  for (int64_t q = 0; q < P; ++q) {
    r.get_vec(d.plan.send[q]);
    r.get_vec(d.plan.recv[q]);
  }
  r.get_vec(d.plan.owned);
  r.get_vec(d.x_cut);
  d.world = load_world(r, params, setup);
  const std::size_t n = d.world->particles().size();
  std::size_t n_owned = 0;
  for (char o : d.plan.owned) n_owned += o ? 1 : 0;
  bool in_range = d.plan.owned.size() == n && d.x_cut.size() == 3 * n_owned;
  for (int64_t q = 0; q < P; ++q)
    for (const auto* v : {&d.plan.send[q], &d.plan.recv[q]})
      for (uint32_t i : *v) in_range = in_range && i < n;
  if (!in_range) r.fail("the domain's exchange plan does not match its particles");
  std::vector<char> ghost(n);
  for (std::size_t i = 0; i < n; ++i) ghost[i] = d.plan.owned[i] ? 0 : 1;
  d.world->set_ghosts(ghost);
  return d;
}

std::string assemble_charge(const std::vector<const World*>& parts, const std::vector<std::vector<char>>& owned,
                            const WorldParams& params, const std::function<void(World&)>& setup,
                            const std::function<void(World&)>& edit) {
  const auto whole = new_world(params, setup);
  whole->assemble(parts, owned);
  if (edit) edit(*whole);
  std::ostringstream os;
  core::BinaryWriter w(os);
  whole->save_state(w);
  return os.str();
}

std::vector<BondBreak> owned_breaks(const World& w, const GhostPlan& plan) {
  std::vector<BondBreak> out;
  for (const BondBreak& b : w.breaks()) {
    const long i = w.index_of(b.id_i);
    if (i >= 0 && plan.owned[i]) out.push_back(b);
  }
  return out;
}

LocalDomains::LocalDomains(const std::string& checkpoint, const WorldParams& params,
                           const std::function<void(World&)>& setup, int ranks, double reach)
    : params_(params), setup_(setup), reach_(reach) {
  if (ranks < 1) throw std::invalid_argument("LocalDomains: ranks must be >= 1 (got " + std::to_string(ranks) + ")");
  for (int r = 0; r < ranks; ++r) domains_.push_back(cut_charge(checkpoint, params, setup, ranks, r, reach));
}

void LocalDomains::edit(const std::function<void(World&)>& edit) { recut(edit); }

void LocalDomains::recut(const std::function<void(World&)>& edit) {
  std::vector<const World*> parts;
  std::vector<std::vector<char>> owned;
  for (const Domain& d : domains_) parts.push_back(d.world.get()), owned.push_back(d.plan.owned);
  const std::string whole = assemble_charge(parts, owned, params_, setup_, edit);
  const int P = ranks();
  domains_.clear();
  for (int r = 0; r < P; ++r) domains_.push_back(cut_charge(whole, params_, setup_, P, r, reach_));
  ++recuts_;
}

double LocalDomains::max_displacement() const {
  double d = 0;
  for (const Domain& x : domains_) d = std::max(d, x.max_displacement());
  return d;
}

void LocalDomains::exchange() {
  std::vector<double> buf;
  for (int r = 0; r < ranks(); ++r)
    for (int q = 0; q < ranks(); ++q) {
      if (domains_[r].plan.send[q].empty()) continue;
      pack_ghosts(domains_[r].world->particles(), domains_[r].plan.send[q], buf);
      unpack_ghosts(domains_[q].world->particles(), domains_[q].plan.recv[r], buf.data());
    }
}

void LocalDomains::migrate() {
  const int P = ranks();
  std::vector<std::vector<char>> to;
  for (const Domain& d : domains_) to.push_back(migration_peers(d, reach_));
  std::vector<Domain> next;
  for (int r = 0; r < P; ++r) {  // rank r's parts in rank order: its own and those of the peers that send to it
    std::vector<const World*> parts;
    std::vector<std::vector<char>> owned;
    for (int q = 0; q < P; ++q)
      if (q == r || to[q][r]) parts.push_back(domains_[q].world.get()), owned.push_back(domains_[q].plan.owned);
    next.push_back(migrate_domain(parts, owned, domains_[r], params_, setup_, reach_));
  }
  domains_.swap(next);
  ++migrations_;
}

void LocalDomains::step(long n) {
  for (long s = 0; s < n; ++s) {
    if (max_displacement() > margin()) {
      std::vector<long> counts(static_cast<std::size_t>(ranks()), 0);
      for (const Domain& d : domains_) {
        const std::vector<long> c = owner_counts(d);
        for (std::size_t q = 0; q < c.size(); ++q) counts[q] += c[q];
      }
      if (needs_rebalance(counts, rebalance_tolerance_)) recut(); else migrate();
    }
    for (Domain& d : domains_) d.world->step_begin();
    exchange();
    for (Domain& d : domains_) d.world->step_end();
  }
}

void owned_state(const std::vector<const World*>& parts, const std::vector<const std::vector<char>*>& owned,
                 std::vector<uint64_t>& ids, std::vector<double>& state) {
  std::vector<std::pair<uint64_t, std::pair<std::size_t, uint32_t>>> all;
  for (std::size_t r = 0; r < parts.size(); ++r) {
    const Particles& p = parts[r]->particles();
    for (std::size_t i = 0; i < p.size(); ++i)
      if (!owned[r] || (*owned[r])[i]) all.push_back({p.id[i], {r, static_cast<uint32_t>(i)}});
  }
  std::sort(all.begin(), all.end());
  ids.clear();
  state.clear();
  std::vector<double> one;
  for (const auto& [id, at] : all) {
    ids.push_back(id);
    pack_ghosts(parts[at.first]->particles(), {at.second}, one);
    state.insert(state.end(), one.begin(), one.end());
  }
}

void LocalDomains::owned_state(std::vector<uint64_t>& ids, std::vector<double>& state) const {
  std::vector<const World*> parts;
  std::vector<const std::vector<char>*> owned;
  for (const Domain& d : domains_) parts.push_back(d.world.get()), owned.push_back(&d.plan.owned);
  dem::owned_state(parts, owned, ids, state);
}

std::vector<BondBreak> LocalDomains::breaks() const {
  std::vector<BondBreak> out;
  for (const Domain& d : domains_) {
    const auto b = owned_breaks(*d.world, d.plan);
    out.insert(out.end(), b.begin(), b.end());
  }
  return out;
}

}  // namespace dem
