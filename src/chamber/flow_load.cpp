#include "chamber/flow_load.hpp"

#include <numeric>

namespace chamber {

FlowLoad::FlowLoad(const FlowParams& p, const mbd::MechanismParams& m)
    : model_(p, m.chamber.mantle, m.chamber.concave) {}

void FlowLoad::step(mbd::Mechanism& mech) {
  using mbd::BodyId;
  const auto M = mech.body(BodyId::FloatingCone), C = mech.body(BodyId::FixedCone);
  LinerTwists tw;
  tw.v_mantle = M.linear_velocity, tw.w_mantle = M.angular_velocity;
  tw.v_concave = C.linear_velocity, tw.w_concave = C.angular_velocity;
  last_ = model_.step(mech.liner_pose(BodyId::FloatingCone), mech.liner_pose(BodyId::FixedCone), M.position,
                      C.position, mech.dt(), mech.params().gravity_m_s2, &tw);
  mech.set_particle_wrench(BodyId::FloatingCone, last_.f_mantle, last_.t_mantle);
  mech.set_particle_wrench(BodyId::FixedCone, last_.f_concave, last_.t_concave);
  mech.step();
}

double ProductWindow::discharged_kg() const {
  const auto c = by_class();
  return std::accumulate(c.begin(), c.end(), 0.0);
}

double ProductWindow::throughput_tph() const { return t1 > t0 ? discharged_kg() / (t1 - t0) * 3.6 : 0.0; }

double ProductWindow::extruded_pct() const {
  const double kg = discharged_kg();
  return kg > 0 ? 100.0 * (extruded1 - extruded0) / kg : 0.0;
}

double ProductWindow::extruded_gap_m() const {
  const double kg = extruded1 - extruded0;
  return kg > 0 ? (extruded_gap1 - extruded_gap0) / kg : 0.0;
}

std::vector<double> ProductWindow::by_class() const {
  std::vector<double> c(discharged1.size());
  for (std::size_t j = 0; j < c.size(); ++j) c[j] = discharged1[j] - discharged0[j];
  return c;
}

ProductWindow snapshot(const FlowModel& m, double t) {
  ProductWindow w;
  w.t0 = w.t1 = t;
  w.discharged0 = w.discharged1 = m.discharged_by_class();
  w.energy0 = w.energy1 = m.crushing_energy_J();
  w.friction0 = w.friction1 = m.friction_energy_J();
  w.extrusion0 = w.extrusion1 = m.extrusion_energy_J();
  w.extruded0 = w.extruded1 = m.extruded_out_kg();
  w.extruded_gap0 = w.extruded_gap1 = m.extruded_out_gap_kg_m();
  return w;
}

void close_window(ProductWindow& w, const FlowModel& m, double t) {
  w.t1 = t;
  w.discharged1 = m.discharged_by_class();
  w.energy1 = m.crushing_energy_J();
  w.friction1 = m.friction_energy_J();
  w.extrusion1 = m.extrusion_energy_J();
  w.extruded1 = m.extruded_out_kg();
  w.extruded_gap1 = m.extruded_out_gap_kg_m();
}

}  // namespace chamber
