#include "rocks/calibration.hpp"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

#include "core/units.hpp"

namespace rocks {

using namespace core::units;

CalibrationConfig CalibrationConfig::load(const std::string& file) {
  const auto root = core::ConfigNode::load_file(file);
  const auto c = root.child("calibration");
  CalibrationConfig k;
  const auto sp = c.child("specimen");
  k.diameter = sp.number("diameter_mm", 5.0, 500.0, "mm", mm);
  k.length = sp.number("length_mm", 2.0, 500.0, "mm", mm);
  const auto mp = c.child("metaparticles");
  k.base.metaparticles = SizeDistribution::from_config(mp);
  YAML::Emitter e;
  e << YAML::Flow << mp.raw();
  k.base.metaparticles_yaml = e.c_str();
  k.base.packing = packing_from_config(c.child("packing"));
  const auto b = c.child("bond");
  k.stiffness_ratio = b.number("stiffness_ratio", 0.5, 10.0, "");
  k.base.bond.reference_radius = b.number("reference_radius_mm", 0.05, 100.0, "mm", mm);
  k.base.bond.damping = b.number_or("damping", 0.0, 0.0, 1.0, "");
  const auto t = c.child("test");
  k.test.closing_speed = t.number("closing_speed_mm_s", 1.0, 5000.0, "mm/s", mm_per_s);
  k.test.dt = t.number_or("dt_s", 0.0, 0.0, 1e-3, "s");
  k.test.dt_safety = t.number_or("dt_safety", 0.8, 0.05, 1.0, "");
  k.test.max_compression_ratio = t.number("max_compression_ratio", 0.001, 0.3, "");
  k.test.record_every = t.integer_or("record_every", 100, 1, 100000);
  const auto g = c.child("target");
  k.target_force = g.number("critical_force_kN", 0.01, 1e4, "kN", kN);
  const auto lv = c.child("levels");
  k.normal_strength = lv.numbers("normal_strength_MPa", 0.01, 1e4, "MPa", MPa, 4);
  k.shear_strength = lv.numbers("shear_strength_MPa", 0.01, 1e4, "MPa", MPa, 4);
  k.shear_stiffness = lv.numbers("shear_stiffness_GPa_per_m", 1.0, 1e5, "GPa/m", GPa_per_m, 4);
  k.disk_radius = lv.numbers("bond_disk_radius_mm", 0.01, 100.0, "mm", mm, 4);
  const auto r = c.child("refine");
  k.tolerance = r.number("tolerance", 0.001, 0.5, "");
  k.max_refinements = r.integer("max_iterations", 0, 20);
  const auto s = c.child("single_particle");
  k.single_particle = s.boolean("enabled");
  k.rock_sizes = s.numbers("sizes_mm", 5.0, 500.0, "mm", mm, 4);
  k.rock_seed = static_cast<unsigned long long>(s.integer("seed", 0, 2000000000L));
  root.finish();
  return k;
}

BondSettings doe_settings(const CalibrationConfig& c, int row) {
  const auto& a = l16_array();
  if (row < 0 || row >= static_cast<int>(a.size())) throw std::invalid_argument("doe_settings: row out of range");
  BondSettings s = c.base.bond;
  const auto& lv = a[row];
  s.sigma_c = c.normal_strength.at(lv[0] - 1);  // column 1
  s.tau_c = c.shear_strength.at(lv[1] - 1);     // column 2 (column 3: error)
  s.kt = c.shear_stiffness.at(lv[3] - 1);       // column 4
  s.kn = c.stiffness_ratio * s.kt;              // k_bn / k_bt = 2.5 (section 2.4.3)
  s.disk_radius = c.disk_radius.at(lv[4] - 1);  // column 5
  return s;
}

void run_parallel(int n, int threads, const std::function<void(int)>& job, const std::function<void(int)>& done) {
  std::atomic<int> next{0};
  std::mutex m;
  std::exception_ptr err;
  auto worker = [&]() {
    for (;;) {
      const int i = next.fetch_add(1);
      if (i >= n) return;
      try {
        job(i);
        std::lock_guard<std::mutex> lock(m);
        done(i);
      } catch (...) {
        std::lock_guard<std::mutex> lock(m);
        if (!err) err = std::current_exception();
        next = n;
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 0; t < std::max(1, threads); ++t) pool.emplace_back(worker);
  for (auto& t : pool) t.join();
  if (err) std::rethrow_exception(err);
}

SingleParticleRock single_particle_rock(const CalibrationConfig& c, const BpmModel& m, int k) {
  if (k < 0 || k >= static_cast<int>(c.rock_sizes.size()))
    throw std::invalid_argument("single_particle_rock: rock index " + std::to_string(k) + " out of range");
  SingleParticleRock r;
  r.shape = make_irregular_rock(c.rock_seed + k, c.rock_sizes[k], 22, "rock" + std::to_string(k + 1));
  PackingOptions po = m.packing;
  po.seed = m.packing.seed + 100 + k;
  for (;;) {  // coarse metaparticles in a small rock may not reach the disk's density
    try {
      r.packing = pack_shape(*r.shape, m.metaparticles, po);
      return r;
    } catch (const std::runtime_error&) {
      if (po.density < 0.46) throw;
      po.density -= 0.03;
    }
  }
}

PlatenTestOptions single_particle_options(const CalibrationConfig& c) {
  PlatenTestOptions o = c.test;
  o.load_axis = 2;  // along the shortest axis, as a rock lies on a platen
  o.max_compression_ratio = std::max(o.max_compression_ratio, 0.15);  // irregular rocks crush late
  return o;
}

std::vector<int> taguchi_optimum(const std::vector<std::vector<double>>& means_fcd) {
  std::vector<int> best;
  for (const auto& col : means_fcd)
    best.push_back(static_cast<int>(std::min_element(col.begin(), col.end()) - col.begin()) + 1);
  return best;
}

}  // namespace rocks
