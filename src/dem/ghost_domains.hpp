#pragma once
// Ghost exchange of an azimuthal domain decomposition (issue 25), ROS-free and without MPI: how one rank's World
// is cut from the whole charge's state, which of its particles it sends to each peer and which ghosts it receives,
// and the exchange itself in one process (LocalDomains; the MPI engine sends the same buffers between processes).
//
// Each rank holds a World with the particles it owns and its ghosts (owned elsewhere, within `reach` of its wedge:
// sector_decomposition.hpp), in the whole charge's particle order, with their bonds, contact histories and walls.
// Every step: World::step_begin() (kick, drift), then every ghost takes its owner's x, v, w, then World::step_end()
// (forces, kick). A pair or bond is computed on each rank that holds both particles, from the same state: an owned
// particle gets every force it would get in one World; only the order in which its pair forces are summed differs
// (each World's own neighbour slabs), so positions agree to round-off, not bit for bit (one rank: bit for bit).
// What the ghosts' own forces sum to is not used: pairs and bonds of two ghosts are left out, meshes skip ghosts
// (World::set_ghosts), so a rank's liner wrench is its owned particles' share.
//
// The layout holds while no particle has moved more than margin = (reach - 2 r_max) / 2 from where it was at the
// cut: two particles that were `reach` apart cannot touch before. Then the particles migrate, the sectors kept: each
// rank sends its part to the peers that own one of its particles now or see it as a ghost (migration_peers), and
// cuts its new part from the union of its own and the received parts (migrate_domain), so particles change owner
// with their bonds, contact histories and break logs; a rank sends, loads and assembles O(N / P) bytes (the peers'
// parts, not the whole charge). Only when the sectors' counts would differ by more than the rebalance tolerance
// (default 5 % over the mean), and at edits, is the charge cut anew: put back together whole (World::assemble) and
// cut into equal-count sectors (in one process; MPI: through rank 0, O(N) per rank).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dem/sector_decomposition.hpp"
#include "dem/world.hpp"

