// Virtual gap slice on dem::World (see gap_slice.hpp).
#include "chamber/gap_slice.hpp"

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "chamber/rock_pour.hpp"
#include "dem/world.hpp"

namespace chamber {
namespace {

constexpr int kSteel = 1;  // dem::default_table4()
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

double centre_of_mass_z(const dem::World& w) {
  const auto& P = w.particles();
  double mz = 0.0, m = 0.0;
  for (std::size_t i = 0; i < P.size(); ++i) mz += P.m[i] * P.z[i], m += P.m[i];
  return m > 0.0 ? mz / m : 0.0;
}

// The box's planes: x- (concave), x+ (mantle), y-, y+, floor; no top. Returns the mantle plate's index.
int add_slice_walls(dem::World& w, double gap, double depth) {
  const double lo[3] = {0, 0, 0}, hi[3] = {gap, depth, 1.0};
  return w.add_box(lo, hi, kSteel, false) + 1;
}

}  // namespace

void GapSliceOptions::validate() const {
  auto bad = [](const std::string& what) { throw std::invalid_argument("gap slice: " + what); };
  if (!(rock_min > 0.0 && rock_max >= rock_min && rock_max <= 0.2))
    bad("rock sizes: accepted 0 < rock_min <= rock_max <= 200 mm");
  if (!(gap >= 2.0 * rock_max && gap <= 1.0))
    bad("gap " + std::to_string(gap * 1e3) + " mm: accepted 2 x rock_max (" + std::to_string(2e3 * rock_max) +
        " mm) to 1000 mm");
  if (!(depth >= 2.0 * rock_max && depth <= 1.0))
    bad("depth " + std::to_string(depth * 1e3) + " mm: accepted 2 x rock_max to 1000 mm");
  if (!(stroke > 0.0 && stroke <= 0.5 * gap))
    bad("stroke " + std::to_string(stroke * 1e3) + " mm: accepted (0, gap / 2]");
  if (frequencies.empty()) bad("frequencies: none given; accepted one or more in (0, 50] Hz");
  for (double f : frequencies)
    if (!(f > 0.0 && f <= 50.0)) bad("frequency " + std::to_string(f) + " Hz: accepted (0, 50] Hz");
  if (cycles < 1 || cycles > 100) bad("cycles: accepted 1-100");
  if (rock_count < 1 || rock_count > 100000) bad("rock_count: accepted 1-100000");
  if (!(rock_density >= 500.0 && rock_density <= 20000.0)) bad("rock_density: accepted 500-20000 kg/m^3");
  if (!(settle_min_time >= 0.0 && settle_max_time >= settle_min_time && settle_max_time <= 10.0))
    bad("settle times: accepted 0 <= settle_min_time <= settle_max_time <= 10 s");
  if (!(settle_speed > 0.0)) bad("settle_speed: accepted > 0 m/s");
  if (!(dt_safety > 0.0 && dt_safety <= 1.0)) bad("dt_safety: accepted (0, 1]");
  if (!(max_overlap_fraction > 0.0 && max_overlap_fraction <= 1.0)) bad("max_overlap_fraction: accepted (0, 1]");
  if (record_every < 1) bad("record_every: accepted >= 1");
  if (threads < 1 || threads > 256) bad("threads: accepted 1-256");
}

GapSliceResult run_gap_slice(const rocks::BpmModel& bpm, const GapSliceOptions& o) {
  o.validate();
  const auto t0 = Clock::now();
  GapSliceResult res;

  // ---- loose pouring between the plates (rock_pour.hpp)
  rocks::Rng rng(o.seed);
  PourSpec spec;
  spec.rock_count = o.rock_count;
  spec.rock_min = o.rock_min, spec.rock_max = o.rock_max, spec.rock_density = o.rock_density, spec.seed = o.seed;
  const double W = o.gap, D = o.depth;
  spec.sample_xy = [W, D](rocks::Rng& g) {
    const double x = W * g.uniform(), y = D * g.uniform();
    return Eigen::Vector2d(x, y);
  };
  spec.inside = [W, D](const Eigen::Vector3d& x, double r) {
    return x.x() - r >= 1e-4 && x.x() + r <= W - 1e-4 && x.y() - r >= 1e-4 && x.y() + r <= D - 1e-4;
  };
  spec.max_height = 100.0 * W;
  const std::vector<PouredRock> feed = pour_rocks(bpm, spec, rng);
  res.rocks = static_cast<int>(feed.size());

  const dem::WorldParams wp = rock_world_params(o.threads, o.max_overlap_fraction, o.blowup_dump_path);
  dem::World w(wp);
  add_slice_walls(w, W, D);
  const FilledWorld filled = fill_with_rocks(w, feed, bpm, o.dt_safety);
  res.particles = filled.particles, res.bonds = filled.bonds, res.dt = filled.dt, res.rock_mass = filled.mass;
  if (o.verbose)
    std::fprintf(stderr, "gap slice: %d rocks, %zu particles, %zu bonds, dt %.3g s\n", res.rocks, res.particles,
                 res.bonds, res.dt);
  const double v_settled = settle_world(w, res.rock_mass, o.settle_min_time, o.settle_max_time, o.settle_speed);
  res.settle_time = w.time();
  res.bed_height = highest_top(w);
  res.loose_solid_fraction = res.rock_mass / (W * D * res.bed_height * o.rock_density);
  if (o.verbose)
    std::fprintf(stderr, "gap slice: settled %.3f s (rms speed %.4f m/s), bed %.1f mm, solid fraction %.3f\n",
                 w.time(), v_settled, res.bed_height * 1e3, res.loose_solid_fraction);
  const std::string settled = world_state_bytes(w);

  // ---- each frequency on a copy of the settled bed: the mantle plate x(t) = W - stroke (1 - cos 2 pi f t) / 2
  for (double f : o.frequencies) {
    dem::World wk(wp);
    const int mantle = add_slice_walls(wk, W, D);
    load_world_state(wk, settled, "settled gap-slice bed");
    GapSliceRun run;
    run.frequency = f;
    const long steps = std::max(2L, static_cast<long>(std::lround(1.0 / (f * res.dt))));
    const double h = 1.0 / (f * steps);  // the cycle in whole steps of about dt
    wk.set_dt(h);
    const double wf = 2.0 * M_PI * f;
    double fsum = 0.0, gsum = 0.0, tsum = 0.0;
    int n = 0;
    for (int k = 0; k < o.cycles; ++k) {
      const auto tc = Clock::now();
      GapCycle C;
      const std::size_t breaks0 = wk.breaks().size();
      const double com0 = centre_of_mass_z(wk);
      C.top = highest_top(wk);
      const double open[3] = {W, 0, 0};
      wk.set_wall_position(mantle, open);
      double work = 0.0;
      for (long i = 0; i < steps; ++i) {
        // the plate moves over the step at the exact mean speed of its path over that step
        const double t0s = i * h, t1s = (i + 1) * h;
        const double x0 = W - 0.5 * o.stroke * (1.0 - std::cos(wf * t0s));
        const double x1 = W - 0.5 * o.stroke * (1.0 - std::cos(wf * t1s));
        const double vx = (x1 - x0) / h, vel[3] = {vx, 0, 0};
        wk.set_wall_velocity(mantle, vel);
        try {
          wk.step(1);
        } catch (const dem::BlowUp& e) {
          run.blowup = "cycle " + std::to_string(k + 1) + " blew up: " + e.what();
          break;
        }
        const double F = wk.wall(mantle).force[0];  // the rock pushes the plate out (+x)
        const double dW = -F * vx * h;              // the plate's work on the rock
        work += dW;
        if (2 * i < steps) C.loading_work_per_kg += dW;
        C.peak_force = std::max(C.peak_force, F);
        fsum += F, gsum += wk.wall(mantle).p[0], tsum += k / f + t1s;  // where the world moved the plate
        if (++n == o.record_every) {
          run.t.push_back(tsum / n), run.gap.push_back(gsum / n), run.force.push_back(fsum / n);
          fsum = gsum = tsum = 0.0;
          n = 0;
        }
      }
      if (!run.blowup.empty()) {
        if (o.verbose) std::fprintf(stderr, "  %.2f Hz: %s\n", f, run.blowup.c_str());
        break;
      }
      C.work_per_kg = work / res.rock_mass;
      C.loading_work_per_kg /= res.rock_mass;
      C.peak_pressure = C.peak_force / (D * C.top);
      C.com_drop = com0 - centre_of_mass_z(wk);
      C.bonds_broken = wk.breaks().size() - breaks0;
      if (o.verbose)
        std::fprintf(stderr, "  %.2f Hz cycle %d: %.3f J/kg (closing %.3f), peak %.0f N, top %.1f mm, sank %.2f mm, "
                     "%zu bonds broken, %.0f s\n", f, k + 1, C.work_per_kg, C.loading_work_per_kg, C.peak_force,
                     C.top * 1e3, C.com_drop * 1e3, C.bonds_broken, seconds_since(tc));
      run.cycles.push_back(C);
    }
    res.runs.push_back(std::move(run));
  }
  res.wall_s = seconds_since(t0);
  return res;
}

}  // namespace chamber
