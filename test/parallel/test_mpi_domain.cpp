// The ghost exchange over MPI (parallel/mpi_domain.hpp), run by CTest under mpirun with 1, 2 and 3 ranks
// (oversubscribed on 2 cores). The pressed charge (test/common/pressed_charge.hpp) stepped on the ranks equals the
// same cut in one process (LocalDomains) bit for bit, and the whole charge in one World bit for bit on one rank and
// to round-off on more (the bound and its reason: test/dem/test_ghost_domains.cpp); every particle is owned once,
// the breaks are the whole World's; migrations and re-cuts through rank 0 give the one process's bit for bit; a run
// resumed from its checkpoint per rank continues bit for bit; a liner mesh's wrench summed over the ranks is the whole World's;
// particles added and removed between steps (on rank 0) reach their owners.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <unistd.h>
#include <string>
#include <vector>

#include "../common/pressed_charge.hpp"
#include "dem/ghost_domains.hpp"
#include "dem/mesh_contact.hpp"
#include "parallel/mpi_domain.hpp"

namespace {

using namespace pressed_charge;

bool rank_is_root() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r == 0;
}

// On rank 0: the MPI run's owned state (ids, x: MpiDomain::gather_owned) equals the same cut stepped in one process.
void expect_as_in_one_process(const std::vector<uint64_t>& ids, const std::vector<double>& x,
                              const dem::LocalDomains& local) {
  std::vector<uint64_t> lids;
  std::vector<double> lx;
  local.owned_state(lids, lx);
  ASSERT_EQ(ids, lids);
  ASSERT_EQ(x.size(), lx.size());
  EXPECT_EQ(0, std::memcmp(x.data(), lx.data(), x.size() * sizeof(double))) << "MPI and one process differ";
}

TEST(MpiDomain, StepsLikeTheSameCutInOneProcessAndTheWholeCharge) {
  const std::string ckpt = parallel::broadcast_bytes(MPI_COMM_WORLD, rank_is_root() ? state() : std::string());
  ASSERT_EQ(ckpt, state());  // every rank builds the same charge; the broadcast must not change a byte
  parallel::MpiDomain d(MPI_COMM_WORLD, ckpt, params(), walls, kReach);
  d.step(kSteps);
  std::vector<uint64_t> ids;
  std::vector<double> x;
  d.gather_owned(ids, x);
  const auto breaks = d.gather_breaks();
  if (!rank_is_root()) return;
  dem::LocalDomains local(state(), params(), walls, d.ranks(), kReach);
  local.step(kSteps);
  expect_as_in_one_process(ids, x, local);
  const Reference ref = reference(kSteps);
  ASSERT_EQ(ids, ref.ids);  // every particle owned by one rank
  const double worst = largest_position_difference(x, ref.x);
  if (d.ranks() == 1) {
    EXPECT_EQ(worst, 0.0);
  }
  EXPECT_LT(worst, 1e-13);
  EXPECT_EQ(breaks_after_cut(breaks), ref.breaks);
  EXPECT_FALSE(ref.breaks.empty());
  std::printf("%d ranks: largest position difference to the whole charge %.3g m, %zu breaks\n", d.ranks(), worst,
              ref.breaks.size());
}

TEST(MpiDomain, CutsTheChargeAnewLikeOneProcess) {
  // a margin of 0.1 mm, spent 8 times in 600 steps: the particles migrate point to point (default tolerance), or the
  // charge is cut anew through rank 0 (tolerance -1), as in one process (test_ghost_domains.cpp checks both against
  // the whole World)
  const double reach = 2e-3 + 0.2e-3;
  for (double tolerance : {-1.0, dem::kRebalanceTolerance}) {
    parallel::MpiDomain d(MPI_COMM_WORLD, state(), params(), walls, reach);
    d.set_rebalance_tolerance(tolerance);
    d.step(600);
    std::vector<uint64_t> ids;
    std::vector<double> x;
    d.gather_owned(ids, x);
    const auto breaks = d.gather_breaks();
    if (!rank_is_root()) continue;
    SCOPED_TRACE("tolerance " + std::to_string(tolerance));
    dem::LocalDomains local(state(), params(), walls, d.ranks(), reach);
    local.set_rebalance_tolerance(tolerance);
    local.step(600);
    EXPECT_EQ(d.recuts(), local.recuts());
    EXPECT_EQ(d.migrations(), local.migrations());
    EXPECT_GE(tolerance < 0 ? d.recuts() : d.migrations(), 5);
    expect_as_in_one_process(ids, x, local);
    EXPECT_EQ(breaks_after_cut(breaks), breaks_after_cut(local.breaks()));
  }
}

