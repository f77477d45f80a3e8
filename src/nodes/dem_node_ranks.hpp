#pragma once
// dem_node on MPI ranks (issue 25; `crusher run --load dem --ranks N`): rank 0 is the ROS node, talking to mbd_node as
// always; every rank steps its azimuthal part of the charge (coupling::ChamberDem::decompose over
// parallel::MpiEngine). Before each of ChamberDem's collective calls rank 0 tells the other ranks which one
// (tell_ranks); they wait for it and make the same call (follow_rank0) until told to stop. Launched without mpirun,
// dem_node runs in one process as before.
#include <vector>

#include "coupling/chamber_dem.hpp"

namespace nodes {

enum class RankCall : int { Advance = 1, Product = 2, Save = 3, Load = 4, Stop = 5 };

bool launched_by_mpirun();                      // mpirun's rank variables are in the environment
void init_ranks(int* argc, char*** argv);       // MPI_Init
int rank();                                     // 0 without MPI
int ranks();                                    // 1 without MPI
void finish_ranks();                            // MPI_Finalize (when initialised)
[[noreturn]] void abort_ranks(int status);      // every rank stops (MPI_Abort)
// The ghost reach for a chamber: three times its largest sphere radius (margin half a radius between re-cuts).
void decompose_over_ranks(coupling::ChamberDem& dem);

// Rank 0, with more than one rank: tells the others the next collective call. Advance takes the mantle's and the
// concave's motion and the interval.
void tell_ranks(RankCall call);
void tell_ranks_advance(const coupling::BodyMotion& mantle, const coupling::BodyMotion& concave, double dt);
// Ranks other than 0: make the calls rank 0 tells until Stop; returns 0 then. A failure here stops every rank.
int follow_rank0(coupling::ChamberDem& dem);

}  // namespace nodes
