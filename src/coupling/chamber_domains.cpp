// ChamberDem on a decomposed charge (issue 25, dem/domain_engine.hpp): which World the chamber works on, the liners of
// the engine's new Worlds, and what goes between the processes (crushed ids and their liner planes, growing fragments).
#include <algorithm>
#include <sstream>
#include <stdexcept>

#include "coupling/chamber_dem.hpp"

namespace coupling {

void ChamberDem::focus(dem::World& w) {
  const auto& ia = w.interactions();
  if (ia.size() < 4) throw std::logic_error("ChamberDem: a World without the chamber's four liners");
  world_ = &w;
  mantle_ = static_cast<dem::MeshContact*>(ia[0].get());
  concave_ = static_cast<dem::MeshContact*>(ia[1].get());
  cap_ = static_cast<dem::MeshContact*>(ia[2].get());
  hopper_ = static_cast<dem::MeshContact*>(ia[3].get());
}

// The same liners (meshes, regions, threads) as whole_'s, in the same order; their state comes with the checkpoint.
void ChamberDem::add_liners(dem::World& w) const {
  const auto& ia = whole_->interactions();
  for (int k = 0; k < 4; ++k) {
    const auto& from = static_cast<const dem::MeshContact&>(*ia[k]);
    auto mc = std::make_shared<dem::MeshContact>(from.mesh(), wp_.materials, from.wall_material());
    if (from.regions()) mc->set_regions(*from.regions());
    mc->set_threads(w.threads());
    w.add_interaction(mc);
  }
}

double ChamberDem::largest_sphere_radius() const {
  double r = 0;
  for (const auto& rk : rocks_)
    for (double x : rk.radii) r = std::max(r, x);
  return r;
}

void ChamberDem::decompose(dem::EngineFactory make) {
  if (decomposed_) throw std::logic_error("ChamberDem::decompose: already decomposed");
  if (!make) throw std::invalid_argument("ChamberDem::decompose: no engine factory");
  make_engine_ = std::move(make);
  if (prefilled_ || !p_.feed.prefill) start_engine();
}

void ChamberDem::start_engine() {
  focus(*whole_);
  std::ostringstream os;
  core::BinaryWriter w(os);
  whole_->save_state(w);
  engine_ = make_engine_(os.str(), wp_, [this](dem::World& x) { add_liners(x); });
  if (engine_->root()) take_snapshot();  // the outputs' charge until the first bookkeeping (only the root's are read)
  decomposed_ = true;
  focus(engine_->part(0));
  share_root_state();
}

void ChamberDem::follow_load() {
  if (!make_engine_) throw std::logic_error("ChamberDem::follow_load: not decomposed (decompose first)");
  start_engine();  // the root's charge, loaded there, comes with the engine; the rest with share_root_state
}

// A failure in one rank's step (a blow-up) is every rank's: they agree on it before the next exchange, so that all
// leave advance() with the same message and none waits for a peer that stopped.
void ChamberDem::step_parts() {
  if (!decomposed_) {
    engine_->step();
    return;
  }
  std::string err;
  try {
    engine_->step();
  } catch (const std::exception& e) {
    err = e.what();
  }
  if (engine_->max(err.empty() ? 0.0 : 1.0) == 0) return;
  const std::string all = engine_->broadcast(engine_->gather(err.empty() ? std::string() : err + "\n"));
  throw std::runtime_error(all.substr(0, all.size() - 1));
}

void ChamberDem::edit_whole(const std::function<void()>& fn) {
  engine_->edit([&](dem::World& w) {
    focus(w);
    fn();
  });
  focus(engine_->part(0));
  if (decomposed_) share_root_state();
}

void ChamberDem::harvest_breaks() {
  const auto& br = world_->breaks();
  broken_total_ += static_cast<long>(br.size());
  breaks_.insert(breaks_.end(), br.begin(), br.end());
  world_->clear_breaks();
}

void ChamberDem::prune_growing() {
  std::size_t keep = 0;
  for (const Growing& g : growing_) {
    const long i = world_->index_of(g.id);
    if (i >= 0 && world_->particles().r[i] < g.r_end) growing_[keep++] = g;
  }
  growing_.resize(keep);
}

// What every process needs of the root's bookkeeping to take the same steps and edits: the growing fragments, when
// the next bookkeeping falls, whether the prefill is done.
void ChamberDem::share_root_state() {
  std::string mine;
  if (engine_->root()) {
    std::ostringstream os;
    core::BinaryWriter w(os);
    put_growing(w);
    w.put(next_bookkeeping_);
    w.put<char>(prefilled_);
    mine = os.str();
  }
  const std::string all = engine_->broadcast(mine);
  if (engine_->root()) return;
  std::istringstream is(all);
  core::BinaryReader r(is, "the root's bookkeeping");
  get_growing(r);
  r.get(next_bookkeeping_);
  prefilled_ = r.get<char>() != 0;
}

void ChamberDem::take_snapshot() {
  snapshot_ = world_->particles();
  snapshot_labels_ = labels_of(*world_);
}

// Every process's crushed ids and liner planes to the root: ids sorted without repeats, planes in rank order (each
// sphere's all from the process that owns it).
void ChamberDem::gather_crushed(const std::vector<uint64_t>& mine, LinerPlanes& planes, std::vector<uint64_t>& ids) {
  if (!decomposed_) {
    ids = mine;
    return;
  }
  std::ostringstream os;
  core::BinaryWriter w(os);
  std::vector<uint64_t> pid;
  std::vector<double> pxn;
  for (const auto& [id, pn] : planes) {
    pid.push_back(id);
    pxn.insert(pxn.end(), pn.first.data(), pn.first.data() + 3);
    pxn.insert(pxn.end(), pn.second.data(), pn.second.data() + 3);
  }
  w.put_vec(mine);
  w.put_vec(pid);
  w.put_vec(pxn);
  const std::string all = engine_->gather(os.str());
  ids.clear();
  planes.clear();
  if (!engine_->root()) return;
  std::istringstream is(all);
  core::BinaryReader r(is, "crushed spheres from the ranks");
  while (is.peek() != std::char_traits<char>::eof()) {
    std::vector<uint64_t> some;
    r.get_vec(some);
    r.get_vec(pid);
    r.get_vec(pxn);
    if (pxn.size() != 6 * pid.size()) r.fail("liner planes do not match their ids");
    ids.insert(ids.end(), some.begin(), some.end());
    for (std::size_t k = 0; k < pid.size(); ++k)
      planes.push_back({pid[k], {Eigen::Vector3d::Map(&pxn[6 * k]), Eigen::Vector3d::Map(&pxn[6 * k + 3])}});
  }
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
}

void ChamberDem::owned_state(std::vector<uint64_t>& ids, std::vector<double>& state) const {
  std::vector<const dem::World*> parts;
  std::vector<const std::vector<char>*> owned;
  for (int j = 0; j < engine_->parts(); ++j) parts.push_back(&engine_->part(j)), owned.push_back(engine_->owned(j));
  dem::owned_state(parts, owned, ids, state);
}

}  // namespace coupling
