#pragma once
// dem::World: the DEM engine. Spheres (Particles), Hertz-Mindlin contacts with history and rolling friction
// (hertz_mindlin.hpp), bonds (bond_law.hpp), moving planar walls (walls.hpp) and extra force terms
// (Interaction, e.g. triangle meshes). Velocity-Verlet integration, cell-list Verlet neighbour list,
// OpenMP with results identical run to run and across thread counts: pair forces are added straight into
// the particles' force arrays, slab by slab in a fixed three-colour order (slabs of the same colour touch
// disjoint particles); bond forces too, each particle's in bond order (bond_forces).
//
// Step order: half kick (v += dt/2 F/m, w += dt/2 T/I) -> drift (x += dt v, walls move) -> neighbour list
// rebuild if any particle moved more than skin/2 -> pair forces (added to gravity) -> bond forces (breaks
// logged) -> bond gather and wall forces -> Interaction::add_forces -> half kick. Blow-up checks (BlowUp) on
// overlaps and non-finite states happen inside these loops. Forces of a new particle are zero until
// its first step. Particles with fixed[i] = 1 keep their velocities (prescribed motion).
//
// Checkpoint/restart: save_state / load_state (world_checkpoint.cpp) write and read the complete evolving state
// through core::BinaryWriter/BinaryReader; a World loaded from a checkpoint continues bit for bit like the run
// that wrote it.
#include <array>
#include <cstddef>
#include <cstdint>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/binary_io.hpp"
#include "dem/bonds.hpp"
#include "dem/cell_grid.hpp"
#include "dem/interaction.hpp"
#include "dem/materials.hpp"
#include "dem/particles.hpp"
#include "dem/time_step.hpp"
#include "dem/walls.hpp"

namespace dem {

struct WorldParams {
  double dt = 1e-6;                             // s
  std::array<double, 3> gravity{{0, 0, -9.81}};  // m/s^2
  double skin = -1;                 // Verlet skin (m); < 0: 0.1 x the largest diameter at the first build
  int threads = 0;                  // OpenMP threads; 0: omp_get_max_threads()
  double max_rayleigh_fraction = 0.5;  // step() refuses dt above this fraction of the Rayleigh step
  bool check_time_step = true;      // step() checks dt (Rayleigh and bonds) whenever particles/bonds changed
  MaterialTable materials = default_table4();
  // Blow-up detection: step() throws BlowUp when a position or velocity is non-finite or a contact overlap
  // (particle-particle or planar wall) exceeds this fraction of the smaller radius (<= 0: no overlap check).
  double max_overlap_fraction = 0.5;
  // The same for mesh contacts (Interaction::worst_overlap). 1: the centre has reached the surface. Looser than
  // between particles: rigid liners driven from outside squeeze coarse spheres larger than the gap (the quick
  // demo's 15 mm spheres reach 0.5 r at a ~10 mm setting) without the integration failing.
  double max_mesh_overlap_fraction = 1.0;
  // CSV state dump written before BlowUp is thrown: a file in the run's own folder, set by the caller. Empty: a new
  // file of an unguessable name, <temp dir>/dem_blowup_XXXXXX.csv (mkstemps), never a fixed name there.
  std::string blowup_dump_path;
};

// Numerical blow-up: what() names the step, the particle and the dump file.
struct BlowUp : std::runtime_error {
  BlowUp(const std::string& msg, long step, uint64_t id, double overlap, std::string dump)
      : std::runtime_error(msg), step(step), id(id), overlap(overlap), dump_path(std::move(dump)) {}
  long step;              // step count at which it was detected (World::step_count() + 1)
  uint64_t id;            // particle id
  double overlap;         // overlap / smaller radius (NaN for a non-finite state)
  std::string dump_path;  // CSV: id, x, y, z, vx, vy, vz, wx, wy, wz, fx, fy, fz, r, m, material, fixed
};

class World {
 public:
  explicit World(const WorldParams& params);

  // ---- particles (ids are stable; indices change on removal)
  // Solid sphere with the material's density. v, w may be null (zero).
  std::size_t add_particle(const double x[3], double radius, int material, const double v[3] = nullptr,
                           const double w[3] = nullptr);
  std::size_t add_particle(const double x[3], double radius, int material, double density, const double v[3],
                           const double w[3]);
  // Removes particles with remove[i] != 0 and their bonds (not logged as breaks); keeps the others' order.
  void remove_particles(const std::vector<char>& remove);
  void remove_particles_by_id(const std::vector<uint64_t>& ids);
  long index_of(uint64_t id) const;  // -1 if absent
  Particles& particles() { return p_; }  // may move/modify state; call invalidate_neighbors() after teleporting
  const Particles& particles() const { return p_; }
  void invalidate_neighbors() { need_rebuild_ = true; }
  // Sets particle i's radius keeping its mass (1/I follows; a fragment growing into the volume of its parent). The
  // neighbour list counts the change like a displacement and the interactions re-check i, so contacts the new
  // radius makes are found. Bonds of i keep the geometry they formed with. Throws std::invalid_argument on a
  // radius <= 0 or one whose Rayleigh step (with i's mass) is below dt / max_rayleigh_fraction.
  void set_radius(std::size_t i, double radius);

