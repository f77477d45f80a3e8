// dem::World checkpoints (world.hpp: save_state / load_state). The file holds what one step carries to the
// next; everything derived (bond CSR, neighbour list beyond the touching pairs, cell grid, slabs, reference
// positions of the displacement check) is rebuilt by the forced neighbour-list rebuild of the next step, which
// the writing run takes too.
#include <algorithm>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "dem/world.hpp"

namespace dem {

namespace {

constexpr uint32_t kVersion = 1;

// Any bit set (a history of -0.0 is kept too: the continuation is bit for bit).
bool any_bits(const std::array<double, 3>& h) {
  static const std::array<double, 3> zero{{0.0, 0.0, 0.0}};
  return std::memcmp(h.data(), zero.data(), sizeof zero) != 0;
}


// An array of exactly n entries; the error names it.
template <class V>
void get_sized(core::BinaryReader& r, V& v, uint64_t n, const std::string& what) {
  try {
    r.get_vec(v, n);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string(e.what()) + " (reading " + what + ", expected " + std::to_string(n) +
                             " entries)");
  }
  if (v.size() != n)
    r.fail(what + " holds " + std::to_string(v.size()) + " entries, expected " + std::to_string(n));
}

// A count read from the file, refused above `max` before anything is allocated for it.
uint64_t get_count(core::BinaryReader& r, uint64_t max, const std::string& what) {
  const uint64_t n = r.get<uint64_t>();
  if (n > max) r.fail("implausible " + what + " count " + std::to_string(n));
  return n;
}

}  // namespace

void World::save_state(core::BinaryWriter& w) {
  // per-particle arrays laid out for the current particles and walls (what prepare() does at the next step)
  resize_per_particle();
  const std::size_t n = p_.size(), nw = walls_.size();

  w.tag("WRLD");
  w.put<uint32_t>(kVersion);
  w.put<uint64_t>(n);
  w.put<uint64_t>(nw);
  w.put<uint64_t>(interactions_.size());
  w.put<int32_t>(prm_.materials.n());
  w.put<double>(t_);
  w.put<int64_t>(nstep_);
  w.put<int64_t>(nrebuild_);
  w.put<double>(skin_);
  w.put<double>(prm_.dt);
  w.put<uint8_t>(dt_checked_ ? 1 : 0);

  w.tag("PART");
  w.put<uint64_t>(p_.next_id);
  for (const SVec<double>* a : static_cast<const Particles&>(p_).doubles()) w.put_vec(*a);
  w.put_vec(p_.id);
  w.put_vec(p_.material);
  w.put_vec(p_.fixed);

  w.tag("WALL");
  for (const PlanarWall& wl : walls_) {
    w.put_xyz(wl.p);
    w.put_xyz(wl.n);
    w.put_xyz(wl.v);
    w.put<int32_t>(wl.material);
    w.put_xyz(wl.force);
  }
  w.put_vec(wtouch_);
  uint64_t nwh = 0;
  for (const auto& h : whist_) nwh += any_bits(h) ? 1 : 0;
  w.put<uint64_t>(nwh);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = 0; k < nw; ++k) {
      const auto& h = whist_[i * nw + k];
      if (!any_bits(h)) continue;
      w.put<uint32_t>(static_cast<uint32_t>(i));
      w.put<uint32_t>(static_cast<uint32_t>(k));
      w.put_xyz(h.data());
    }

  w.tag("BOND");
  sync_bonds();
  w.put<uint64_t>(bonds_.size());
  for (const Bond& b : bonds_) {  // broken ones not compacted yet too: the loaded World compacts them
    w.put<uint32_t>(b.i);
    w.put<uint32_t>(b.j);
    for (double v : {b.rb, b.A, b.J, b.kn, b.kt, b.sigma_c, b.tau_c, b.damping, b.fn}) w.put<double>(v);
    w.put_xyz(b.ft);
    w.put<double>(b.tn);
    w.put_xyz(b.tt);
    w.put<uint8_t>(b.alive ? 1 : 0);
  }
  w.put<uint64_t>(breaks_.size());
  for (const BondBreak& e : breaks_) {
    w.put<double>(e.t);
    w.put_xyz(e.x);
    w.put<uint64_t>(e.id_i);
    w.put<uint64_t>(e.id_j);
    w.put<uint8_t>(e.tensile ? 1 : 0);
    w.put<double>(e.sigma);
    w.put<double>(e.tau);
  }

  // Neighbour pairs with a history or touching at the last step, in list order (by owner, then j). The
  // others have a zero history and no touch flag, exactly what the rebuild gives a new pair.
  w.tag("PAIR");
  uint64_t nkeep = 0;
  for (std::size_t q = 0; q < npairs_; ++q) nkeep += (touch_[q] || any_bits(hist_[q])) ? 1 : 0;
  w.put<uint64_t>(nkeep);
  for (std::size_t q = 0; q < npairs_; ++q) {
    if (!(touch_[q] || any_bits(hist_[q]))) continue;
    w.put<uint32_t>(pi_[q]);
    w.put<uint32_t>(pj_[q]);
    w.put_xyz(hist_[q].data());
    w.put<uint8_t>(touch_[q]);
  }

  for (const auto& ia : interactions_) {
    w.tag("INTR");
    w.put_string(ia->label());
    ia->save_state(w);
  }
  w.tag("WEND");
  // The loaded World starts with a rebuild; so does this one, so both build the same list and slabs from the
  // same positions (the order of the force sums follows them).
  need_rebuild_ = true;
}

