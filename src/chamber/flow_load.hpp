#pragma once
// The flow model as the mechanism's load (run.load flow): at every mechanism step the chamber is pressed at the
// liners' current pose, its wrench is set on both cones (mbd::Mechanism::set_particle_wrench, booked as external
// work), then the mechanism steps. The same explicit force-then-step order as the mechanism's own bed.
#include "chamber/flow_model.hpp"
#include "mbd/mechanism.hpp"

namespace chamber {

class FlowLoad {
 public:
  FlowLoad(const FlowParams& p, const mbd::MechanismParams& m);
  void step(mbd::Mechanism& mech);  // one mechanism step under the chamber's load
  const FlowModel& model() const { return model_; }
  const FlowLoads& last() const { return last_; }
  void save_state(core::BinaryWriter& w) const { model_.save_state(w); }
  void load_state(core::BinaryReader& r) { model_.load_state(r); }

 private:
  FlowModel model_;
  FlowLoads last_;
};

// Product figures over a window [t0, t1] from two snapshots of the model's cumulative discharge.
struct ProductWindow {
  double t0 = 0, t1 = 0;
  std::vector<double> discharged0, discharged1;  // kg per class at t0 and t1
  double energy0 = 0, energy1 = 0;               // crushing energy booked (J)
  double friction0 = 0, friction1 = 0;           // the rock's friction on the liners, work booked (J)
  double extrusion0 = 0, extrusion1 = 0;         // the part of the crushing energy spent at the compaction limit (J)
  double extruded0 = 0, extruded1 = 0;           // discharge pressed out of the bottom nip (kg; FlowModel::extruded_out_kg)
  double extruded_gap0 = 0, extruded_gap1 = 0;   // its kg x gap (kg m)
  double extruded_pct() const;                   // share of the window's discharge pressed out (%; 0 when none left)
  double extruded_gap_m() const;                 // mean gap it left through (m; 0 when none was pressed out)
  double throughput_tph() const;
  double discharged_kg() const;                   // kg discharged in the window
  std::vector<double> by_class() const;           // kg per class discharged in the window
};
ProductWindow snapshot(const FlowModel& m, double t);  // t0 = t1 = t, both snapshots the same
void close_window(ProductWindow& w, const FlowModel& m, double t);

}  // namespace chamber