  // ---- walls
  int add_plane(const double point[3], const double normal[3], int material);
  // Six inward-facing planes of the box [lo, hi] (x-, x+, y-, y+, z-, z+); with_top = false leaves out z+.
  // Returns the index of the first plane.
  int add_box(const double lo[3], const double hi[3], int material, bool with_top = true);
  void set_wall_velocity(int k, const double v[3]);
  void set_wall_position(int k, const double point[3]);
  const PlanarWall& wall(int k) const { return walls_.at(k); }
  std::size_t n_walls() const { return walls_.size(); }

  // ---- bonds (Eq. 20-25). Formation sets the spring state to zero at the current geometry.
  // Bonds every unbonded pair with both indices in [first, last) whose gap d - r_i - r_j < gap_tolerance.
  std::size_t bond_within(double gap_tolerance, const BondParams& bp, std::size_t first = 0,
                          std::size_t last = static_cast<std::size_t>(-1));
  std::size_t bond_pairs(const std::vector<std::pair<std::size_t, std::size_t>>& pairs, const BondParams& bp);
  // May hold broken ones (alive == 0). The spring states live in the engine's own compact copy while it steps
  // (World::BondHot): this call copies them into the list it returns (O(bonds) once per step() call).
  const std::vector<Bond>& bonds() const {
    sync_bonds();
    return bonds_;
  }
  std::size_t n_bonds_intact() const;
  const std::vector<BondBreak>& breaks() const { return breaks_; }
  void clear_breaks() { breaks_.clear(); }

  // ---- extra forces (meshes); called every step after pair, bond and wall forces
  void add_interaction(std::shared_ptr<Interaction> ia) { interactions_.push_back(std::move(ia)); }
  const std::vector<std::shared_ptr<Interaction>>& interactions() const { return interactions_; }  // in the order added

  // ---- time stepping
  TimeStepCheck time_step_check() const;
  void require_stable_time_step() const;  // throws std::invalid_argument with both critical steps
  void set_dt(double dt);
  double dt() const { return prm_.dt; }
  void step(long n = 1);
  // One step in two halves, for a caller that changes particles in between (ghost exchange of a domain
  // decomposition, ghost_domains.hpp): step_begin() does the opening half kick and drift (walls move),
  // step_end() re-measures every particle's displacement, then forces, the closing half kick and the step count.
  // step_begin(); step_end(); equals step(1) bit for bit. Throws std::logic_error when unpaired.
  void step_begin();
  void step_end();
  double time() const { return t_; }
  long step_count() const { return nstep_; }

  // ---- observables
  double kinetic_energy() const;  // translational + rotational (J)
  std::size_t n_contacts() const;  // touching particle pairs at the current positions
  std::size_t n_wall_contacts() const;  // (particle, planar wall) pairs touching at the current positions
  // Per particle, the sum over its particle contacts and intact bonds of sym(a (x) f) (a: centre to contact point,
  // taken at the sphere's radius, so that a diametral load F gives -2 r F n n; f: force on the particle), 6 entries
  // xx yy zz xy yz zx per particle (N m); / volume it is the particle's mean stress (Love-Weber). Contacts at the
  // last step's positions with their elastic force (Eq. 16-19 without damping: the spring state as it stands),
  // bonds with their spring forces. Walls and interactions are not in it (contact_stress.cpp).
  void contact_stress(std::vector<double>& s) const;
  std::size_t n_pairs() const { return npairs_; }  // neighbour-list pairs
  long n_rebuilds() const { return nrebuild_; }
  const MaterialTable& materials() const { return prm_.materials; }
  int threads() const { return nt_; }
  double skin() const { return skin_; }
  // Memory of the engine's arrays (capacity) per particle and per intact bond, for the benchmark.
  double bytes_per_particle() const;
  double bytes_per_bond() const;
  // Wall-clock seconds spent per phase since construction: 0 kick+drift, 1 neighbour rebuild, 2 pair forces,
  // 3 bond forces, 4 gather+walls, 5 interactions, 6 final kick.
  const std::array<double, 7>& phase_seconds() const { return phase_s_; }
  // Writes the particle state as CSV (the blow-up dump); throws std::runtime_error if the file cannot be written.
  void write_state_csv(const std::string& path) const;

