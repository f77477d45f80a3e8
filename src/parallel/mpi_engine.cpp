#include "parallel/mpi_engine.hpp"

namespace parallel {

MpiEngine::MpiEngine(MPI_Comm comm, const std::string& checkpoint, const dem::WorldParams& params,
                     const std::function<void(dem::World&)>& setup, double reach)
    : comm_(comm), d_(comm, broadcast_bytes(comm, checkpoint), params, setup, reach) {}

// In rank order on rank 0 (((v0 + v1) + v2) ...), as LocalEngine's caller sums its parts, then to every rank: the same
// bits as the ranks in one process (MPI_Allreduce's order is the library's).
void MpiEngine::sum(std::vector<double>& v) {
  int size = 1, rank = 0;
  MPI_Comm_size(comm_, &size);
  MPI_Comm_rank(comm_, &rank);
  const int n = static_cast<int>(v.size());
  std::vector<double> all(rank == 0 ? v.size() * static_cast<std::size_t>(size) : 0);
  MPI_Gather(v.data(), n, MPI_DOUBLE, all.data(), n, MPI_DOUBLE, 0, comm_);
  if (rank == 0)
    for (int r = 1; r < size; ++r)
      for (int q = 0; q < n; ++q) v[q] += all[static_cast<std::size_t>(r) * n + q];
  MPI_Bcast(v.data(), n, MPI_DOUBLE, 0, comm_);
}

double MpiEngine::min(double x) {
  double y = x;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return y;
}

double MpiEngine::max(double x) {
  double y = x;
  MPI_Allreduce(&x, &y, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return y;
}

std::string MpiEngine::gather(const std::string& mine) {
  const std::vector<char> all = gather_bytes(comm_, std::vector<char>(mine.begin(), mine.end()));
  return std::string(all.begin(), all.end());
}

dem::EngineFactory mpi_engine(MPI_Comm comm, double reach, double rebalance_tolerance) {
  return [comm, reach, rebalance_tolerance](const std::string& ckpt, const dem::WorldParams& wp,
                                            const std::function<void(dem::World&)>& setup) {
    auto e = std::make_unique<MpiEngine>(comm, ckpt, wp, setup, reach);
    e->set_rebalance_tolerance(rebalance_tolerance);
    return e;
  };
}

}  // namespace parallel
