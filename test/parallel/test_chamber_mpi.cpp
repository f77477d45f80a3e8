// The coupled chamber's DEM on MPI ranks (issue 25): coupling::ChamberDem decomposed with parallel::MpiEngine on 1, 2
// and 3 ranks (CTest's test_parallel_np1-3) equals the same rank count in one process (dem::LocalEngine) bit for bit:
// particles, wrenches, force map, feed, breaks, crushing and discharge. How that rank count compares with the whole
// charge in one World (bit for bit on one rank, to round-off on more): test/coupling/test_chamber_domains.cpp.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "../coupling/chamber_outcome.hpp"
#include "../coupling/small_chamber.hpp"
#include "coupling/chamber_dem.hpp"
#include "dem/domain_engine.hpp"
#include "parallel/mpi_engine.hpp"

namespace {

constexpr double kReach = 0.02;  // as test_chamber_domains.cpp
constexpr int kSteps = 8;  // feed, breaks, crushing into growing fragments, discharge (test_chamber_domains.cpp)

int rank_of_world() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r;
}

using test_chamber::Outcome;

// Every rank's owned state to rank 0, sorted by id.
void gather_owned(const coupling::ChamberDem& d, Outcome* o) {
  std::vector<uint64_t> ids;
  std::vector<double> x;
  d.owned_state(ids, x);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int n = static_cast<int>(ids.size());
  std::vector<int> counts(size), displs(size), counts9(size), displs9(size);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD);
  for (int r = 0; r < size; ++r) counts9[r] = 9 * counts[r];
  for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1], displs9[r] = 9 * displs[r];
  const int total = displs[size - 1] + counts[size - 1];
  std::vector<uint64_t> all_ids(rank_of_world() == 0 ? total : 0);
  std::vector<double> all_x(rank_of_world() == 0 ? 9 * total : 0);
  MPI_Gatherv(ids.data(), n, MPI_UINT64_T, all_ids.data(), counts.data(), displs.data(), MPI_UINT64_T, 0, MPI_COMM_WORLD);
  MPI_Gatherv(x.data(), 9 * n, MPI_DOUBLE, all_x.data(), counts9.data(), displs9.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD);
  std::vector<std::size_t> order(all_ids.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all_ids[a] < all_ids[b]; });
  for (std::size_t k : order) {
    o->ids.push_back(all_ids[k]);
    o->state.insert(o->state.end(), all_x.begin() + 9 * k, all_x.begin() + 9 * k + 9);
  }
}

Outcome finish(coupling::ChamberDem& d, std::vector<double> wrench, bool gather) {
  Outcome o;
  if (gather)
    gather_owned(d, &o);
  else
    d.owned_state(o.ids, o.state);
  o.wrench = std::move(wrench);
  test_chamber::finish_outcome(d, &o);
  return o;
}

void expect_bit_for_bit(const Outcome& a, const Outcome& b) {
  test_chamber::expect_same_counts(a, b);
  ASSERT_EQ(a.state.size(), b.state.size());
  EXPECT_EQ(0, std::memcmp(a.state.data(), b.state.data(), a.state.size() * sizeof(double)));
  EXPECT_EQ(a.wrench, b.wrench);
  EXPECT_EQ(a.map, b.map);
  EXPECT_EQ(a.product.in_chamber_kg, b.product.in_chamber_kg);
}

}  // namespace

TEST(ChamberMpi, RanksStepTheChamberAsTheSameCutInOneProcess) {
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const auto p = test_chamber::busy_small_chamber();
  coupling::ChamberDem d(p);
  d.decompose(parallel::mpi_engine(MPI_COMM_WORLD, kReach));
  std::vector<double> wrench;
  test_chamber::gyrate_steps(d, p, 0, kSteps, &wrench);
  const Outcome mpi = finish(d, wrench, true);
  if (rank_of_world() != 0) return;
  coupling::ChamberDem local(p);
  local.decompose([size](const std::string& ckpt, const dem::WorldParams& wp, const std::function<void(dem::World&)>& setup) {
    return std::make_unique<dem::LocalEngine>(ckpt, wp, setup, size, kReach);
  });
  std::vector<double> lw;
  test_chamber::gyrate_steps(local, p, 0, kSteps, &lw);
  const Outcome one = finish(local, lw, false);
  expect_bit_for_bit(mpi, one);
  EXPECT_GT(mpi.broken.size(), 0u);
  EXPECT_GT(mpi.product.metaparticles_fragmented, 0);
  EXPECT_GT(d.engine().recuts(), kSteps);
}

// A decomposed run's checkpoint (the whole charge, written on rank 0) resumed on the same ranks continues as the
// saving run does, bit for bit.
TEST(ChamberMpi, RunResumedFromItsCheckpointContinuesBitForBit) {
  const auto p = test_chamber::busy_small_chamber();
  coupling::ChamberDem a(p);
  a.decompose(parallel::mpi_engine(MPI_COMM_WORLD, kReach));
  std::vector<double> wa, wb;
  test_chamber::gyrate_steps(a, p, 0, 6, &wa);
  std::stringstream file;
  {
    core::BinaryWriter w(file);
    a.save_state(w);  // collective; rank 0 writes
  }
  const std::string bytes = parallel::broadcast_bytes(MPI_COMM_WORLD, file.str());
  coupling::ChamberDem b(p);
  std::istringstream is(bytes);
  core::BinaryReader r(is, "in memory");
  b.load_state(r);
  b.decompose(parallel::mpi_engine(MPI_COMM_WORLD, kReach));
  wa.clear();
  test_chamber::gyrate_steps(a, p, 6, 12, &wa);
  test_chamber::gyrate_steps(b, p, 6, 12, &wb);
  const Outcome oa = finish(a, wa, true), ob = finish(b, wb, true);
  if (rank_of_world() != 0) return;
  expect_bit_for_bit(oa, ob);
}
