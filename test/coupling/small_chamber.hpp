#pragma once
// The coupling tests' chamber: a 1:4 model of the GYP1200's fed with 30 mm rocks of ~4 mm metaparticles
// (bonds a tenth of Table 4's stiffness for a 3x longer stable step, Table 4 strengths), and a mantle that
// gyrates with its axis tilted and precessing at 10 Hz about the crusher axis.
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "coupling/chamber_dem.hpp"
#include "mbd/mechanism_params.hpp"

namespace test_chamber {

// Density of particle i's sphere (kg/m^3): its mass over its volume.
inline double sphere_density(const dem::Particles& P, std::size_t i) {
  return P.m[i] / (4.0 / 3.0 * M_PI * std::pow(P.r[i], 3));
}

inline coupling::ChamberParams small_chamber() {
  coupling::ChamberParams p;
  p.chamber.mantle.z = {-0.05, -0.20};
  p.chamber.mantle.r = {0.045, 0.150};
  p.chamber.concave.z = {-0.02, -0.21};
  p.chamber.concave.r = {0.080, 0.175};
  p.mantle_com_z_m = -0.30;
  p.concave_com_z_m = -0.10;
  p.liner_sectors = 36;
  p.threads = 1;
  p.feed.rock_size_m = 0.03;
  p.bpm.metaparticles = rocks::SizeDistribution({{4e-3, 0.4e-3, 1.0}});
  p.feed.choke_height_m = 0.03;
  p.bpm.packing.density = 0.45;  // few coarse spheres per rock cannot reach 0.6 without overlap
  p.feed.max_fed_kg = 0.6;
  p.feed.drop_speed_m_s = 3.0;
  p.bpm.bond.kn = 40e9;
  p.bpm.bond.kt = 16e9;
  p.bpm.bond.sigma_c = 25e6;
  p.bpm.bond.tau_c = 9e6;
  p.bpm.bond.disk_radius = 3.2e-3;  // 0.8 x the 4 mm metaparticle radius
  p.bpm.bond.reference_radius = 4e-3;
  p.discharge_below_m = 0.02;
  return p;
}

// The small chamber on 2 threads, pre-filled with up to prefill_kg of rock (rock in contact with the liners from
// the first step) and choke-fed up to max_fed_kg in all.
inline coupling::ChamberParams prefilled_small_chamber(double prefill_kg, double max_fed_kg) {
  auto p = small_chamber();
  p.threads = 2;
  p.feed.prefill = true;
  p.feed.prefill_max_kg = prefill_kg;
  p.feed.max_fed_kg = max_fed_kg;
  return p;
}

// The small chamber on 1 thread with everything a coupled run does between steps at once: choke feed, bonds breaking
// (a tenth of Table 4's strengths), metaparticles crushed into growing fragments (tensile strength 0.5 MPa:
// F_c(8 mm) = 36 N, the gyration crushes many) and discharge. The decomposition tests' chamber.
inline coupling::ChamberParams busy_small_chamber() {
  auto p = prefilled_small_chamber(0.4, 0.8);
  p.threads = 1;
  p.feed.max_rate_kg_s = 4.0;
  p.bpm.bond.sigma_c = 2.5e6;
  p.bpm.bond.tau_c = 0.9e6;
  p.crushing.enabled = true;
  p.crushing.fragments = true;
  p.crushing.fragment_growth_s = 5e-3;
  p.crushing.tensile_strength = 0.5e6;
  p.crushing.min_fragment_m = 4e-3;
  p.crushing.batch_s = 2e-4;
  return p;
}

// The mantle's motion at time t: axis tilted by `tilt` (rad), precessing at 10 Hz; the liner COM on the axis.
inline void gyrate(const coupling::ChamberParams& p, double t, double tilt, coupling::BodyMotion* m) {
  const double w = 2 * M_PI * 10;
  Eigen::Vector3d axis(std::sin(tilt) * std::cos(w * t), std::sin(tilt) * std::sin(w * t), std::cos(tilt));
  m->orientation = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis);
  Eigen::Vector3d axis_dot(-std::sin(tilt) * w * std::sin(w * t), std::sin(tilt) * w * std::cos(w * t), 0);
  m->angular_velocity = axis.cross(axis_dot);
  m->com = m->orientation * Eigen::Vector3d(0, 0, p.mantle_com_z_m);
  m->velocity = m->angular_velocity.cross(m->com);
}

// Coupling steps from..to of 1 ms: the mantle gyrates 2 degrees at 10 Hz, the concave rests; each step's mantle and
// concave force and torque (12 values) appended to wrench.
inline void gyrate_steps(coupling::ChamberDem& d, const coupling::ChamberParams& p, int from, int to,
                         std::vector<double>* wrench) {
  coupling::BodyMotion m, c;
  c.com = Eigen::Vector3d(0, 0, p.concave_com_z_m);
  for (int k = from; k < to; ++k) {
    gyrate(p, k * 1e-3, 2.0 * M_PI / 180, &m);
    auto [wm, wc] = d.advance(m, c, 1e-3);
    for (const auto* v : {&wm.force, &wm.torque, &wc.force, &wc.torque}) wrench->insert(wrench->end(), v->data(), v->data() + 3);
  }
}

// launch_free_configs/quick_demo.yaml as text.
inline std::string quick_demo_text() {
  std::ifstream in(std::string(CRUSHER_SOURCE_DIR) + "/launch_free_configs/quick_demo.yaml");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The chamber parameters of a run config given as text (the liner profiles and COM heights from its mbd section).
inline coupling::ChamberParams chamber_params_of(const std::string& text) {
  auto root = core::ConfigNode::load_string(text, "quick_demo+test");
  const auto mech = mbd::load_mechanism_params(root.child("mbd"));
  const auto flow = root.child_or_empty("flow");
  return coupling::load_chamber_params(root.child("dem"), mech.chamber, mech.floating_cone.com_z_m,
                                       mech.fixed_cone.com_z_m, &flow);
}

// The quick demo's chamber parameters with `extra` (YAML lines) inserted before the line `before` (which must be
// in the file).
inline coupling::ChamberParams quick_demo_with(const std::string& extra, const std::string& before) {
  std::string text = quick_demo_text();
  const auto at = text.find(before);
  if (at == std::string::npos) throw std::logic_error("quick_demo.yaml has no line '" + before + "'");
  text.insert(at, extra);
  return chamber_params_of(text);
}

}  // namespace test_chamber