namespace dem {

// One rank's exchange with each peer q: send[q] its owned particles that q holds as ghosts, recv[q] its ghosts that q
// owns; indices into the rank's World, both in the whole charge's order, so that the two ends list the same
// particles in the same order.
struct GhostPlan {
  int rank = 0;
  std::vector<std::vector<uint32_t>> send, recv;
  std::vector<char> owned;  // per particle of the rank's World: 1 owned, 0 ghost
};

// Cuts rank r's part out of a World that holds the whole charge (for example loaded from its checkpoint): removes
// every particle the rank neither owns nor sees as a ghost (their bonds and contact histories go with them), marks
// the ghosts (World::set_ghosts) and returns the exchange plan. `layout` is rank_layout() of the whole charge's particles in the World's order.
// Throws std::invalid_argument when the layout does not match the World's particle count, or when a bond of an
// owned particle has its other end beyond the ghosts (reach shorter than the bond: named).
GhostPlan cut_domain(World& w, const RankLayout& layout, int rank);

// A World made with params and setup (the walls and interactions of the charge's Worlds); load_world then reads its
// state from r (World::save_state), throwing std::runtime_error as World::load_state does.
std::unique_ptr<World> new_world(const WorldParams& params, const std::function<void(World&)>& setup);
std::unique_ptr<World> load_world(core::BinaryReader& r, const WorldParams& params,
                                  const std::function<void(World&)>& setup);

// x, y, z, v, w of the listed particles: 9 doubles each, in list order.
constexpr std::size_t kGhostDoubles = 9;
void pack_ghosts(const Particles& p, const std::vector<uint32_t>& idx, std::vector<double>& buf);
void unpack_ghosts(Particles& p, const std::vector<uint32_t>& idx, const double* buf);

// Default relative imbalance of the sectors' counts over which a spent margin rebalances (a whole re-cut) instead of
// migrating.
constexpr double kRebalanceTolerance = 0.05;

// One rank's part of the charge: its World, exchange plan and owned particles' positions at the cut.
struct Domain {
  std::unique_ptr<World> world;
  GhostPlan plan;
  std::vector<double> x_cut;  // owned particles' x, y, z at the cut, in World order
  double margin = 0;          // (reach - 2 r_max) / 2 of the whole charge (m)
  SectorDecomposition sectors{{0.0, 2 * M_PI}};
  double max_displacement() const;  // largest displacement of an owned particle since the cut (m)
};

// Rank `rank` of `ranks`: loads the whole charge's checkpoint (World::save_state) into a World made with params and
// setup (the walls and interactions the saving World had), cuts equal-count sectors (balanced_sectors) and keeps the
// rank's part. Every rank computes the same layout from the same bytes. Throws std::invalid_argument on a reach not
// above the largest contact distance 2 r_max, or one shorter than a bond across a boundary.
Domain cut_charge(const std::string& checkpoint, const WorldParams& params, const std::function<void(World&)>& setup,
                  int ranks, int rank, double reach);

// A rank's part as it stands between two steps, for a checkpoint per rank: the World (World::save_state), the plan,
// the positions at the cut, the margin and the sectors (block "DOMN"). load_domain restores it into a World made with
// params and setup, so that the rank continues bit for bit; it throws std::runtime_error naming what does not match
// (a rank or rank count other than the caller's, a damaged file).
void save_domain(Domain& d, core::BinaryWriter& w);
Domain load_domain(core::BinaryReader& r, const WorldParams& params, const std::function<void(World&)>& setup,
                   int ranks, int rank);

// Per rank q, how many of d's owned particles lie in q's sector now (summed over the ranks: the counts a migration
// leaves).
std::vector<long> owner_counts(const Domain& d);
// Whether sectors of these counts are out of balance: the largest above (1 + tolerance) x the mean.
bool needs_rebalance(const std::vector<long>& counts, double tolerance);
// Per rank q (1: yes), whether q needs d's part for a migration: one of d's owned particles lies in q's sector now
// or within `reach` of it (never d's own rank).
std::vector<char> migration_peers(const Domain& d, double reach);
// A rank's new part after its particles moved, the sectors of `mine` (its current part) kept: cut from the union of
// the owned particles of parts (in rank order: its own World and those of the peers whose migration_peers name it,
// with their ownership masks), World::assemble leaving out the bonds and pairs that reach beyond them. Throws
// std::runtime_error naming a particle of the new part that lost a bond or contact that way (a peer that should
// have sent did not).
Domain migrate_domain(const std::vector<const World*>& parts, const std::vector<std::vector<char>>& owned,
                      const Domain& mine, const WorldParams& params, const std::function<void(World&)>& setup,
                      double reach);

// The whole charge put back together from the domains' Worlds (World::assemble of their owned particles), saved as
// a checkpoint for cut_charge: how the charge is cut anew once the margin is spent (particles change owner, sectors
// are rebalanced). setup: as for cut_charge.
// edit (optional): changes the whole charge before it is saved (particles added or removed: feed, discharge,
// crushing), as LocalDomains::edit and MpiDomain::edit do between two steps.
std::string assemble_charge(const std::vector<const World*>& parts, const std::vector<std::vector<char>>& owned,
                            const WorldParams& params, const std::function<void(World&)>& setup,
                            const std::function<void(World&)>& edit = nullptr);

// The decomposed charge in one process: `ranks` Worlds cut from a checkpoint of the whole charge.
class LocalDomains {
 public:
  // checkpoint: World::save_state of the whole charge; setup adds the walls and interactions that the saving World
  // had (load_state needs them). Sectors of equal particle count (balanced_sectors).
  LocalDomains(const std::string& checkpoint, const WorldParams& params,
               const std::function<void(World&)>& setup, int ranks, double reach);
  int ranks() const { return static_cast<int>(domains_.size()); }
  World& world(int r) { return *domains_.at(r).world; }
  const GhostPlan& plan(int r) const { return domains_.at(r).plan; }
  const SectorDecomposition& sectors() const { return domains_.at(0).sectors; }
  double margin() const { return domains_.at(0).margin; }
  // Largest displacement of an owned particle since the cut (m).
  double max_displacement() const;
  // n steps of every rank with the ghost exchange; before a step that the layout no longer covers the particles
  // migrate, or the charge is cut anew when the sectors are out of balance.
  void step(long n = 1);
  int recuts() const { return recuts_; }          // how often the charge was cut anew (rebalanced, or edited)
  int migrations() const { return migrations_; }  // how often the particles migrated, the sectors kept
  // Relative imbalance of the sectors' counts over which the charge is cut anew instead of migrating (default 0.05;
  // 0: rebalance at every re-cut; a large value: always migrate).
  void set_rebalance_tolerance(double t) { rebalance_tolerance_ = t; }
  // Between two steps: the charge put together, changed by `edit` in one World (particles added or removed, as a
  // coupled run's feed, discharge and crushing do; new particles take the whole charge's next ids), and cut anew.
  void edit(const std::function<void(World&)>& edit);
  // The owned particles' state by particle id: x, y, z, vx, vy, vz, wx, wy, wz (kGhostDoubles each), ids ascending.
  void owned_state(std::vector<uint64_t>& ids, std::vector<double>& state) const;
  // Bond breaks counted once (by the rank that owns the bond's first particle), in break-log order per rank.
  std::vector<BondBreak> breaks() const;

 private:
  void exchange();
  void recut(const std::function<void(World&)>& edit = nullptr);
  void migrate();
  WorldParams params_;
  std::function<void(World&)> setup_;
  double reach_ = 0, rebalance_tolerance_ = kRebalanceTolerance;
  int recuts_ = 0, migrations_ = 0;
  std::vector<Domain> domains_;
};

// The owned particles of some Worlds (owned[k]: per particle of parts[k], 1 owned; null: all) by id, ascending: ids
// and x, y, z, vx, vy, vz, wx, wy, wz (kGhostDoubles each).
void owned_state(const std::vector<const World*>& parts, const std::vector<const std::vector<char>*>& owned,
                 std::vector<uint64_t>& ids, std::vector<double>& state);

// Breaks in w's log counted by this rank: those whose first particle it owns.
std::vector<BondBreak> owned_breaks(const World& w, const GhostPlan& plan);

}  // namespace dem
