#pragma once
// One rank's part of the decomposed charge over MPI (issue 25): the ghost exchange of dem/ghost_domains.hpp with
// the buffers sent between processes instead of copied. ROS-free; the only library that links MPI.
//
// Every rank cuts its part from the same whole-charge checkpoint (broadcast from rank 0), so all compute the same
// layout. A step: World::step_begin(), each rank sends its owned particles' x, v, w to the peers that hold them as
// ghosts and takes its ghosts' from their owners (non-blocking, one message per peer and direction), then
// World::step_end(). A run on P ranks equals LocalDomains with P ranks in one process bit for bit (the same Worlds
// take the same steps). Before each step the ranks agree (MPI_Allreduce) whether a particle has left the layout's
// margin; then the particles migrate point to point, the sectors kept (each rank's part to the peers that need it:
// O(N / P) bytes per rank), or, when the sectors' counts are out of balance and at edits, the charge is cut anew through
// rank 0 (every rank's World to it, the whole charge assembled and broadcast: O(N) per rank).
#include <mpi.h>

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "dem/ghost_domains.hpp"
#include "dem/mesh_contact.hpp"

namespace parallel {

// Collective: the sum over the ranks of each rank's wrench on a liner (its owned particles' share, the ghosts being
// skipped: dem/mesh_contact.hpp), about the same point on every rank: the whole charge's wrench, on every rank.
dem::MeshWrench sum_over_ranks(MPI_Comm comm, const dem::MeshWrench& mine);

// Collective: on rank 0 every rank's bytes, concatenated in rank order (empty elsewhere), and, when asked, each rank's
// byte count.
std::vector<char> gather_bytes(MPI_Comm comm, const std::vector<char>& mine, std::vector<int>* counts_out = nullptr);

// Rank 0's bytes on every rank of comm.
std::string broadcast_bytes(MPI_Comm comm, const std::string& on_root);

class MpiDomain {
 public:
  // Collective. checkpoint: the whole charge's World::save_state, the same on every rank; setup: the walls and
  // interactions of the saving World.
  MpiDomain(MPI_Comm comm, const std::string& checkpoint, const dem::WorldParams& params,
            const std::function<void(dem::World&)>& setup, double reach);
  // Collective: resumes from the files save() wrote (the same rank count), continuing bit for bit.
  static MpiDomain resume(MPI_Comm comm, const std::string& prefix, const dem::WorldParams& params,
                          const std::function<void(dem::World&)>& setup);
  // Collective: each rank writes its part to PREFIX.rank<r>-of-<P> (whole files, through a rename); throws
  // std::runtime_error on every rank when any rank could not write (its message names the file).
  void save(const std::string& prefix);
  static std::string rank_file(const std::string& prefix, int rank, int ranks);
  int rank() const { return rank_; }
  int ranks() const { return size_; }
  dem::World& world() { return *d_.world; }
  const dem::GhostPlan& plan() const { return d_.plan; }
  double margin() const { return d_.margin; }
  // Collective: n steps with the ghost exchange, the charge cut anew when the margin is spent.
  void step(long n = 1);
  int recuts() const { return recuts_; }          // whole re-cuts (rebalanced, or edited)
  int migrations() const { return migrations_; }  // migrations, the sectors kept (this process's, not checkpointed)
  // As LocalDomains::set_rebalance_tolerance; the same on every rank.
  void set_rebalance_tolerance(double t) { rebalance_tolerance_ = t; }
  // Collective, between two steps: the charge put together on rank 0, changed there by `edit` (particles added or
  // removed: feed, discharge, crushing; new particles take the whole charge's next ids; edit runs on rank 0 only),
  // and cut anew.
  void edit(const std::function<void(dem::World&)>& edit);
  // Wall seconds this rank spent since construction in the ghost exchange (packing, MPI and waiting for the peers),
  // in re-cuts and in migrations (with the count that chose between them), for the benchmark.
  double exchange_seconds() const { return exchange_s_; }
  double recut_seconds() const { return recut_s_; }
  double migrate_seconds() const { return migrate_s_; }
  std::size_t ghosts() const;  // this rank's ghost count
  // Collective: the largest displacement of any rank's owned particle since the cut (m).
  double max_displacement() const;
  // Collective: on rank 0 every owned particle's x, v, w by id (kGhostDoubles each, ids ascending); empty elsewhere.
  void gather_owned(std::vector<uint64_t>& ids, std::vector<double>& state) const;
  // Collective: on rank 0 the breaks each rank counts (dem::owned_breaks); empty elsewhere.
  std::vector<dem::BondBreak> gather_breaks() const;

 private:
  MpiDomain(MPI_Comm comm, const dem::WorldParams& params, const std::function<void(dem::World&)>& setup);
  void exchange();
  void recut(const std::function<void(dem::World&)>& edit = nullptr);
  void migrate();
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
  dem::WorldParams params_;
  std::function<void(dem::World&)> setup_;
  double reach_ = 0, rebalance_tolerance_ = dem::kRebalanceTolerance;
  int recuts_ = 0, migrations_ = 0;
  double exchange_s_ = 0, recut_s_ = 0, migrate_s_ = 0;
  dem::Domain d_;
  std::vector<std::vector<double>> out_, in_;  // per peer: send and receive buffers
};

}  // namespace parallel
