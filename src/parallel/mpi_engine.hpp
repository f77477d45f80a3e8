#pragma once
// dem::DomainEngine over MPI (issue 25): one rank's part of the decomposed charge (MpiDomain) behind the interface a
// coupled chamber steps and edits (coupling::ChamberDem::decompose), with the reductions, gather and broadcast it
// needs. Rank 0 is the root: edits run there.
#include <mpi.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dem/domain_engine.hpp"
#include "parallel/mpi_domain.hpp"

namespace parallel {

class MpiEngine : public dem::DomainEngine {
 public:
  // Collective: every rank cuts its part from rank 0's checkpoint (broadcast).
  MpiEngine(MPI_Comm comm, const std::string& checkpoint, const dem::WorldParams& params,
            const std::function<void(dem::World&)>& setup, double reach);
  int parts() const override { return 1; }
  dem::World& part(int) override { return d_.world(); }
  const std::vector<char>* owned(int) const override { return &d_.plan().owned; }
  void step() override { d_.step(1); }
  void edit(const std::function<void(dem::World&)>& fn) override { d_.edit(fn); }
  bool root() const override { return d_.rank() == 0; }
  void sum(std::vector<double>& v) override;
  double min(double x) override;
  double max(double x) override;
  std::string gather(const std::string& mine) override;
  std::string broadcast(const std::string& on_root) override { return broadcast_bytes(comm_, on_root); }
  int recuts() const override { return d_.recuts(); }
  int migrations() const override { return d_.migrations(); }
  const MpiDomain& domain() const { return d_; }
  void set_rebalance_tolerance(double t) { d_.set_rebalance_tolerance(t); }

 private:
  MPI_Comm comm_;
  MpiDomain d_;
};

// The factory coupling::ChamberDem::decompose takes: an MpiEngine on comm with the given reach (m) and rebalance
// tolerance (dem::LocalDomains::set_rebalance_tolerance).
dem::EngineFactory mpi_engine(MPI_Comm comm, double reach, double rebalance_tolerance = dem::kRebalanceTolerance);

}  // namespace parallel