void World::load_state(core::BinaryReader& r) {
  r.expect("WRLD");
  const uint32_t version = r.get<uint32_t>();
  if (version != kVersion)
    r.fail("World state version " + std::to_string(version) + ", this build reads version " +
           std::to_string(kVersion));
  const uint64_t n = get_count(r, 0xFFFFFFF0ull, "particle");
  const uint64_t nw = r.get<uint64_t>(), nia = r.get<uint64_t>();
  const int32_t nmat = r.get<int32_t>();
  if (nw != walls_.size())
    r.fail("written for a World with " + std::to_string(nw) + " planar walls, this World has " +
           std::to_string(walls_.size()) + " (add the same walls before load_state)");
  if (nia != interactions_.size())
    r.fail("written for a World with " + std::to_string(nia) + " interactions, this World has " +
           std::to_string(interactions_.size()) + " (add the same interactions in the same order before load_state)");
  if (nmat != prm_.materials.n())
    r.fail("written for a material table of " + std::to_string(nmat) + " materials, this World has " +
           std::to_string(prm_.materials.n()));
  const double t = r.get<double>();
  const int64_t nstep = r.get<int64_t>(), nrebuild = r.get<int64_t>();
  const double skin = r.get<double>(), dt = r.get<double>();
  const bool dt_checked = r.get<uint8_t>() != 0;
  if (!(dt > 0)) r.fail("time step " + std::to_string(dt) + " s is not > 0");

  r.expect("PART");
  Particles np;
  np.next_id = r.get<uint64_t>();
  {
    const auto arrays = np.doubles();
    const auto names = Particles::double_names();
    for (std::size_t a = 0; a < arrays.size(); ++a) get_sized(r, *arrays[a], n, "particle array " + names[a]);
  }
  get_sized(r, np.id, n, "particle ids");
  get_sized(r, np.material, n, "particle materials");
  get_sized(r, np.fixed, n, "particle fixed flags");
  for (std::size_t i = 0; i < n; ++i) {
    if ((i > 0 && np.id[i] <= np.id[i - 1]) || np.id[i] >= np.next_id)
      r.fail("particle ids are not increasing below next_id (index " + std::to_string(i) + ")");
    if (np.material[i] < 0 || np.material[i] >= nmat)
      r.fail("particle " + std::to_string(i) + " has material " + std::to_string(np.material[i]));
  }

  r.expect("WALL");
  std::vector<PlanarWall> walls(nw);
  for (PlanarWall& wl : walls) {
    r.get_doubles(wl.p, 3);
    r.get_doubles(wl.n, 3);
    r.get_doubles(wl.v, 3);
    wl.material = r.get<int32_t>();
    r.get_doubles(wl.force, 3);
    if (wl.material < 0 || wl.material >= nmat) r.fail("wall material " + std::to_string(wl.material));
  }
  SVec<char> wtouch;
  get_sized(r, wtouch, n, "wall-touch flags");
  SVec<std::array<double, 3>> whist(n * nw, std::array<double, 3>{{0, 0, 0}});
  const uint64_t nwh = get_count(r, n * nw, "wall history");
  for (uint64_t e = 0; e < nwh; ++e) {
    const uint32_t i = r.get<uint32_t>(), k = r.get<uint32_t>();
    if (i >= n || k >= nw)
      r.fail("wall history entry for particle " + std::to_string(i) + ", wall " + std::to_string(k) + " out of range");
    r.get_doubles(whist[i * nw + k].data(), 3);
  }

  r.expect("BOND");
  std::vector<Bond> bonds(get_count(r, 0xFFFFFFFFull, "bond"));
  for (Bond& b : bonds) {
    b.i = r.get<uint32_t>();
    b.j = r.get<uint32_t>();
    for (double* v : {&b.rb, &b.A, &b.J, &b.kn, &b.kt, &b.sigma_c, &b.tau_c, &b.damping, &b.fn}) *v = r.get<double>();
    r.get_doubles(b.ft, 3);
    b.tn = r.get<double>();
    r.get_doubles(b.tt, 3);
    b.alive = r.get<uint8_t>() ? 1 : 0;
    if (b.i >= n || b.j >= n || b.i == b.j)
      r.fail("bond between particles " + std::to_string(b.i) + " and " + std::to_string(b.j) + " of " +
             std::to_string(n));
  }
  std::vector<BondBreak> breaks(get_count(r, uint64_t(1) << 34, "bond break"));
  for (BondBreak& e : breaks) {
    e.t = r.get<double>();
    r.get_doubles(e.x, 3);
    e.id_i = r.get<uint64_t>();
    e.id_j = r.get<uint64_t>();
    e.tensile = r.get<uint8_t>() != 0;
    e.sigma = r.get<double>();
    e.tau = r.get<double>();
  }

  r.expect("PAIR");
  const uint64_t npairs = get_count(r, 0xFFFFFFFFull, "neighbour pair");
  SVec<uint32_t> pi(npairs), pj(npairs), istart(n + 1, 0);
  SVec<std::array<double, 3>> hist(npairs);
  SVec<uint8_t> touch(npairs);
  for (uint64_t q = 0; q < npairs; ++q) {
    pi[q] = r.get<uint32_t>();
    pj[q] = r.get<uint32_t>();
    r.get_doubles(hist[q].data(), 3);
    touch[q] = r.get<uint8_t>();
    if (!(pi[q] < pj[q] && pj[q] < n) || (q > 0 && (pi[q] < pi[q - 1] || (pi[q] == pi[q - 1] && pj[q] <= pj[q - 1]))))
      r.fail("neighbour pair (" + std::to_string(pi[q]) + ", " + std::to_string(pj[q]) + ") out of range or order");
    ++istart[pi[q] + 1];
  }
  for (std::size_t i = 0; i < n; ++i) istart[i + 1] += istart[i];

  // interactions in the order added; each block opened by the label it was saved under
  for (std::size_t k = 0; k < interactions_.size(); ++k) {
    r.expect("INTR");
    const std::string label = r.get_string();
    if (label != interactions_[k]->label())
      r.fail("interaction " + std::to_string(k) + " was " + label + " when saved, here it is " +
             interactions_[k]->label());
    interactions_[k]->load_state(r);
  }
  r.expect("WEND");

  // commit
  p_ = std::move(np);
  walls_ = std::move(walls);
  wtouch_.swap(wtouch);
  whist_.swap(whist);
  bonds_ = std::move(bonds);
  bhot_ahead_ = false;  // bhot_ is rebuilt from bonds_ before the next step (bonds_dirty_)
  breaks_ = std::move(breaks);
  npairs_ = npairs;
  pi_.swap(pi);
  pj_.swap(pj);
  hist_.swap(hist);
  touch_.swap(touch);
  istart_.swap(istart);
  x0_.assign(p_.x.begin(), p_.x.end());
  y0_.assign(p_.y.begin(), p_.y.end());
  z0_.assign(p_.z.begin(), p_.z.end());
  n_known_ = n;
  t_ = t;
  nstep_ = nstep;
  nrebuild_ = nrebuild;
  skin_ = skin;
  prm_.dt = dt;
  dt_checked_ = dt_checked;
  ghost_.clear();        // a decomposition marks its ghosts again (ghost_domains.hpp)
  bonds_dirty_ = true;   // bond CSR (and compaction of the broken bonds it holds) at the next step
  need_rebuild_ = true;  // neighbour list from the saved pairs, as the writing run does after save_state
}

}  // namespace dem
