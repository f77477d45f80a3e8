#include "parallel/mpi_domain.hpp"

#include "core/atomic_file.hpp"

#include <algorithm>
#include <chrono>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace parallel {

namespace {
int rank_of(MPI_Comm c) {
  int r = 0;
  MPI_Comm_rank(c, &r);
  return r;
}
int size_of(MPI_Comm c) {
  int n = 1;
  MPI_Comm_size(c, &n);
  return n;
}

template <class T>
std::vector<char> bytes_of(const std::vector<T>& v) {
  const char* b = reinterpret_cast<const char*>(v.data());
  return std::vector<char>(b, b + v.size() * sizeof(T));
}
template <class T>
std::vector<T> from_bytes(const std::vector<char>& b) {
  std::vector<T> v(b.size() / sizeof(T));
  std::copy(b.begin(), b.begin() + static_cast<long>(v.size() * sizeof(T)), reinterpret_cast<char*>(v.data()));
  return v;
}
}  // namespace

// Rank 0 gets every rank's bytes, concatenated in rank order (and, when asked, each rank's byte count).
std::vector<char> gather_bytes(MPI_Comm comm, const std::vector<char>& mine, std::vector<int>* counts_out) {
  const int size = size_of(comm), rank = rank_of(comm);
  int n = static_cast<int>(mine.size());
  std::vector<int> counts(size), displs(size);
  MPI_Gather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm);
  std::vector<char> all;
  if (rank == 0) {
    for (int r = 1; r < size; ++r) displs[r] = displs[r - 1] + counts[r - 1];
    all.resize(static_cast<std::size_t>(displs[size - 1] + counts[size - 1]));
  }
  MPI_Gatherv(mine.data(), n, MPI_CHAR, all.data(), counts.data(), displs.data(), MPI_CHAR, 0, comm);
  if (counts_out) *counts_out = counts;
  return all;
}

dem::MeshWrench sum_over_ranks(MPI_Comm comm, const dem::MeshWrench& mine) {
  double in[6] = {mine.force.x(), mine.force.y(), mine.force.z(), mine.torque.x(), mine.torque.y(), mine.torque.z()};
  double out[6];
  MPI_Allreduce(in, out, 6, MPI_DOUBLE, MPI_SUM, comm);
  dem::MeshWrench w;
  w.force = Eigen::Vector3d(out[0], out[1], out[2]);
  w.torque = Eigen::Vector3d(out[3], out[4], out[5]);
  w.point = mine.point;
  return w;
}

std::string broadcast_bytes(MPI_Comm comm, const std::string& on_root) {
  unsigned long long n = on_root.size();
  MPI_Bcast(&n, 1, MPI_UNSIGNED_LONG_LONG, 0, comm);
  std::string s = rank_of(comm) == 0 ? on_root : std::string(n, '\0');
  for (unsigned long long off = 0; off < n;) {  // in pieces under INT_MAX bytes
    const int piece = static_cast<int>(std::min<unsigned long long>(n - off, 1ull << 30));
    MPI_Bcast(&s[off], piece, MPI_CHAR, 0, comm);
    off += static_cast<unsigned long long>(piece);
  }
  return s;
}

MpiDomain::MpiDomain(MPI_Comm comm, const std::string& checkpoint, const dem::WorldParams& params,
                     const std::function<void(dem::World&)>& setup, double reach)
    : comm_(comm), rank_(rank_of(comm)), size_(size_of(comm)),
      params_(params), setup_(setup), reach_(reach),
      d_(dem::cut_charge(checkpoint, params, setup, size_of(comm), rank_of(comm), reach)),
      out_(static_cast<std::size_t>(size_)), in_(static_cast<std::size_t>(size_)) {}

MpiDomain::MpiDomain(MPI_Comm comm, const dem::WorldParams& params, const std::function<void(dem::World&)>& setup)
    : comm_(comm), rank_(rank_of(comm)), size_(size_of(comm)), params_(params), setup_(setup),
      out_(static_cast<std::size_t>(size_)), in_(static_cast<std::size_t>(size_)) {}

std::string MpiDomain::rank_file(const std::string& prefix, int rank, int ranks) {
  return prefix + ".rank" + std::to_string(rank) + "-of-" + std::to_string(ranks);
}

void MpiDomain::save(const std::string& prefix) {
  std::ostringstream os;
  core::BinaryWriter w(os);
  w.put<double>(reach_);
  w.put<int64_t>(recuts_);
  dem::save_domain(d_, w);
  const std::string err = core::write_file_atomically(rank_file(prefix, rank_, size_), os.str());
  int bad = err.empty() ? 0 : 1, any = 0;
  MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, comm_);
  if (!err.empty()) throw std::runtime_error(err);
  if (any) throw std::runtime_error("MpiDomain::save: another rank could not write its part of " + prefix);
}

