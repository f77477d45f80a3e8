#pragma once
// Extra force contributions (meshes, fixes), LAMMPS "fix"-style: World calls add_forces every step after
// the particle-particle, wall and bond forces and before the second velocity half-step.
// Implementations add into p.fx/fy/fz and p.tx/ty/tz; they must be deterministic for a given thread
// count (no atomics on doubles in varying order).
#include <string>
#include <utility>
#include <vector>

#include "dem/particles.hpp"

namespace dem {

struct Interaction {
  // t: time at the end of the current step's drift (positions are at t), dt: the step
  virtual void add_forces(Particles& p, double t, double dt) = 0;
  // Called after particles were removed/reordered: old index -> new index (-1 removed). Default: nothing.
  virtual void on_reindex(const std::vector<long>& old_to_new) { (void)old_to_new; }
  // Largest contact overlap / particle radius of the last add_forces and that particle's index (-1: no
  // contact), for World's blow-up check; and what to call this interaction in its message.
  virtual std::pair<double, long> worst_overlap() const { return {0.0, -1}; }
  virtual std::string label() const { return "an extra interaction"; }
  virtual ~Interaction() = default;
};

}  // namespace dem
