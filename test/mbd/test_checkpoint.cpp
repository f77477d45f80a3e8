// Checkpoint / restart of the mechanism (Mechanism::save_state / load_state): a run saved and continued in
// a fresh Mechanism is bit for bit the uninterrupted run; damaged or foreign files are refused by name.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "core/binary_io.hpp"
#include "core/config.hpp"
#include "mbd/mechanism.hpp"
#include "mbd/mechanism_params.hpp"
#include "shipped_mechanism.hpp"

namespace {

mbd::MechanismParams hysteretic() {
  auto p = test_mbd::shipped_mechanism();
  p.bed.law = mbd::BedLaw::Hysteretic;  // the README's alternative bed: its memory decides the force
  p.bed.rebound = 0.14;
  p.bed.viscosity_Pa_s = 0;
  p.vibrator_static_moment_kg_m = 88.5;
  return p;
}

// Every observable of a mechanism, flattened with names, for exact comparison.
struct Observables {
  std::vector<std::string> names;
  std::vector<double> values;
  void add(const std::string& n, double v) { names.push_back(n), values.push_back(v); }
  void add(const std::string& n, const Eigen::Vector3d& v) {
    for (int i = 0; i < 3; ++i) add(n + "[" + std::to_string(i) + "]", v[i]);
  }
};

Observables observe(const mbd::Mechanism& m, bool with_energy = true) {
  Observables o;
  o.add("time", m.time());
  for (int i = 0; i < mbd::kBodyCount; ++i) {
    const auto s = m.body(mbd::BodyId(i));
    const std::string b = mbd::body_name(mbd::BodyId(i));
    o.add(b + ".position", s.position);
    o.add(b + ".q.w", s.orientation.w());
    o.add(b + ".q.xyz", s.orientation.vec());
    o.add(b + ".linear_velocity", s.linear_velocity);
    o.add(b + ".angular_velocity", s.angular_velocity);
    const Eigen::Isometry3d lp = i < 2 ? m.liner_pose(mbd::BodyId(i)) : Eigen::Isometry3d::Identity();
    for (int c = 0; c < 3; ++c) o.add(b + ".R.col" + std::to_string(c), Eigen::Vector3d(lp.linear().col(c)));
  }
  const auto tp = m.test_point();
  o.add("test_point.displacement", tp.displacement);
  o.add("test_point.velocity", tp.velocity);
  o.add("test_point.acceleration", tp.acceleration);
  const auto d = m.drive();
  o.add("drive.speed", d.speed);
  o.add("drive.torque", d.torque);
  o.add("drive.power", d.power);
  o.add("drive.input_power", d.input_power);
  o.add("nutation", m.nutation_angle());
  o.add("mantle_spin", m.mantle_spin());
  o.add("min_gap", m.min_gap());
  o.add("bed_force", m.bed_force());
  o.add("contact_force", m.contact_force());
  o.add("constraint_error", m.constraint_error());
  if (with_energy) {  // energy() runs the contact search: call it on both sides alike
    const auto e = m.energy();
    o.add("energy.drive_work", e.drive_work);
    o.add("energy.absorber_dissipation", e.absorber_dissipation);
    o.add("energy.contact_dissipation", e.contact_dissipation);
    o.add("energy.bed_dissipation", e.bed_dissipation);
    o.add("energy.joint_friction_dissipation", e.joint_friction_dissipation);
    o.add("energy.bushing_friction_dissipation", e.bushing_friction_dissipation);
    o.add("energy.sphere_friction_dissipation", e.sphere_friction_dissipation);
    o.add("energy.motor_input_work", e.motor_input_work);
    o.add("energy.external_work", e.external_work);
    o.add("energy.kinetic", e.kinetic);
    o.add("energy.gravity_potential", e.gravity_potential);
    o.add("energy.elastic_potential", e.elastic_potential);
  }
  return o;
}

// Exact (==) comparison; reports every mismatch (first few by name) and the largest relative difference.
void expect_identical(const Observables& a, const Observables& b, const std::string& what) {
  ASSERT_EQ(a.values.size(), b.values.size());
  int bad = 0;
  double worst = 0;
  std::string first;
  for (std::size_t i = 0; i < a.values.size(); ++i) {
    if (a.values[i] == b.values[i]) continue;
    const double rel = std::abs(a.values[i] - b.values[i]) / std::max(std::abs(a.values[i]), 1e-300);
    worst = std::max(worst, rel);
    if (bad++ < 6)
      first += "\n  " + a.names[i] + ": " + std::to_string(a.values[i]) + " vs " + std::to_string(b.values[i]) +
               " (rel " + std::to_string(rel) + ")";
  }
  EXPECT_EQ(bad, 0) << what << ": " << bad << " of " << a.values.size()
                    << " observables differ, largest relative difference " << worst << first;
}

// Runs `before` seconds (after `setup`), saves, runs `after` seconds more (run A); a fresh Mechanism with the
// same parameters loads the file and runs `after` seconds (run B). `then`, when given, replaces the plain
// `after` seconds on both sides. Returns the checkpoint size (bytes).
std::size_t continuation(const std::string& what, const mbd::MechanismParams& p, mbd::LoadModel load, double before,
                         double after, const std::function<void(mbd::Mechanism&)>& setup = nullptr,
                         const std::function<void(mbd::Mechanism&)>& then = nullptr) {
  mbd::Mechanism a(p, load);
  if (setup) setup(a);
  a.advance(before);
  std::stringstream file;
  {
    core::BinaryWriter w(file);
    a.save_state(w);
  }
  const std::string bytes = file.str();
  const Observables saved = observe(a);
  then ? then(a) : a.advance(after);

  mbd::Mechanism b(p, load);
  {
    core::BinaryReader r(file, "test " + what);
    b.load_state(r);
  }
  EXPECT_EQ(file.peek(), std::char_traits<char>::eof()) << what << ": load_state left bytes unread";
  expect_identical(saved, observe(b), what + ", right after load_state");
  then ? then(b) : b.advance(after);
  expect_identical(observe(a), observe(b), what + ", continued " + std::to_string(after) + " s");
  EXPECT_GT(a.time(), 0.0);
  return bytes.size();
}

TEST(Checkpoint, ContinuationIsBitwiseWithTheViscousBed) {
  const auto p = test_mbd::shipped_mechanism();
  const std::size_t size = continuation("viscous bed", p, mbd::LoadModel::Bed, 1.5, 1.0);
  std::printf("checkpoint size (viscous bed, %d x %d bed patches): %zu bytes\n", p.sampling.azimuth,
              p.sampling.generator, size);
  EXPECT_LT(size, 8000u);
}

TEST(Checkpoint, ContinuationIsBitwiseWithTheHystereticBed) {
  continuation("hysteretic bed", hysteretic(), mbd::LoadModel::Bed, 1.5, 1.0);
}

TEST(Checkpoint, ContinuationIsBitwiseWithEffectsEnabled) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.motor_droop.enabled = true;  // drive torque from the speed-torque line
  p.effects.motor_droop.droop_rad_s_per_Nm = 0.5e-3;
  p.effects.absorber_nonlinearity.enabled = true;  // cubic stiffness + hysteresis loss
  p.effects.absorber_nonlinearity.cubic_N_per_m3 = 2e10;
  p.effects.absorber_nonlinearity.hysteresis = 0.3;
  p.effects.joint_friction.enabled = true;
  p.effects.joint_friction.coulomb_Nm = 300;
  p.effects.joint_friction.viscous_Nms = 5;
  p.effects.cardan_misalignment.enabled = true;
  p.effects.cardan_misalignment.angle_rad = 2.0 * M_PI / 180;
  continuation("effects", p, mbd::LoadModel::Bed, 1.5, 1.0);
}