MpiDomain MpiDomain::resume(MPI_Comm comm, const std::string& prefix, const dem::WorldParams& params,
                            const std::function<void(dem::World&)>& setup) {
  MpiDomain m(comm, params, setup);
  const std::string path = rank_file(prefix, m.rank_, m.size_);
  std::string err;
  try {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error("cannot open " + path + " (written by a run on another rank count?)");
    core::BinaryReader r(f, path);
    m.reach_ = r.get<double>();
    m.recuts_ = static_cast<int>(r.get<int64_t>());
    m.d_ = dem::load_domain(r, params, setup, m.size_, m.rank_);
  } catch (const std::exception& e) {
    err = e.what();
  }
  int bad = err.empty() ? 0 : 1, any = 0;
  MPI_Allreduce(&bad, &any, 1, MPI_INT, MPI_MAX, comm);
  if (!err.empty()) throw std::runtime_error(err);
  if (any) throw std::runtime_error("MpiDomain::resume: another rank could not read its part of " + prefix);
  return m;
}

double MpiDomain::max_displacement() const {
  double mine = d_.max_displacement(), all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return all;
}

void MpiDomain::exchange() {
  std::vector<MPI_Request> req;
  for (int q = 0; q < size_; ++q) {
    if (d_.plan.recv[q].empty()) continue;
    in_[q].resize(d_.plan.recv[q].size() * dem::kGhostDoubles);
    req.emplace_back();
    MPI_Irecv(in_[q].data(), static_cast<int>(in_[q].size()), MPI_DOUBLE, q, 0, comm_, &req.back());
  }
  for (int q = 0; q < size_; ++q) {
    if (d_.plan.send[q].empty()) continue;
    dem::pack_ghosts(d_.world->particles(), d_.plan.send[q], out_[q]);
    req.emplace_back();
    MPI_Isend(out_[q].data(), static_cast<int>(out_[q].size()), MPI_DOUBLE, q, 0, comm_, &req.back());
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  for (int q = 0; q < size_; ++q)
    if (!d_.plan.recv[q].empty()) dem::unpack_ghosts(d_.world->particles(), d_.plan.recv[q], in_[q].data());
}

void MpiDomain::step(long n) {
  using clk = std::chrono::steady_clock;
  for (long s = 0; s < n; ++s) {
    if (max_displacement() > d_.margin) {
      const auto t0 = clk::now();
      const std::vector<long> mine = dem::owner_counts(d_);
      std::vector<long> counts(mine.size());
      MPI_Allreduce(mine.data(), counts.data(), static_cast<int>(mine.size()), MPI_LONG, MPI_SUM, comm_);
      if (dem::needs_rebalance(counts, rebalance_tolerance_)) {
        recut();
        recut_s_ += std::chrono::duration<double>(clk::now() - t0).count();
      } else {
        migrate();
        migrate_s_ += std::chrono::duration<double>(clk::now() - t0).count();
      }
    }
    d_.world->step_begin();
    const auto t0 = clk::now();
    exchange();
    exchange_s_ += std::chrono::duration<double>(clk::now() - t0).count();
    d_.world->step_end();
  }
}

std::size_t MpiDomain::ghosts() const {
  std::size_t g = 0;
  for (const auto& v : d_.plan.recv) g += v.size();
  return g;
}

// Through rank 0: every rank's World and ownership mask to it, the whole charge assembled and broadcast, each rank
// cuts its new part.
void MpiDomain::edit(const std::function<void(dem::World&)>& edit) { recut(edit); }

void MpiDomain::recut(const std::function<void(dem::World&)>& edit) {
  std::ostringstream os;
  core::BinaryWriter w(os);
  d_.world->save_state(w);
  const std::string mine = os.str();
  std::vector<int> sizes, counts;
  const std::vector<char> world_bytes = gather_bytes(comm_, std::vector<char>(mine.begin(), mine.end()), &sizes);
  const std::vector<char> mask_bytes = gather_bytes(comm_, d_.plan.owned, &counts);
  std::string whole, err;
  if (rank_ == 0) try {
    std::vector<std::unique_ptr<dem::World>> parts;
    std::vector<const dem::World*> views;
    std::vector<std::vector<char>> owned;
    std::size_t at = 0, mat = 0;
    for (int r = 0; r < size_; ++r) {
      std::istringstream is(std::string(world_bytes.begin() + static_cast<long>(at),
                                        world_bytes.begin() + static_cast<long>(at + sizes[r])));
      core::BinaryReader rd(is, "rank " + std::to_string(r) + "'s part");
      parts.push_back(dem::load_world(rd, params_, setup_));
      views.push_back(parts.back().get());
      owned.emplace_back(mask_bytes.begin() + static_cast<long>(mat), mask_bytes.begin() + static_cast<long>(mat + counts[r]));
      at += static_cast<std::size_t>(sizes[r]);
      mat += static_cast<std::size_t>(counts[r]);
    }
    whole = dem::assemble_charge(views, owned, params_, setup_, edit);
  } catch (const std::exception& e) {
    err = e.what();
  }
  err = broadcast_bytes(comm_, err);  // every rank learns of a failure on rank 0 (none waits for the charge)
  if (!err.empty()) throw std::runtime_error("re-cut on rank 0: " + err);
  whole = broadcast_bytes(comm_, whole);
  d_ = dem::cut_charge(whole, params_, setup_, size_, rank_, reach_);
  ++recuts_;
}

// Each rank's World and ownership mask to the peers that need them (dem::migration_peers), point to point; each rank
// cuts its new part from its own and the received parts, in rank order, as LocalDomains does.
void MpiDomain::migrate() {
  const std::vector<char> to = dem::migration_peers(d_, reach_);
  std::string mine;
  if (std::find(to.begin(), to.end(), 1) != to.end()) {
    std::ostringstream os;
    core::BinaryWriter w(os);
    d_.world->save_state(w);
    w.put_vec(d_.plan.owned);
    mine = os.str();
  }
  std::vector<unsigned long long> out(static_cast<std::size_t>(size_), 0), in(static_cast<std::size_t>(size_), 0);
  for (int q = 0; q < size_; ++q) out[q] = to[q] ? mine.size() : 0;
  MPI_Alltoall(out.data(), 1, MPI_UNSIGNED_LONG_LONG, in.data(), 1, MPI_UNSIGNED_LONG_LONG, comm_);
  const unsigned long long limit = static_cast<unsigned long long>(std::numeric_limits<int>::max());
  int too_big = mine.size() > limit ? 1 : 0, any = 0;
  MPI_Allreduce(&too_big, &any, 1, MPI_INT, MPI_MAX, comm_);
  if (any)
    throw std::runtime_error("migration: a rank's part is over 2 GiB (" + std::to_string(mine.size()) +
                             " bytes here); run on more ranks");
  std::vector<std::string> got(static_cast<std::size_t>(size_));
  std::vector<MPI_Request> req;
  for (int q = 0; q < size_; ++q) {
    if (!in[q]) continue;
    got[q].resize(in[q]);
    req.emplace_back();
    MPI_Irecv(&got[q][0], static_cast<int>(in[q]), MPI_CHAR, q, 1, comm_, &req.back());
  }
  for (int q = 0; q < size_; ++q) {
    if (!out[q]) continue;
    req.emplace_back();
    MPI_Isend(mine.data(), static_cast<int>(mine.size()), MPI_CHAR, q, 1, comm_, &req.back());
  }
  MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE);
  std::string err;
  try {
    std::vector<std::unique_ptr<dem::World>> peers;
    std::vector<const dem::World*> parts;
    std::vector<std::vector<char>> owned;
    for (int q = 0; q < size_; ++q) {
      if (q == rank_) {
        parts.push_back(d_.world.get()), owned.push_back(d_.plan.owned);
        continue;
      }
      if (!in[q]) continue;
      std::istringstream is(got[q]);
      core::BinaryReader rd(is, "rank " + std::to_string(q) + "'s part");
      peers.push_back(dem::load_world(rd, params_, setup_));
      owned.emplace_back();
      rd.get_vec(owned.back());
      parts.push_back(peers.back().get());
    }
    d_ = dem::migrate_domain(parts, owned, d_, params_, setup_, reach_);
  } catch (const std::exception& e) {
    err = e.what();
  }
  int bad = err.empty() ? 0 : 1, failed = 0;
  MPI_Allreduce(&bad, &failed, 1, MPI_INT, MPI_MAX, comm_);
  if (!err.empty()) throw std::runtime_error(err);
  if (failed) throw std::runtime_error("migration: another rank failed (its message names why)");
  ++migrations_;
}

