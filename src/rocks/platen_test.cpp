#include "rocks/platen_test.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "dem/time_step.hpp"
#include "dem/world.hpp"

namespace rocks {

double brazilian_tensile_strength(double critical_force, double diameter, double length) {
  if (!(diameter > 0.0) || !(length > 0.0)) throw std::invalid_argument("brazilian_tensile_strength: D, L > 0");
  return 2.0 * critical_force / (M_PI * diameter * length);  // Eq. 26
}

PlatenTestResult run_platen_test(const RockPacking& rock, const dem::BondParams& bp, const PlatenTestOptions& o) {
  if (rock.size() == 0) throw std::invalid_argument("run_platen_test: empty rock");
  if (!(o.closing_speed > 0.0 && o.closing_speed <= 10.0))
    throw std::invalid_argument("run_platen_test: closing_speed must be in (0, 10] m/s");
  if (!(o.max_compression_ratio > 0.0 && o.max_compression_ratio < 0.5))
    throw std::invalid_argument("run_platen_test: max_compression_ratio must be in (0, 0.5)");
  if (o.load_axis < 0 || o.load_axis > 2) throw std::invalid_argument("run_platen_test: load_axis must be 0, 1 or 2");
  if (o.record_every < 1) throw std::invalid_argument("run_platen_test: record_every must be >= 1");
  if (!(o.max_overlap_fraction > 0.0 && o.max_overlap_fraction <= 1.0))
    throw std::invalid_argument("run_platen_test: max_overlap_fraction must be in (0, 1]");
  bp.validate();
  const auto t0 = std::chrono::steady_clock::now();
  dem::WorldParams wp;
  wp.gravity = {0.0, 0.0, 0.0};  // 2.6 N of weight against kN of load: left out
  wp.threads = o.threads;
  wp.materials = o.materials;
  wp.max_overlap_fraction = o.max_overlap_fraction;
  wp.blowup_dump_path = o.blowup_dump_path;
  wp.dt = 1e-7;  // replaced below once the particles and bonds exist
  dem::World world(wp);
  const int rock_mat = 0, steel_mat = 1;
  const int ax = o.load_axis;
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i < rock.size(); ++i) {
    const double x[3] = {rock.positions[i].x(), rock.positions[i].y(), rock.positions[i].z()};
    world.add_particle(x, rock.radii[i], rock_mat);
    lo = std::min(lo, x[ax] - rock.radii[i]);
    hi = std::max(hi, x[ax] + rock.radii[i]);
  }
  std::vector<std::pair<std::size_t, std::size_t>> pairs(rock.bonds.begin(), rock.bonds.end());
  PlatenTestResult res;
  res.bonds_initial = world.bond_pairs(pairs, bp);
  res.height = hi - lo;
  double pb[3] = {0, 0, 0}, pt[3] = {0, 0, 0}, nb[3] = {0, 0, 0}, nt[3] = {0, 0, 0};
  pb[ax] = lo;
  pt[ax] = hi;
  nb[ax] = 1.0;
  nt[ax] = -1.0;
  const int wb = world.add_plane(pb, nb, steel_mat);
  const int wt = world.add_plane(pt, nt, steel_mat);
  double vb[3] = {0, 0, 0}, vt[3] = {0, 0, 0};
  vb[ax] = 0.5 * o.closing_speed;
  vt[ax] = -0.5 * o.closing_speed;
  world.set_wall_velocity(wb, vb);
  world.set_wall_velocity(wt, vt);

  const dem::TimeStepCheck c = world.time_step_check();
  res.dt = o.dt > 0.0 ? o.dt : o.dt_safety * std::min(0.3 * c.rayleigh, c.bond);
  world.set_dt(res.dt);
  world.require_stable_time_step();

  const double max_closure = o.max_compression_ratio * res.height;
  if (o.verbose)
    std::fprintf(stderr, "  platen test: %zu particles, %zu bonds, dt %.3g s (Rayleigh %.3g s, bond %.3g s)\n",
                 rock.size(), res.bonds_initial, res.dt, c.rayleigh, c.bond);
  const long max_steps = static_cast<long>(std::ceil(max_closure / (o.closing_speed * res.dt)));
  double fsum = 0.0;
  int nsum = 0;
  long step = 0;
  double next_report = 5.0;
  while (step < max_steps) {
    world.step(1);
    ++step;
    fsum += 0.5 * (std::abs(world.wall(wb).force[ax]) + std::abs(world.wall(wt).force[ax]));
    ++nsum;
    if (nsum == o.record_every) {
      const double closure = o.closing_speed * res.dt * (step - 0.5 * o.record_every);
      const double f = fsum / nsum;
      res.closure.push_back(closure);
      res.force.push_back(f);
      fsum = 0.0;
      nsum = 0;
      if (f > res.peak_force) {
        res.peak_force = f;
        res.peak_closure = closure;
      }
      // (not before 1 % closure: a loose surface particle makes an early, meaningless peak)
      if (res.peak_force > 0.0 && closure > 0.01 * res.height && f < o.stop_force_ratio * res.peak_force &&
          closure > (1.0 + o.stop_after_peak_ratio) * res.peak_closure) {
        res.broke = true;
        break;
      }
      if (o.verbose) {
        const double el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (el > next_report) {
          std::fprintf(stderr, "  platen test: closure %.3f mm, force %.2f kN, peak %.2f kN, %zu bonds broken\n",
                       closure * 1e3, f * 1e-3, res.peak_force * 1e-3, world.breaks().size());
          next_report = el + 5.0;
        }
      }
    }
  }
  res.steps = step;
  res.simulated_s = step * res.dt;
  res.critical_compression_ratio = res.peak_closure / res.height;
  res.breaks = world.breaks();
  res.bonds_broken = res.breaks.size();
  for (const auto& b : res.breaks) (b.tensile ? res.tensile_breaks : res.shear_breaks)++;
  res.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return res;
}

void write_force_curve_csv(const PlatenTestResult& r, const std::string& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("write_force_curve_csv: cannot write '" + file + "'");
  out << "closure_mm,force_kN\n";
  for (std::size_t k = 0; k < r.closure.size(); ++k) out << r.closure[k] * 1e3 << "," << r.force[k] * 1e-3 << "\n";
}

}  // namespace rocks