  // ---- checkpoint/restart (world_checkpoint.cpp)
  // Writes the complete evolving state, between two step() calls: particles (x, v, w, r, m, 1/m, 1/I, material,
  // fixed, and f, t of the last step: the next step's first half kick uses them), ids and next_id; bonds with
  // their spring state (broken ones of the last step included); the touching neighbour pairs with their
  // tangential histories and touch flags (the forced rebuild below carries them into the new list by pair
  // identity); per planar wall its point, normal, velocity, material and last force, per particle the wall
  // histories (non-zero ones) and wall-touch flag; time, step count, rebuild count, skin, dt and whether dt was
  // checked; the break log; then each Interaction's state (Interaction::save_state) in the order added, each
  // preceded by its label(). Blocks are tagged "WRLD", "PART", "WALL", "BOND", "PAIR", "INTR" (one per
  // interaction), "WEND".
  // Non-const: it also schedules a neighbour-list rebuild for the next step (the list's pair and slab layout
  // fixes the order in which forces are summed), so that this run and a World loaded from the file take
  // identical steps afterwards (results equal bit for bit). Not written: WorldParams (construction) and the
  // phase timings.
  void save_state(core::BinaryWriter& w);
  // Restores a state written by save_state into a World constructed with the same WorldParams (the thread count
  // may differ: results do not depend on it; dt is taken from the file, as set_dt may have changed it) with the
  // same walls and the same interactions added in the same order. Particles, bonds, pairs, wall state, break log,
  // time and counters are replaced by the file's (particles added before the call are dropped). Throws
  // std::runtime_error ("checkpoint <name>: ...") naming what does not match: a missing block tag, wall,
  // interaction or material count, an interaction's label, inconsistent array lengths or indices, a truncated
  // file. On an error the World's own state is unchanged; interactions read before the failing block may have
  // been restored, so do not step such a World.
  void load_state(core::BinaryReader& r);
  // Replaces this World's state by the union of the parts' owned particles (owned[k][i] != 0: part k owns its
  // particle i; every particle id owned once), the whole charge of a domain decomposition put back together
  // (ghost_domains.hpp re-cuts it). Particles in ascending id order with every per-particle array, wall histories
  // and flags; the bonds (broken ones of the last step too) and touching or sliding neighbour pairs (histories,
  // touch flags) whose first particle a part owns, from that part, sorted by their particles; each part's breaks of
  // bonds whose first particle it owns, by time; walls, time, counters, skin and dt from parts[0]; each interaction
  // from the parts' same interaction (Interaction::assemble_state; all Worlds have the same interactions in the same
  // order). As after load_state, the next step rebuilds the neighbour list. Throws std::invalid_argument on a mask
  // of the wrong size, an id owned twice, a bond or pair whose second particle is not in its part, other walls or
  // interactions, or an interaction that cannot be put together.
  // dangling (a rank's migration, ghost_domains.hpp: the parts are its own and its peers', not the whole charge): an
  // intact bond or kept pair whose second particle no part owns is dropped, and its first particle's id appended to
  // *dangling, instead of the throw.
  void assemble(const std::vector<const World*>& parts, const std::vector<std::vector<char>>& owned,
                std::vector<uint64_t>* dangling = nullptr);
  // Marks the ghosts of a domain decomposition (ghost_domains.hpp): ghost[i] != 0 for a copy of a particle another
  // rank owns, whose forces are not used. What concerns ghosts alone is left out: pairs of two ghosts are not listed,
  // bonds between two ghosts are dropped (their owners keep them), interactions skip ghosts (Interaction::set_ghosts).
  // Particles added later are not ghosts; removals keep the mask; load_state and assemble clear it. Throws
  // std::invalid_argument on a mask of the wrong size.
  void set_ghosts(const std::vector<char>& ghost);

 private:
  struct BondOutSlot {  // force on j (i gets -f), torques on i and j
    double f[3], ti[3], tj[3];
  };
  // What the bond loop reads and writes each step, 80 bytes a bond (a Bond is 144, its constants read and written
  // back with its state): the particles, the spring state and the index of the bond's constants in bprm_, a
  // table of the distinct constant sets (1199 for the gyp1200 chamber's 381,758 bonds). Built from bonds_ by
  // build_bond_hot in the same order; bonds_ gets the state back by sync_bonds. defer_i, defer_j: that
  // particle has bonds in more than one of the bond loop's thread chunks (bond_forces).
  struct BondHot {
    uint32_t i, j, prm;
    uint8_t alive, defer_i, defer_j, unused;
    double fn, tn, ft[3], tt[3];
  };
  struct BondPrm {
    double kn, kt, A, J, rb, damping, sigma_c, tau_c;
  };
  uint32_t bond_prm_index(const Bond& b);
  void build_bond_hot();  // bhot_, bdefer_ from bonds_ and the CSR
  void sync_bonds() const;  // the spring states and alive flags of bhot_ into bonds_, when bhot_ is ahead
  void prepare();
  void open_step();
  void run_steps(long nsteps);
  void rebuild();
  void rebuild_bond_csr();
  void resize_per_particle();
  void pair_forces();
  void bond_forces();
  void gather_forces(bool kick, bool drift);
  void move_walls();
  void build_slabs();
  // Adds pairs (i < j, not yet listed) to the neighbour list without a rebuild; false (nothing changed) when the
  // list is stale or a pair spans more than adjacent slabs. Used for bonds that just broke.
  bool insert_pairs(std::vector<std::pair<uint32_t, uint32_t>>& add);
  [[noreturn]] void blow_up(long culprit, double overlap, const std::string& what);
  void check_blow_up(bool walls);
  bool bonded(uint32_t i, uint32_t j) const;

