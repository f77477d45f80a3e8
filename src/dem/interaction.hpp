#pragma once
// Extra force contributions (meshes, fixes), LAMMPS "fix"-style: World calls add_forces every step after
// the particle-particle, wall and bond forces and before the second velocity half-step.
// Implementations add into p.fx/fy/fz and p.tx/ty/tz; they must be deterministic for a given thread
// count (no atomics on doubles in varying order).
// Checkpoints: World::save_state/load_state call save_state/load_state of every Interaction in the order they
// were added; an Interaction that keeps anything from one step to the next (contact histories, a lazily built
// search structure whose layout depends on the particles present then) writes it there.
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/binary_io.hpp"
#include "dem/particles.hpp"

namespace dem {

struct Interaction {
  // t: time at the end of the current step's drift (positions are at t), dt: the step
  virtual void add_forces(Particles& p, double t, double dt) = 0;
  // Called after particles were removed/reordered: old index -> new index (-1 removed). Default: nothing.
  virtual void on_reindex(const std::vector<long>& old_to_new) { (void)old_to_new; }
  // Called when particle i's radius changed (World::set_radius). Default: nothing.
  virtual void on_radius_change(long i) { (void)i; }
  // Largest contact overlap / particle radius of the last add_forces and that particle's index (-1: no
  // contact), for World's blow-up check; and what to call this interaction in its message.
  virtual std::pair<double, long> worst_overlap() const { return {0.0, -1}; }
  virtual std::string label() const { return "an extra interaction"; }
  // Checkpoint of the state this interaction carries from one step to the next (default: stateless, writes and
  // reads nothing). load_state reads exactly what save_state wrote (open it with a BinaryWriter tag so that a
  // mismatched file fails there) and throws std::runtime_error (BinaryReader::fail) on a mismatch.
  virtual void save_state(core::BinaryWriter& w) const {}
  virtual void load_state(core::BinaryReader& r) {}
  // Domain decomposition (ghost_domains.hpp): ghost[i] != 0 marks particle i as a ghost, a copy of a particle another
  // rank owns, whose forces are not used; an interaction may skip it and must leave it out of its totals. Default:
  // ignored (a stateless interaction without totals computes ghosts like the others).
  virtual void set_ghosts(const Particles& p, const std::vector<char>& ghost) {
    (void)p;
    (void)ghost;
  }
  // World::assemble: this interaction's state put together from the same interaction of each part (whose ghosts it
  // skipped). Default: refused, for an interaction that carries state and does not implement it.
  virtual void assemble_state(const std::vector<const Interaction*>& parts) {
    (void)parts;
    throw std::invalid_argument(label() + ": its state cannot be put together from a domain decomposition's parts");
  }
  virtual ~Interaction() = default;
};

}  // namespace dem