void MpiDomain::gather_owned(std::vector<uint64_t>& ids, std::vector<double>& state) const {
  const dem::Particles& p = d_.world->particles();
  std::vector<uint64_t> my_ids;
  std::vector<uint32_t> idx;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (d_.plan.owned[i]) my_ids.push_back(p.id[i]), idx.push_back(static_cast<uint32_t>(i));
  std::vector<double> my_state;
  dem::pack_ghosts(p, idx, my_state);
  const auto all_ids = from_bytes<uint64_t>(gather_bytes(comm_, bytes_of(my_ids)));
  const auto all_state = from_bytes<double>(gather_bytes(comm_, bytes_of(my_state)));
  ids.clear();
  state.clear();
  if (rank_ != 0) return;
  std::vector<std::size_t> order(all_ids.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all_ids[a] < all_ids[b]; });
  for (std::size_t k : order) {
    ids.push_back(all_ids[k]);
    state.insert(state.end(), all_state.begin() + static_cast<long>(k * dem::kGhostDoubles),
                 all_state.begin() + static_cast<long>((k + 1) * dem::kGhostDoubles));
  }
}

std::vector<dem::BondBreak> MpiDomain::gather_breaks() const {
  return from_bytes<dem::BondBreak>(gather_bytes(comm_, bytes_of(dem::owned_breaks(*d_.world, d_.plan))));
}

}  // namespace parallel
