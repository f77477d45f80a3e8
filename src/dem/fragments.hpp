#pragma once
// Fragments: connected components of particles over intact bonds (DESIGN.md: "Fragments are
// connected components over intact bonds"), kept up to date from break events. A break re-examines
// only the component that held the bond (breadth-first search from one end; if the other end is no
// longer reached, the reached part becomes a new fragment). Particles are named by their stable id
// (Particles::id), so compaction of the particle arrays does not disturb the fragments.
//
// Square-mesh sieve size of a fragment (the smallest square aperture it passes): principal axes of
// the fragment's mass distribution (sphere centres plus each sphere's own r^2/5 spread), extents
// L >= I >= S of the union of its spheres along those axes, and
//   sieve = min(I, (I + S) / sqrt(2))
// i.e. the I x S cross-section passes a square hole of side a either aligned (I <= a) or turned by
// 45 degrees ((I + S)/sqrt(2) <= a), whichever is smaller. A sphere of diameter d gives d; a straight
// rod of spheres of diameter d gives d; a plate s x s x t (t < 0.41 s) gives (s + t)/sqrt(2).
#include <Eigen/Core>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "dem/bonds.hpp"
#include "dem/particles.hpp"

namespace dem {

struct FragmentInfo {
  int label;                // fragment label (stable until the fragment splits or is removed)
  int count;                // particles
  double mass;              // kg
  Eigen::Vector3d centre;   // centre of mass, m
  double sieve_size;        // m, see above
};

// Sieve size of a union of spheres (centres in m, radii in m, masses in kg as weights).
double square_sieve_size(const std::vector<Eigen::Vector3d>& centres, const std::vector<double>& radii,
                         const std::vector<double>& masses);

class Fragments {
 public:
  Fragments() = default;
  // particle_ids: every particle tracked (duplicates rejected); bonds: pairs of ids (intact bonds).
  // Throws std::invalid_argument on unknown ids, self bonds or duplicate ids.
  Fragments(const std::vector<uint64_t>& particle_ids,
            const std::vector<std::pair<uint64_t, uint64_t>>& bonds);
  // Convenience: every particle of `p`, bonds given as index pairs into `p`.
  static Fragments from_particles(const Particles& p, const std::vector<std::pair<int, int>>& bonds);
  // Convenience: every particle of `p` and the intact bonds (alive != 0) of World::bonds().
  static Fragments from_bonds(const Particles& p, const std::vector<Bond>& bonds);

  // Break event: removes the bond (a, b). Returns true when it split a fragment in two.
  // Throws std::invalid_argument if no such intact bond exists.
  bool break_bond(uint64_t a, uint64_t b);
  // Applies World's break log (BondBreak::id_i, id_j); returns the number of splits. Breaks of bonds
  // this tracker does not hold (already applied) are an error (std::invalid_argument).
  int apply_breaks(const std::vector<BondBreak>& breaks);
  // Adds a new particle as its own fragment (e.g. fed later). Throws on a duplicate id.
  void add_particle(uint64_t id);
  // Removes a particle (e.g. discharged) and its bonds; its fragment may split.
  void remove_particle(uint64_t id);

  bool contains(uint64_t id) const { return node_.count(id) != 0; }
  int fragment_of(uint64_t id) const;       // label
  int num_fragments() const { return live_; }
  std::vector<int> labels() const;          // live fragment labels, ascending
  std::vector<uint64_t> members(int label) const;  // particle ids, ascending
  bool bonded(uint64_t a, uint64_t b) const;
  size_t num_bonds() const { return bonds_; }

  // Mass, count, centre and sieve size of every fragment, from the current particle state.
  // Every tracked particle must be in `p` (std::invalid_argument otherwise). Ascending label order.
  std::vector<FragmentInfo> info(const Particles& p) const;

 private:
  int node_of(uint64_t id) const;
  void relabel_split(int start, int avoid_node, bool* split);
  int new_label();

  std::unordered_map<uint64_t, int> node_;
  std::vector<uint64_t> id_;               // node -> id (0 for a freed node)
  std::vector<char> alive_;
  std::vector<std::vector<int>> adj_;      // intact bonds per node
  std::vector<int> comp_;                  // node -> label
  std::vector<std::vector<int>> members_;  // label -> nodes (empty for a dead label)
  std::vector<int> free_labels_;
  int live_ = 0;
  size_t bonds_ = 0;
};

}  // namespace dem
