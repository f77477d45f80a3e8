// The ghost exchange over MPI (parallel/mpi_domain.hpp), run by CTest under mpirun with 1, 2 and 3 ranks
// (oversubscribed on 2 cores). The pressed charge (test/common/pressed_charge.hpp) stepped on the ranks equals the
// same cut in one process (LocalDomains) bit for bit, and the whole charge in one World bit for bit on one rank and
// to round-off on more (the bound and its reason: test/dem/test_ghost_domains.cpp); every particle is owned once,
// the breaks are the whole World's; re-cuts through rank 0 give the one process's re-cuts bit for bit.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "../common/pressed_charge.hpp"
#include "dem/ghost_domains.hpp"
#include "parallel/mpi_domain.hpp"

namespace {

using namespace pressed_charge;

bool rank_is_root() {
  int r = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &r);
  return r == 0;
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
  std::vector<uint64_t> lids;
  std::vector<double> lx;
  local.owned_state(lids, lx);
  ASSERT_EQ(ids, lids);
  ASSERT_EQ(x.size(), lx.size());
  EXPECT_EQ(0, std::memcmp(x.data(), lx.data(), x.size() * sizeof(double))) << "MPI and one process differ";
  const Reference ref = reference(kSteps);
  ASSERT_EQ(ids, ref.ids);  // every particle owned by one rank
  double worst = 0;
  for (std::size_t k = 0; k < x.size(); ++k)
    if (k % dem::kGhostDoubles < 3) worst = std::max(worst, std::fabs(x[k] - ref.x[k]));
  if (d.ranks() == 1) EXPECT_EQ(worst, 0.0);
  EXPECT_LT(worst, 1e-13);
  EXPECT_EQ(breaks_after_cut(breaks), ref.breaks);
  EXPECT_FALSE(ref.breaks.empty());
  std::printf("%d ranks: largest position difference to the whole charge %.3g m, %zu breaks\n", d.ranks(), worst,
              ref.breaks.size());
}

TEST(MpiDomain, CutsTheChargeAnewLikeOneProcess) {
  // a margin of 0.1 mm, spent 8 times in 600 steps: each re-cut goes through rank 0 (test_ghost_domains.cpp checks
  // the re-cut itself against the whole World)
  const double reach = 2e-3 + 0.2e-3;
  parallel::MpiDomain d(MPI_COMM_WORLD, state(), params(), walls, reach);
  d.step(600);
  std::vector<uint64_t> ids;
  std::vector<double> x;
  d.gather_owned(ids, x);
  const auto breaks = d.gather_breaks();
  if (!rank_is_root()) return;
  dem::LocalDomains local(state(), params(), walls, d.ranks(), reach);
  local.step(600);
  EXPECT_EQ(d.recuts(), local.recuts());
  EXPECT_GE(d.recuts(), 5);
  std::vector<uint64_t> lids;
  std::vector<double> lx;
  local.owned_state(lids, lx);
  ASSERT_EQ(ids, lids);
  ASSERT_EQ(x.size(), lx.size());
  EXPECT_EQ(0, std::memcmp(x.data(), lx.data(), x.size() * sizeof(double))) << "MPI and one process differ";
  EXPECT_EQ(breaks_after_cut(breaks), breaks_after_cut(local.breaks()));
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