  WorldParams prm_;
  Particles p_;
  int nt_ = 1;
  mutable std::vector<double> stress_pair_force_;  // contact_stress's scratch: per pair f and n (6), touching
  mutable std::vector<char> stress_pair_touch_;
  double skin_ = -1;
  double t_ = 0;
  long nstep_ = 0, nrebuild_ = 0;
  bool need_rebuild_ = true, bonds_dirty_ = true, dt_checked_ = false;
  // Bonds broken since the last compaction: they stay in bonds_ (alive 0, no force) until they are 1/32 of it, so a
  // break costs O(1) instead of the O(bonds) compaction and index rebuild (rebuild_bond_csr).
  std::size_t dead_bonds_ = 0;
  bool opened_ = false;  // between step_begin() and step_end()
  std::vector<char> ghost_;  // set_ghosts: per particle, 1 a ghost; empty: none
  std::size_t n_known_ = 0;  // particle count the per-particle arrays are sized for

  // neighbour list: pairs (i < j) grouped by owner i: i's pairs are [istart[i], istart[i+1])
  std::size_t npairs_ = 0;
  SVec<uint32_t> pj_, pi_;
  SVec<std::array<double, 3>> hist_;
  SVec<uint8_t> touch_;  // per pair: touching at the last force evaluation (else its history is zero)
  SVec<uint32_t> istart_;
  // slabs of cell layers along the grid's longest axis (set at each build): a pair's particles lie in the same
  // or adjacent slabs; owners of slab s are sorder_[sstart_[s] .. sstart_[s+1]) in index order
  SVec<uint32_t> sorder_, sstart_, slab_of_layer_, slab_of_;  // slab_of_: per particle
  // double buffers for the rebuild
  SVec<uint32_t> pj2_, pi2_, cnt_;
  SVec<std::array<double, 3>> hist2_;
  SVec<uint8_t> touch2_;
  std::vector<char> bad_thr_;  // per thread: overlap beyond the bound seen
  SVec<double> x0_, y0_, z0_;
  CellGrid grid_;

  // walls
  std::vector<PlanarWall> walls_;
  SVec<std::array<double, 3>> whist_;  // [particle * n_walls + wall]
  std::vector<double> wforce_thr_;            // per thread partial wall forces
  SVec<char> wtouch_;                  // per particle: had a wall contact last step
  std::vector<double> wplane_;                // per wall: n, n . p (fast distance test)
  std::vector<double> maxd_thr_;              // per thread max squared displacement since the last build
  // radius changes (set_radius): largest change since the last step, and a bound on any particle's since the build
  double step_growth_ = 0, growth_since_build_ = 0;

  // bonds
  mutable std::vector<Bond> bonds_;  // its spring state and alive flags are bhot_'s while bhot_ahead_
  SVec<BondHot> bhot_;
  mutable bool bhot_ahead_ = false;  // bhot_ holds newer spring states than bonds_ (the bond loop ran since)
  bool bhot_stale_ = true;           // bonds_ changed since bhot_ was built
  SVec<BondPrm> bprm_;
  std::map<std::array<uint64_t, 8>, uint32_t> bprm_index_;  // a set's bits -> its row of bprm_
  // the bonds with a deferred side, ascending, and their forces of the last step (bond_forces)
  std::vector<uint32_t> bdefer_;
  int bchunks_ = 1;  // the bond loop's chunks, one per thread (build_bond_hot)
  SVec<BondOutSlot> bout_;
  bool bonds_damped_ = false;  // some bond has damping > 0
  SVec<uint8_t> bcode_;  // per bond, last step: 0 intact, 1 broke in tension, 2 in shear
  SVec<uint32_t> bstart_, bref_;  // per particle: refs 2 * bond + (0: i side, 1: j side)
  std::vector<BondBreak> breaks_;

  std::vector<std::shared_ptr<Interaction>> interactions_;
  std::array<double, 7> phase_s_{};
};

// s6 += sym(a (x) f), in contact_stress's order xx yy zz xy yz zx (contact_stress.cpp).
void add_contact_stress(double* s6, const double a[3], const double f[3]);

}  // namespace dem
