#pragma once
// What a caller that steps a charge and edits it between steps (coupling::ChamberDem) needs from the DEM, whether the
// charge is one World or the ranks' parts of an azimuthal decomposition (ghost_domains.hpp), in this process or
// across processes (parallel::MpiEngine). ROS-free, MPI-free.
//
// A process steps parts() Worlds. Each holds owned particles and ghosts (owned(k); null: every particle is owned); a
// liner's wrench or a region's force is the sum over the parts' owned shares and, with several processes, over the
// processes (sum). Particles are added or removed only through edit(), which hands the whole charge, in one World,
// to fn on the root process and cuts it anew: the parts' Worlds may be replaced by edit() and by step() (a re-cut
// once a particle has left the layout's margin), so a caller re-reads part(k) after each.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "dem/ghost_domains.hpp"
#include "dem/world.hpp"

namespace dem {

class DomainEngine {
 public:
  virtual ~DomainEngine() = default;
  virtual int parts() const = 0;
  virtual World& part(int k) = 0;
  virtual const std::vector<char>* owned(int k) const = 0;  // per particle of part(k): 1 owned; null: all owned
  virtual void step() = 0;                                  // one step of the whole charge (collective)
  // Collective, between two steps: fn changes the whole charge in one World on the root process.
  virtual void edit(const std::function<void(World&)>& fn) = 0;
  virtual bool root() const = 0;  // this process runs edit()'s fn
  // Collective reductions over the processes (identity in one process): element-wise sum in place, in rank order
  // (((v0 + v1) + v2) ..., as a caller sums its parts, so that P ranks in one process and P processes agree bit for
  // bit), minimum, maximum.
  virtual void sum(std::vector<double>& v) = 0;
  virtual double min(double x) = 0;
  virtual double max(double x) = 0;
  // Collective: every process's bytes, concatenated in rank order, on the root (empty elsewhere); the root's bytes on
  // every process.
  virtual std::string gather(const std::string& mine) = 0;
  virtual std::string broadcast(const std::string& on_root) = 0;
  virtual int recuts() const = 0;  // how often the charge was cut anew (rebalanced, or edited)
  virtual int migrations() const { return 0; }  // how often the particles migrated, the sectors kept
};

// The reductions of one process: identities.
class OneProcessEngine : public DomainEngine {
 public:
  bool root() const override { return true; }
  void sum(std::vector<double>&) override {}
  double min(double x) override { return x; }
  double max(double x) override { return x; }
  std::string gather(const std::string& mine) override { return mine; }
  std::string broadcast(const std::string& on_root) override { return on_root; }
};

// The whole charge in one World (not owned): step() is World::step(1), edit(fn) is fn(world).
class WholeEngine : public OneProcessEngine {
 public:
  explicit WholeEngine(World& w) : w_(w) {}
  int parts() const override { return 1; }
  World& part(int) override { return w_; }
  const std::vector<char>* owned(int) const override { return nullptr; }
  void step() override { w_.step(1); }
  void edit(const std::function<void(World&)>& fn) override { fn(w_); }
  int recuts() const override { return 0; }

 private:
  World& w_;
};

// Every rank of a decomposition in this process (LocalDomains): what a run on that many MPI ranks computes, bit for bit.
class LocalEngine : public OneProcessEngine {
 public:
  LocalEngine(const std::string& checkpoint, const WorldParams& params, const std::function<void(World&)>& setup,
              int ranks, double reach)
      : d_(checkpoint, params, setup, ranks, reach) {}
  int parts() const override { return d_.ranks(); }
  World& part(int k) override { return d_.world(k); }
  const std::vector<char>* owned(int k) const override { return &d_.plan(k).owned; }
  void step() override { d_.step(1); }
  void edit(const std::function<void(World&)>& fn) override { d_.edit(fn); }
  int recuts() const override { return d_.recuts(); }
  int migrations() const override { return d_.migrations(); }
  const LocalDomains& domains() const { return d_; }

 private:
  LocalDomains d_;
};

// Makes the engine of a decomposed charge from the whole charge's checkpoint (World::save_state), the World's
// parameters and the setup that adds its walls and interactions to a new World (as cut_charge takes them).
using EngineFactory = std::function<std::unique_ptr<DomainEngine>(
    const std::string& checkpoint, const WorldParams& params, const std::function<void(World&)>& setup)>;

}  // namespace dem
