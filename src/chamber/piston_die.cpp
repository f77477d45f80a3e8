// Virtual piston-die test on dem::World (see piston_die.hpp).
#include "chamber/piston_die.hpp"

#include "chamber/rock_pour.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "dem/fragments.hpp"
#include "dem/mesh_contact.hpp"
#include "dem/revolution.hpp"
#include "dem/world.hpp"
#include "rocks/rng.hpp"

namespace chamber {
namespace {

constexpr int kSteel = 1;  // dem::default_table4()
constexpr int kDieSectors = 48;

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Mass fraction passing each sieve (m) of the fragments over intact bonds.
std::vector<double> fragment_passing(const dem::World& w, const std::vector<double>& sieves, double* total,
                                     int* count) {
  const auto frags = dem::Fragments::from_bonds(w.particles(), w.bonds()).info(w.particles());
  std::vector<double> pass(sieves.size(), 0.0);
  double m = 0.0;
  for (const auto& f : frags) {
    m += f.mass;
    for (std::size_t k = 0; k < sieves.size(); ++k)
      if (f.sieve_size <= sieves[k] * (1.0 + 1e-12)) pass[k] += f.mass;
  }
  for (double& x : pass) x = m > 0 ? x / m : 0.0;
  if (total) *total = m;
  if (count) *count = static_cast<int>(frags.size());
  return pass;
}

// The die: steel floor (plane 0), die wall (mesh), piston (plane 1). The same calls build the copy a
// checkpoint is loaded into.
struct Die {
  std::unique_ptr<dem::World> world;
  std::shared_ptr<dem::MeshContact> wall;
  int floor = -1, piston = -1;
};

// The wall reaches `below` m under the floor's start (the room a bed pushed down the die needs).
Die make_die(const dem::WorldParams& wp, double radius, double height, double below, int threads) {
  Die d;
  d.world = std::make_unique<dem::World>(wp);
  const double o[3] = {0, 0, 0}, up[3] = {0, 0, 1}, top[3] = {0, 0, height}, down[3] = {0, 0, -1};
  d.floor = d.world->add_plane(o, up, kSteel);
  d.piston = d.world->add_plane(top, down, kSteel);
  auto mesh = dem::revolve_profile({{-0.01 - below, radius}, {height + 0.01, radius}}, kDieSectors,
                                   dem::NormalSide::Inward, 0.0, "die");
  d.wall = std::make_shared<dem::MeshContact>(std::move(mesh), wp.materials, kSteel);
  d.wall->set_threads(threads);
  d.wall->set_pose(dem::Pose{});
  d.world->add_interaction(d.wall);
  return d;
}

}  // namespace

const std::vector<double>& flow_sieves_mm() {
  static const std::vector<double> s = [] {
    std::vector<double> mm;
    for (double x : FlowParams().sieves_m) mm.push_back(x * 1e3);  // the flow model's default sieves
    return mm;
  }();
  return s;
}

void PistonDieOptions::validate() const {
  auto bad = [](const std::string& what) { throw std::invalid_argument("piston die: " + what); };
  if (!(rock_min > 0.0 && rock_max >= rock_min && rock_max <= 0.2))
    bad("rock sizes: accepted 0 < rock_min <= rock_max <= 200 mm");
  if (!(die_diameter >= 3.0 * rock_max && die_diameter <= 2.0))
    bad("die_diameter " + std::to_string(die_diameter * 1e3) + " mm: accepted >= 3 x rock_max (" +
        std::to_string(3e3 * rock_max) + " mm) and <= 2000 mm");
  if (rock_count < 0 || rock_count > 100000) bad("rock_count: accepted 0 (fill bed_height) to 100000");
  if (rock_count == 0 && !(bed_height >= rock_max && bed_height <= 5.0))
    bad("bed_height: with rock_count 0, accepted rock_max <= bed_height <= 5 m");
  if (!(rock_density >= 500.0 && rock_density <= 20000.0)) bad("rock_density: accepted 500-20000 kg/m^3");
  if (compression_ratios.empty()) bad("compression_ratios: at least one is needed");
  for (std::size_t k = 0; k < compression_ratios.size(); ++k) {
    const double s = compression_ratios[k];
    if (!(s > 0.0 && s <= 0.6)) bad("compression ratio " + std::to_string(s) + ": accepted (0, 0.6]");
    if (k && !(s > compression_ratios[k - 1])) bad("compression_ratios: accepted strictly ascending values");
  }
  if (!(piston_speed > 0.0 && piston_speed <= 5.0)) bad("piston_speed: accepted (0, 5] m/s");
  if (!(settle_min_time >= 0.0 && settle_max_time >= settle_min_time && settle_max_time <= 10.0))
    bad("settle times: accepted 0 <= settle_min_time <= settle_max_time <= 10 s");
  if (!(settle_speed > 0.0)) bad("settle_speed: accepted > 0 m/s");
  if (!(dt_safety > 0.0 && dt_safety <= 1.0)) bad("dt_safety: accepted (0, 1]");
  if (!(max_overlap_fraction > 0.0 && max_overlap_fraction <= 1.0)) bad("max_overlap_fraction: accepted (0, 1]");
  if (!(unload_stop_ratio > 0.0 && unload_stop_ratio < 0.5)) bad("unload_stop_ratio: accepted (0, 0.5)");
  if (reloads < 0 || reloads > 20) bad("reloads: accepted 0-20 pressings of the same bed after the first");
  if (!(sweep >= 0.0 && sweep <= 5.0)) bad("sweep " + std::to_string(sweep) + ": accepted 0-5 (x the piston's speed)");
  if (!(reload_shift >= 0.0 && reload_shift <= 0.2))
    bad("reload_shift " + std::to_string(reload_shift * 1e3) + " mm: accepted 0-200 mm");
  if (reload_shift > 0.0 && reloads == 0) bad("reload_shift: a shift comes before a reload; set reloads >= 1");
  if (record_every < 1) bad("record_every: accepted >= 1");
  if (!(resolve_diameters >= 1.0)) bad("resolve_diameters: accepted >= 1");
  if (threads < 1 || threads > 256) bad("threads: accepted 1-256");
}

PistonDieResult run_piston_die(const rocks::BpmModel& bpm, const PistonDieOptions& o) {
  o.validate();
  const auto t0 = Clock::now();
  PistonDieResult res;
  res.seed = o.seed;
  res.rock_min = o.rock_min, res.rock_max = o.rock_max, res.piston_speed = o.piston_speed;
  const double R = 0.5 * o.die_diameter;
  res.die_diameter = o.die_diameter;
  res.die_area = M_PI * R * R;
  res.solid_density = o.rock_density;
  std::vector<double> sieves;
  for (double mm : flow_sieves_mm()) sieves.push_back(mm * 1e-3);
  double dmean = 0.0;  // volume-mean metaparticle diameter
  for (const auto& m : bpm.metaparticles.modes()) dmean += 2.0 * m.mean_radius * m.volume_fraction;
  res.metaparticle_diameter = dmean;
  res.min_resolved = 0.0;
  for (double a : sieves)
    if (a >= o.resolve_diameters * dmean) {
      res.min_resolved = a;
      break;
    }

  // ---- loose pouring, part 1: random sequential placement in the die (rock_pour.hpp)
  rocks::Rng rng(o.seed);
  const double r_in = R * std::cos(M_PI / kDieSectors) - 1e-4;  // the facets' inscribed radius, less a margin
  PourSpec spec;
  spec.rock_count = o.rock_count;
  spec.fill_volume = 0.5 * res.die_area * o.bed_height;  // rock_count 0: a loose bed of ~0.5 solid
  spec.rock_min = o.rock_min, spec.rock_max = o.rock_max, spec.rock_density = o.rock_density, spec.seed = o.seed;
  spec.sample_xy = [R](rocks::Rng& g) {
    const double phi = 2.0 * M_PI * g.uniform(), rr = R * std::sqrt(g.uniform());
    return Eigen::Vector2d(rr * std::cos(phi), rr * std::sin(phi));
  };
  spec.inside = [r_in](const Eigen::Vector3d& x, double r) { return std::hypot(x.x(), x.y()) + r <= r_in; };
  spec.max_height = 1e3 * o.die_diameter;
  const std::vector<PouredRock> feed = pour_rocks(bpm, spec, rng);
  res.rocks = static_cast<int>(feed.size());
  const double z_top = poured_top(feed);

  // ---- the world
  const dem::WorldParams wp = rock_world_params(o.threads, o.max_overlap_fraction, o.blowup_dump_path);
  const double column = z_top + o.rock_max;
  Die die = make_die(wp, R, column, 0.0, o.threads);
  dem::World& w = *die.world;
  const FilledWorld filled = fill_with_rocks(w, feed, bpm, o.dt_safety);
  res.particles = filled.particles, res.bonds = filled.bonds, res.dt = filled.dt, res.rock_mass = filled.mass;
  if (o.verbose)
    std::fprintf(stderr, "piston die: %d rocks, %zu particles, %zu bonds, dt %.3g s, column %.1f mm\n", res.rocks,
                 res.particles, res.bonds, res.dt, column * 1e3);

  // ---- loose pouring, part 2: settle under gravity until (nearly) at rest
  const double v_settled = settle_world(w, res.rock_mass, o.settle_min_time, o.settle_max_time, o.settle_speed);
  if (o.verbose) std::fprintf(stderr, "piston die: settled %.3f s (rms speed %.4f m/s)\n", w.time(), v_settled);
  res.settle_time = w.time();
  res.bed_height = highest_top(w);
  res.loose_solid_fraction = res.rock_mass / (res.die_area * res.bed_height * res.solid_density);
  res.feed_passing = fragment_passing(w, sieves, nullptr, nullptr);
  const std::size_t settle_breaks = w.breaks().size();
  const std::string settled = world_state_bytes(w);

  // ---- each s_max on a copy of the settled bed: load, unload, screen; then `reloads` more pressings of the same bed
  const double H0 = res.bed_height, A = res.die_area, v = o.piston_speed;
  // One pressing of the bed in wk from the piston's height z0 down to s_max and back until the bed lets go; fills L
  // (curves, energies, bonds broken since `breaks0`, PSD). False when it blew up (res.blowup says where).
  auto press = [&](dem::World& wk, const Die& d, double s_max, double z0, std::size_t breaks0, PressLoop& L) {
    const auto tl = Clock::now();
    // sweep: the piston also slides sideways (+x loading, -x unloading), as the gyrating mantle sweeps the bed
    const double vt = o.sweep * v;
    const double start[3] = {0, 0, z0}, vdown[3] = {vt, 0, -v}, vup[3] = {-vt, 0, v};
    wk.set_wall_position(d.piston, start);
    wk.set_wall_velocity(d.piston, vdown);
    L.s_max = s_max;
    const double floor_z = wk.wall(d.floor).p[2];  // 0, or lower once the bed was pushed down the die
    const double top = std::max(floor_z, highest_top(wk));
    L.s_top = (H0 - (top - floor_z)) / H0;
    L.s.push_back((H0 - (z0 - floor_z)) / H0), L.p.push_back(0.0), L.phase.push_back(0);
    int phase = 0;
    double fsum = 0.0, ssum = 0.0, peak = 0.0, sweep_work = 0.0;
    int n = 0;
    double next_report = seconds_since(tl) + 10.0;
    for (;;) {
      try {
        wk.step(1);
      } catch (const dem::BlowUp& e) {
        if (!o.keep_loops_on_blowup || res.loops.empty()) throw;
        char at[64];
        std::snprintf(at, sizeof at, "s_max %.2f blew up at s %.4f: ", s_max, L.s_reached);
        res.blowup = at + std::string(e.what());
        return false;
      }
      const double s = (H0 - (wk.wall(d.piston).p[2] - floor_z)) / H0;
      fsum += wk.wall(d.piston).force[2];  // particles push the piston up (+z)
      sweep_work -= wk.wall(d.piston).force[0] * wk.wall(d.piston).v[0] * wk.dt();  // the piston's sideways work
      ssum += s;
      if (++n < o.record_every && !(phase == 0 && s >= s_max)) continue;
      const double pm = fsum / n / A, sm = ssum / n;
      fsum = ssum = 0.0;
      n = 0;
      L.s.push_back(sm), L.p.push_back(pm), L.phase.push_back(phase);
      peak = std::max(peak, pm);
      L.s_reached = std::max(L.s_reached, sm);
      if (phase == 0 && s >= s_max) {
        phase = 1;
        wk.set_wall_velocity(d.piston, vup);
      } else if (phase == 1 && (pm < o.unload_stop_ratio * peak || s <= 0.0)) {
        break;
      }
      if (o.verbose && seconds_since(tl) > next_report) {
        std::fprintf(stderr, "  s_max %.2f: %s s %.4f p %.3f MPa, %zu bonds broken\n", s_max,
                     phase ? "unloading" : "loading", sm, pm * 1e-6, wk.breaks().size() - breaks0);
        next_report = seconds_since(tl) + 10.0;
      }
    }
    const double still[3] = {0, 0, 0};
    wk.set_wall_velocity(d.piston, still);
    std::vector<double> sl, pl;
    for (std::size_t k = 0; k < L.s.size(); ++k)
      if (L.phase[k] == 0) sl.push_back(L.s[k]), pl.push_back(L.p[k]);
    L.loading_work = path_integral(sl, pl);
    L.loop_energy = path_integral(L.s, L.p);
    L.energy_per_kg = A * H0 * L.loop_energy / res.rock_mass;
    L.loading_energy_per_kg = A * H0 * L.loading_work / res.rock_mass;
    L.bonds_broken = wk.breaks().size() - breaks0;
    double m = 0.0;
    L.passing = fragment_passing(wk, sieves, &m, &L.fragments);
    L.mass_error = std::abs(m - res.rock_mass) / res.rock_mass;
    L.sweep_energy_per_kg = sweep_work / res.rock_mass;
    L.wall_s = seconds_since(tl);
    if (o.verbose)
      std::fprintf(stderr, "  s_max %.2f%s: peak %.3f MPa, loop %.1f J/kg of %.1f J/kg loading, %zu bonds broken, "
                   "%d fragments, %.0f s\n", s_max, L.s.front() > 0.0 ? " again" : "", peak * 1e-6, L.energy_per_kg,
                   L.loading_energy_per_kg, L.bonds_broken, L.fragments, L.wall_s);
    return true;
  };
  // Pushes the bed `shift` m down the die: floor and piston move down together at the piston's speed (the bed slides
  // along the wall), then everything is left to come to rest (rms speed under settle_speed, at most settle_max_time).
  auto push_down = [&](dem::World& wk, const Die& d, double shift, PressLoop& L) {
    const double vdown[3] = {0, 0, -v}, still[3] = {0, 0, 0};
    const double zf = wk.wall(d.floor).p[2] - shift, zp = wk.wall(d.piston).p[2] - shift;
    wk.set_wall_velocity(d.floor, vdown);
    wk.set_wall_velocity(d.piston, vdown);
    const long n = std::max(1L, static_cast<long>(std::lround(shift / (v * res.dt))));
    for (long k = 0; k < n; ++k) {
      wk.step(1);
      L.shift_peak_pressure = std::max(L.shift_peak_pressure, wk.wall(d.piston).force[2] / A);
    }
    const double fz[3] = {0, 0, zf}, pz[3] = {0, 0, zp};
    wk.set_wall_position(d.floor, fz), wk.set_wall_position(d.piston, pz);
    wk.set_wall_velocity(d.floor, still), wk.set_wall_velocity(d.piston, still);
    settle_world(wk, res.rock_mass, wk.time(), wk.time() + o.settle_max_time, o.settle_speed);
    L.shift = shift;
  };
  // A World built with the die `below` and the state in `bytes` (the pressings go on in a longer die when the bed is
  // pushed down: the pour and the first pressing keep the die without it, so they are those of an unshifted run).
  auto die_with = [&](double below, const std::string& bytes, const char* what) {
    Die d = make_die(wp, R, column, below, o.threads);
    load_world_state(*d.world, bytes, what);
    return d;
  };
  for (double s_max : o.compression_ratios) {
    Die d = die_with(0.0, settled, "settled piston-die bed");
    PressLoop L;
    bool blew_up = !press(*d.world, d, s_max, H0, settle_breaks, L);
    if (!blew_up && o.reloads > 0 && o.reload_shift > 0.0) {
      d = die_with(o.reloads * o.reload_shift, world_state_bytes(*d.world), "pressed piston-die bed");
    }
    dem::World& wk = *d.world;
    for (int k = 0; k < o.reloads && !blew_up; ++k) {  // the same bed again, from where the piston let go of it
      PressLoop again;
      const std::size_t breaks0 = wk.breaks().size();
      if (o.reload_shift > 0.0) push_down(wk, d, o.reload_shift, again);
      blew_up = !press(wk, d, s_max, wk.wall(d.piston).p[2], breaks0, again);
      if (!blew_up) L.reloads.push_back(std::move(again));
    }
    if (blew_up && L.passing.empty()) {  // its first pressing blew up: a deeper pressing of this bed would jam again
      if (o.verbose)
        std::fprintf(stderr, "  %s; the %zu loops completed are kept\n", res.blowup.c_str(), res.loops.size());
      break;
    }
    res.loops.push_back(std::move(L));
    if (blew_up) break;
  }
  res.wall_s = seconds_since(t0);
  return res;
}

}  // namespace chamber