// The bearing friction acts with the joints' reactions of the previous step (state the checkpoint keeps) and the
// drive efficiency integrates the motor's input: both written in their own block.
TEST(Checkpoint, ContinuationIsBitwiseWithBearingFrictionAndDriveEfficiency) {
  auto p = test_mbd::shipped_mechanism();
  p.effects.bearing_friction.enabled = true;
  p.effects.bearing_friction.mu = 0.03;
  p.effects.drive_efficiency.enabled = true;
  p.effects.drive_efficiency.efficiency = 0.9;
  p.effects.drive_efficiency.no_load_W = 3e3;
  continuation("bearing friction and drive efficiency", p, mbd::LoadModel::Bed, 1.5, 1.0);
}

TEST(Checkpoint, ContinuationIsBitwiseWithHeldParticleWrenches) {
  // LoadModel::None as in a DEM-coupled run: the held wrenches are the load (and the cones come into contact).
  const auto p = test_mbd::shipped_mechanism();
  continuation("particle wrenches", p, mbd::LoadModel::None, 1.5, 1.0, [](mbd::Mechanism& m) {
    m.set_particle_wrench(mbd::BodyId::FixedCone, {2e4, -5e3, 1e4}, {1e3, 2e3, -5e2});
    m.set_particle_wrench(mbd::BodyId::FloatingCone, {-3e4, 1e4, -2e4}, {-2e3, 0, 1e3});
    m.set_particle_wrench(mbd::BodyId::Vibrator, {0, 0, -1e3}, {0, 0, 0});
  });
}

