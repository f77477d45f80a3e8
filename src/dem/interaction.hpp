#pragma once
// Extra force contributions (meshes, fixes), LAMMPS "fix"-style: World calls add_forces every step after
// the particle-particle, wall and bond forces and before the second velocity half-step.
// Implementations add into p.fx/fy/fz and p.tx/ty/tz; they must be deterministic for a given thread
// count (no atomics on doubles in varying order).
#include "dem/particles.hpp"

namespace dem {

struct Interaction {
  // t: time at the end of the current step's drift (positions are at t), dt: the step
  virtual void add_forces(Particles& p, double t, double dt) = 0;
  // Called after particles were removed/reordered: old index -> new index (-1 removed). Default: nothing.
  virtual void on_reindex(const std::vector<long>& old_to_new) { (void)old_to_new; }
  virtual ~Interaction() = default;
};

}  // namespace dem
