#pragma once
// Test flow-model parameters shared by the chamber tests: a grid of bands x sectors, no choke feed, prefill as asked;
// a mantle pushed aside with the liners' work summed; a model resumed through a checkpoint.
#include <initializer_list>
#include <memory>
#include <sstream>

#include "chamber/flow_model.hpp"
#include "coaxial_liners.hpp"
#include "core/binary_io.hpp"

namespace test_liners {

inline chamber::FlowParams flow_params(int bands, int sectors, bool prefill = false) {
  chamber::FlowParams p;
  p.bands = bands;
  p.sectors = sectors;
  p.prefill = prefill;
  p.choke_feed = false;
  return p;
}

// Coaxial liners at rest, the mantle of m pushed along -x (one still step of 1 ms per position, no gravity) and the
// liners' work on the rock summed by the trapezoid rule: -(force on the mantle) . d(-x).
struct PushAlongX {
  chamber::FlowModel& m;
  Eigen::Vector3d com_m, com_c;
  double work = 0, x_prev = 0, f_prev = 0;
  void to(double x) {
    const auto L = m.step(shifted({-x, 0, 0}), Eigen::Isometry3d::Identity(), com_m, com_c, 1e-3, 0.0);
    work += 0.5 * (L.f_mantle.x() + f_prev) * (x - x_prev);
    x_prev = x, f_prev = L.f_mantle.x();
  }
};

// A model of p on the given liners that continues from m's state, through a checkpoint stream.
inline std::unique_ptr<chamber::FlowModel> resumed(const chamber::FlowModel& m, const chamber::FlowParams& p,
                                                   const core::Profile& mantle, const core::Profile& concave) {
  std::stringstream file;
  core::BinaryWriter w(file);
  m.save_state(w);
  auto copy = std::make_unique<chamber::FlowModel>(p, mantle, concave);
  core::BinaryReader r(file, "flow test checkpoint");
  copy->load_state(r);
  return copy;
}

// The cone chamber (gyp_mantle, gyp_concave) the long-run tests use: 20 bands x 12 sectors, choke fed and prefilled,
// the default material.
inline chamber::FlowParams cone_chamber_params() {
  chamber::FlowParams p;
  p.bands = 20;
  p.sectors = 12;
  return p;
}

// Steps each of the models (in this order, every step) on the cone chamber's nutating mantle (nutating(t), the concave
// at rest, centres of mass at z -0.5 and -0.6 m) from step `from` to step `to`, steps of h.
inline void nutate(std::initializer_list<chamber::FlowModel*> models, int from, int to, double h = 1e-3) {
  const Eigen::Vector3d com_m(0, 0, -0.5), com_c(0, 0, -0.6);
  for (int i = from; i < to; ++i)
    for (chamber::FlowModel* m : models) m->step(nutating(i * h), Eigen::Isometry3d::Identity(), com_m, com_c, h, 9.81);
}

}  // namespace test_liners