TEST(Checkpoint, ContinuationIsBitwiseAfterAWarmStart) {
  // Saved inside the drive ramp (0.6 s warm start + 0.3 s): the warm start's t_before sets the ramp.
  continuation("after warm start", hysteretic(), mbd::LoadModel::Bed, 0.3, 1.0,
               [](mbd::Mechanism& m) { m.warm_start(0.6, mbd::LoadModel::Bed); });
  // Idle after a warm start with the bed: the two bed-memory buffers swap every idle step (the idle step
  // writes neither), so the memory the bed finds when it comes back is the one the parity selects: both
  // buffers are state.
  continuation("idle after a warm start with the bed", hysteretic(), mbd::LoadModel::None, 0.5, 1.0,
               [](mbd::Mechanism& m) { m.warm_start(1.2, mbd::LoadModel::Bed); },
               [](mbd::Mechanism& m) {
                 m.advance(0.101);  // odd number of idle steps
                 m.set_load_model(mbd::LoadModel::Bed);
                 m.advance(0.9);
               });
}

TEST(Checkpoint, SaveStateChangesNothing) {
  const auto p = hysteretic();
  mbd::Mechanism a(p, mbd::LoadModel::Bed), b(p, mbd::LoadModel::Bed);
  a.advance(1.2);
  b.advance(1.2);
  std::stringstream s1, s2;
  core::BinaryWriter w1(s1), w2(s2);
  a.save_state(w1);
  a.save_state(w2);
  EXPECT_EQ(s1.str(), s2.str());
  a.advance(0.5);
  b.advance(0.5);
  expect_identical(observe(a), observe(b), "saved vs not saved");
}

// ---- refused files ----

std::string saved(const mbd::MechanismParams& p, mbd::LoadModel load, double seconds = 0.2) {
  mbd::Mechanism m(p, load);
  m.advance(seconds);
  std::stringstream s;
  core::BinaryWriter w(s);
  m.save_state(w);
  return s.str();
}

// load_state of `bytes` into a fresh Mechanism must throw std::runtime_error with `needle` in the message,
// and leave the Mechanism as it was.
void expect_refused(const std::string& bytes, const mbd::MechanismParams& p, mbd::LoadModel load,
                    const std::string& needle) {
  mbd::Mechanism m(p, load);
  m.advance(0.05);
  const Observables before = observe(m, false);
  std::stringstream s(bytes);
  core::BinaryReader r(s, "ckpt.bin");
  try {
    m.load_state(r);
    ADD_FAILURE() << "no error, expected one naming '" << needle << "'";
  } catch (const std::runtime_error& e) {
    const std::string msg = e.what();
    std::printf("refused: %s\n", msg.c_str());
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    EXPECT_NE(msg.find("ckpt.bin"), std::string::npos) << msg;
  }
  expect_identical(before, observe(m, false), "mechanism after a refused load");
}

TEST(Checkpoint, TruncatedFileRefused) {
  const auto p = test_mbd::shipped_mechanism();
  const std::string full = saved(p, mbd::LoadModel::Bed);
  for (std::size_t keep : {std::size_t(0), std::size_t(3), full.size() / 2, full.size() - 1})
    expect_refused(full.substr(0, keep), p, mbd::LoadModel::Bed, "truncated");
}

TEST(Checkpoint, WrongTagRefused) {
  const auto p = test_mbd::shipped_mechanism();
  std::string bytes = saved(p, mbd::LoadModel::Bed);
  std::string other = bytes;
  std::memcpy(&other[0], "WRLD", 4);  // e.g. a DEM checkpoint
  expect_refused(other, p, mbd::LoadModel::Bed, "expected block 'MECH', found 'WRLD'");
  const std::size_t at = bytes.find("BEDS");
  ASSERT_NE(at, std::string::npos);
  bytes[at + 1] = 'X';
  expect_refused(bytes, p, mbd::LoadModel::Bed, "expected block 'BEDS'");
}

TEST(Checkpoint, OtherLoadModelRefused) {
  const auto p = test_mbd::shipped_mechanism();
  expect_refused(saved(p, mbd::LoadModel::Bed), p, mbd::LoadModel::None,
                 "saved with load model 'bed', this mechanism has 'none'");
  expect_refused(saved(p, mbd::LoadModel::None), p, mbd::LoadModel::Bed,
                 "saved with load model 'none', this mechanism has 'bed'");
}

TEST(Checkpoint, OtherBodyCountVersionOrParametersRefused) {
  const auto p = test_mbd::shipped_mechanism();
  const std::string bytes = saved(p, mbd::LoadModel::Bed);
  std::string b = bytes;
  const uint32_t seven = 7, nine = 9;
  std::memcpy(&b[8], &seven, 4);  // after "MECH" and the format version
  expect_refused(b, p, mbd::LoadModel::Bed, "body count 7, this mechanism has 6");
  b = bytes;
  std::memcpy(&b[4], &nine, 4);
  expect_refused(b, p, mbd::LoadModel::Bed, "format version 9");
  auto q = p;
  q.bed.modulus_Pa *= 1.5;
  expect_refused(bytes, q, mbd::LoadModel::Bed, "other mechanism parameters (under 'bed:'");
  q = p;
  q.dt_s *= 0.5;
  expect_refused(bytes, q, mbd::LoadModel::Bed, "time step");
}

}  // namespace