TEST(MpiDomain, ResumesFromItsCheckpointBitForBit) {
  // 200 steps, a checkpoint per rank, 400 more (migrations before and after it); a run resumed from the files takes the
  // same 400 steps
  std::string dir;
  if (rank_is_root()) {
    char tmpl[] = "/tmp/test_parallel_XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir = tmpl;
  }
  dir = parallel::broadcast_bytes(MPI_COMM_WORLD, dir);
  const std::string prefix = dir + "/charge";
  parallel::MpiDomain d(MPI_COMM_WORLD, state(), params(), walls, 2e-3 + 0.2e-3);
  d.step(200);
  d.save(prefix);
  const int recuts_at_save = d.recuts(), migrations_at_save = d.migrations();
  d.step(400);
  std::vector<uint64_t> ids, rids;
  std::vector<double> x, rx;
  d.gather_owned(ids, x);
  parallel::MpiDomain r = parallel::MpiDomain::resume(MPI_COMM_WORLD, prefix, params(), walls);
  EXPECT_EQ(r.recuts(), recuts_at_save);
  r.step(400);
  EXPECT_EQ(r.recuts(), d.recuts());
  EXPECT_EQ(r.migrations(), d.migrations() - migrations_at_save);  // a process's own count
  EXPECT_GT(r.migrations(), 0);
  r.gather_owned(rids, rx);
  // a prefix no run wrote: every rank refuses, naming its file
  int refused = 0;
  try {
    parallel::MpiDomain::resume(MPI_COMM_WORLD, dir + "/nothing", params(), walls);
  } catch (const std::runtime_error& e) {
    refused = std::string(e.what()).find("nothing.rank") != std::string::npos ||
              std::string(e.what()).find("another rank") != std::string::npos;
  }
  int all = 0;
  MPI_Allreduce(&refused, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(all, d.ranks());
  MPI_Barrier(MPI_COMM_WORLD);
  if (!rank_is_root()) return;
  ASSERT_EQ(ids, rids);
  ASSERT_EQ(x.size(), rx.size());
  EXPECT_EQ(0, std::memcmp(x.data(), rx.data(), x.size() * sizeof(double))) << "the resumed run differs";
  for (int k = 0; k < d.ranks(); ++k) std::remove(parallel::MpiDomain::rank_file(prefix, k, d.ranks()).c_str());
  rmdir(dir.c_str());
}

TEST(MpiDomain, ALinerMeshGetsTheWholeChargesWrenchSummedOverTheRanks) {
  // the charge on the plate of triangles, re-cut 8 times in 600 steps: the same steps as in one process, and the
  // ranks' wrenches summed (MPI_Allreduce, in its own order) to the whole World's within round-off
  std::vector<std::shared_ptr<dem::MeshContact>> made;
  const double reach = 2e-3 + 0.2e-3;
  parallel::MpiDomain d(MPI_COMM_WORLD, plate_state(), params(), on_plate(&made), reach);
  d.step(600);
  const dem::MeshWrench sum = parallel::sum_over_ranks(MPI_COMM_WORLD, made.back()->wrench_about(Eigen::Vector3d::Zero()));
  std::vector<uint64_t> ids;
  std::vector<double> x;
  d.gather_owned(ids, x);
  if (!rank_is_root()) return;
  std::vector<std::shared_ptr<dem::MeshContact>> lmade;
  dem::LocalDomains local(plate_state(), params(), on_plate(&lmade), d.ranks(), reach);
  local.step(600);
  expect_as_in_one_process(ids, x, local);
  const Reference ref = reference(600, true);
  EXPECT_LT((sum.force - ref.plate.force).norm(), 1e-9 * ref.plate.force.norm());
  EXPECT_LT((sum.torque - ref.plate.torque).norm(), 1e-9 * ref.plate.force.norm() * kHalf);
  std::printf("%d ranks, plate: %d re-cuts, force %.6g N (whole World %.6g N)\n", d.ranks(), d.recuts(), sum.force.z(),
              ref.plate.force.z());
}

TEST(MpiDomain, ParticlesAddedAndRemovedOnRankZeroGoToTheirOwners) {
  // a feed and discharge every 100 steps (pressed_charge::recycle_lowest, run on rank 0 on the whole charge): the
  // same steps as in one process; an edit that fails on rank 0 stops every rank
  parallel::MpiDomain d(MPI_COMM_WORLD, state(), params(), walls, kReach);
  for (int k = 0; k < 3; ++k) {
    d.edit(recycle_lowest);
    d.step(100);
  }
  int refused = 0;
  try {
    d.edit([](dem::World&) { throw std::runtime_error("no room for the feed"); });
  } catch (const std::runtime_error& e) {
    refused = std::string(e.what()).find("no room for the feed") != std::string::npos;
  }
  int all = 0;
  MPI_Allreduce(&refused, &all, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  EXPECT_EQ(all, d.ranks());
  std::vector<uint64_t> ids;
  std::vector<double> x;
  d.gather_owned(ids, x);
  if (!rank_is_root()) return;
  dem::LocalDomains local(state(), params(), walls, d.ranks(), kReach);
  for (int k = 0; k < 3; ++k) {
    local.edit(recycle_lowest);
    local.step(100);
  }
  expect_as_in_one_process(ids, x, local);
  ASSERT_EQ(ids.size(), 500u);
}

}  // namespace

// MPI around gtest: every rank runs the tests, rank 0 alone prints; the exit status is rank 0's and any failure's.
int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  if (!rank_is_root()) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int failed = RUN_ALL_TESTS() != 0, any = 0;
  MPI_Allreduce(&failed, &any, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  MPI_Finalize();
  return any;
}
