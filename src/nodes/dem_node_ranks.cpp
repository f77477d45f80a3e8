#include "nodes/dem_node_ranks.hpp"

#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "parallel/mpi_engine.hpp"

namespace nodes {

namespace {
bool initialised = false;
constexpr int kMotionDoubles = 13;  // com 3, orientation 4 (w x y z), velocity 3, angular velocity 3

void pack(const coupling::BodyMotion& b, double* d) {
  for (int k = 0; k < 3; ++k) d[k] = b.com[k], d[7 + k] = b.velocity[k], d[10 + k] = b.angular_velocity[k];
  d[3] = b.orientation.w(), d[4] = b.orientation.x(), d[5] = b.orientation.y(), d[6] = b.orientation.z();
}

coupling::BodyMotion unpack(const double* d) {
  coupling::BodyMotion b;
  b.com = Eigen::Vector3d(d[0], d[1], d[2]);
  b.orientation = Eigen::Quaterniond(d[3], d[4], d[5], d[6]);
  b.velocity = Eigen::Vector3d(d[7], d[8], d[9]);
  b.angular_velocity = Eigen::Vector3d(d[10], d[11], d[12]);
  return b;
}
}  // namespace

bool launched_by_mpirun() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"); }

void init_ranks(int* argc, char*** argv) {
  MPI_Init(argc, argv);
  initialised = true;
}

int rank() {
  int r = 0;
  if (initialised) MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

int ranks() {
  int n = 1;
  if (initialised) MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

void finish_ranks() {
  if (initialised) MPI_Finalize();
  initialised = false;
}

void abort_ranks(int status) {
  if (initialised) MPI_Abort(MPI_COMM_WORLD, status);
  std::exit(status);
}

void decompose_over_ranks(coupling::ChamberDem& dem) {
  dem.decompose(parallel::mpi_engine(MPI_COMM_WORLD, 3.0 * dem.largest_sphere_radius()));
}

void tell_ranks(RankCall call) {
  if (!initialised || ranks() < 2) return;
  int c = static_cast<int>(call);
  MPI_Bcast(&c, 1, MPI_INT, 0, MPI_COMM_WORLD);
}

void tell_ranks_advance(const coupling::BodyMotion& mantle, const coupling::BodyMotion& concave, double dt) {
  if (!initialised || ranks() < 2) return;
  tell_ranks(RankCall::Advance);
  double d[2 * kMotionDoubles + 1];
  pack(mantle, d);
  pack(concave, d + kMotionDoubles);
  d[2 * kMotionDoubles] = dt;
  MPI_Bcast(d, 2 * kMotionDoubles + 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

int follow_rank0(coupling::ChamberDem& dem) {
  try {
    for (;;) {
      int c = 0;
      MPI_Bcast(&c, 1, MPI_INT, 0, MPI_COMM_WORLD);
      switch (static_cast<RankCall>(c)) {
        case RankCall::Advance: {
          double d[2 * kMotionDoubles + 1];
          MPI_Bcast(d, 2 * kMotionDoubles + 1, MPI_DOUBLE, 0, MPI_COMM_WORLD);
          try {
            dem.advance(unpack(d), unpack(d + kMotionDoubles), d[2 * kMotionDoubles]);
          } catch (const std::exception& e) {  // every rank has it (ChamberDem agrees on a step's failure): rank 0
            std::fprintf(stderr, "dem_node rank %d: %s; waiting for rank 0 to end the run\n", rank(), e.what());
          }                                    // closes its bag and tells the ranks to stop
          break;
        }
        case RankCall::Product:
          dem.product();
          break;
        case RankCall::Save: {
          std::ostringstream os;
          core::BinaryWriter w(os);
          dem.save_state(w);  // rank 0 writes the file
          break;
        }
        case RankCall::Load:
          dem.follow_load();
          break;
        case RankCall::Stop:
          return 0;
        default:
          throw std::runtime_error("unknown call " + std::to_string(c) + " from rank 0");
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dem_node rank %d: %s; stopping every rank\n", rank(), e.what());
    abort_ranks(1);
  }
}

}  // namespace nodes
