#include "coupling/chamber_dem.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <unordered_map>

#include "dem/fragments.hpp"
#include "dem/mesh_liners.hpp"
#include "dem/revolution.hpp"
#include "dem/time_step.hpp"
#include "rocks/shape.hpp"

namespace coupling {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kRock = 0, kSteel = 1;  // dem::default_table4() indices
constexpr int kFragmentOrientations = 8;  // tetrahedron turns tried per crushed sphere (place_fragments)

// Key of the cell (edge `cell`) holding x, shifted by (dx, dy, dz) cells: the hash grids of prefill and
// birth_obstacles (cells of twice the largest radius, so touching spheres lie in neighbouring cells).
long long cell_key(const Eigen::Vector3d& x, double cell, int dx, int dy, int dz) {
  const long long i = static_cast<long long>(std::floor(x.x() / cell)) + dx;
  const long long j = static_cast<long long>(std::floor(x.y() / cell)) + dy;
  const long long k = static_cast<long long>(std::floor(x.z() / cell)) + dz;
  return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
}

// Profile points bottom to top (z is monotonic), as revolve_profile expects for outward normals.
std::vector<dem::ProfilePoint> ascending(const core::Profile& p) {
  auto out = dem::profile_points(p);
  if (out.front().z > out.back().z) std::reverse(out.begin(), out.end());
  return out;
}

Eigen::Quaterniond extrapolate(const Eigen::Quaterniond& q, const Eigen::Vector3d& w, double tau) {
  const double a = w.norm() * tau;
  if (a < 1e-15) return q;
  return (Eigen::Quaterniond(Eigen::AngleAxisd(a, w.normalized())) * q).normalized();
}

}  // namespace

ChamberDem::ChamberDem(const ChamberParams& p) : p_(p), bond_(p.bpm.bond.params()), rng_(p.feed.seed) {
  core::validate_chamber_geometry(p_.chamber);
  auto mant = ascending(p_.chamber.mantle), conc = ascending(p_.chamber.concave);
  z_bottom_ = conc.front().z;
  z_top_ = conc.back().z;
  const double rock = p_.feed.rock_size_m;

  // Breakable rocks: four irregular shapes packed with metaparticles and bonded (section 2.4.1).
  for (int s = 0; s < p_.feed.shapes; ++s) {
    auto shape = rocks::make_irregular_rock(p_.feed.seed + 101 * s, rock, 22, "rock" + std::to_string(s));
    rocks::PackingOptions po = p_.bpm.packing;
    po.seed = p_.feed.seed + 101 * s;
    // A shape too small for a few coarse metaparticles at this density keeps overlaps: step the
    // density down (by 0.03, to 0.30 at least) rather than refuse the run; packing_density() reports it.
    for (;;) {
      try {
        rocks_.push_back(rocks::pack_shape(*shape, p_.bpm.metaparticles, po));
        break;
      } catch (const std::runtime_error&) {
        if (po.density <= 0.3 + 1e-9) throw;
        po.density = std::max(0.3, po.density - 0.03);
      }
    }
  }

  const dem::MaterialTable table4 = dem::default_table4();
  double mass = 0, volume = 0;
  for (const auto& rk : rocks_) {
    // feed.rock_density: spheres heavier by V / (sum of sphere volumes), so that the rock weighs rho V.
    const double rho = p_.feed.rock_density > 0 ? p_.feed.rock_density * rk.container_volume / rk.solid_volume()
                                                 : table4.material(kRock).density;
    sphere_density_.push_back(rho);
    rock_mass_.push_back(rho * rk.solid_volume());
    mass += rock_mass_.back(), volume += rk.solid_volume();
  }
  // Lump sizes (crushing strength, screening) and grown fragments are at the rock spheres' mean density: a crushed
  // sphere's fragments keep its volume, and a sphere is the size it is drawn.
  rock_density_ = p_.feed.rock_density > 0 ? mass / volume : table4.material(kRock).density;

  // Time step from one bonded rock: the stiffer of Hertz (Rayleigh) and bond limits, with margin.
  dem::WorldParams wp;
  wp.threads = p_.threads;
  wp.blowup_dump_path = p_.blowup_dump_path;
  wp.skin = 0.4 * p_.bpm.metaparticles.max_radius();  // the world starts empty: no automatic skin
  wp.materials = table4;
  double dt = p_.dt_s;
  {
    dem::WorldParams probe = wp;
    probe.check_time_step = false;
    dem::World w(probe);
    // Spheres made heavier (feed.rock_density) allow a longer Rayleigh step, but their impacts press deeper: the
    // step stays that of spheres at the material's density.
    const double probe_density =
        std::min(table4.material(kRock).density, *std::min_element(sphere_density_.begin(), sphere_density_.end()));
    const auto& r0 = rocks_.front();
    for (std::size_t i = 0; i < r0.size(); ++i) {
      double x[3] = {r0.positions[i].x(), r0.positions[i].y(), r0.positions[i].z()};
      w.add_particle(x, r0.radii[i], kRock, probe_density, nullptr, nullptr);
    }
    std::vector<std::pair<std::size_t, std::size_t>> pairs(r0.bonds.begin(), r0.bonds.end());
    w.bond_pairs(pairs, bond_);
    auto c = w.time_step_check();
    const double bound = std::min(wp.max_rayleigh_fraction * c.rayleigh, c.bond);
    if (dt <= 0) dt = 0.8 * bound;
    if (dt > bound) {
      throw std::invalid_argument("dem.dt_s = " + std::to_string(dt) + " s is unstable: Rayleigh step " +
                                  std::to_string(c.rayleigh) + " s (x" + std::to_string(wp.max_rayleigh_fraction) +
                                  "), bond step " + std::to_string(c.bond) + " s");
    }
  }
  wp.dt = dt;
  dt_max_ = dt;
  // Smallest sphere of rock density whose Rayleigh step keeps this step stable (fragments of crushed spheres).
  fragment_min_radius_ =
      dt / (wp.max_rayleigh_fraction * dem::rayleigh_time_step(1.0, rock_density_, wp.materials.material(kRock)));
  wp_ = wp;
  whole_ = std::make_unique<dem::World>(wp);
  gravity_ = std::sqrt(wp.gravity[0] * wp.gravity[0] + wp.gravity[1] * wp.gravity[1] + wp.gravity[2] * wp.gravity[2]);

  // Liners from the shared geometry (the concave refined at the force-map ring boundaries), plus a
  // distribution cone on the mantle top and the feed hopper above the concave (both rigid with their body).
  const double r_mtop = mant.back().r, r_ctop = conc.back().r;
  auto liners = dem::make_liner_meshes(p_.chamber, p_.liner_sectors, 0.05, p_.rings, p_.sectors);
  auto cap = dem::revolve_profile({mant.back(), {mant.back().z + 0.6 * r_mtop, 0.0}}, p_.liner_sectors,
                                  dem::NormalSide::Outward, 0.0, "mantle_cap");
  auto hopper = dem::revolve_profile({conc.back(), {z_top_ + p_.feed.choke_height_m + 3.0 * rock, r_ctop}},
                                     p_.liner_sectors, dem::NormalSide::Inward, 0.0, "hopper");
  auto mantle = std::make_shared<dem::MeshContact>(std::move(liners.mantle), wp.materials, kSteel);
  auto concave = std::make_shared<dem::MeshContact>(std::move(liners.concave), wp.materials, kSteel);
  auto cap_mesh = std::make_shared<dem::MeshContact>(std::move(cap), wp.materials, kSteel);
  auto hopper_mesh = std::make_shared<dem::MeshContact>(std::move(hopper), wp.materials, kSteel);
  // The walls the prefill keeps rock within, as drawn by the meshes above (liner frames, z ascending).
  for (const auto& q : mant) inner_.z.push_back(q.z), inner_.r.push_back(q.r);
  inner_.z.push_back(mant.back().z + 0.6 * r_mtop), inner_.r.push_back(0.0);
  for (const auto& q : conc) outer_.z.push_back(q.z), outer_.r.push_back(q.r);
  outer_.z.push_back(z_top_ + p_.feed.choke_height_m + 3.0 * rock), outer_.r.push_back(r_ctop);
  concave->set_regions(std::move(liners.concave_regions));  // 13 x 9 areas P_{ring,sector} (section 4.2.3)
  force_avg_ = dem::RegionAverager(p_.rings * p_.sectors);
  for (auto& m : {mantle, concave, cap_mesh, hopper_mesh}) {  // interactions 0-3 of every World of the run (focus)
    m->set_threads(whole_->threads());
    whole_->add_interaction(m);
  }
  focus(*whole_);
  engine_ = std::make_unique<dem::WholeEngine>(*whole_);

  r_feed_out_ = r_ctop - 0.6 * rock;
  r_feed_in_ = std::max(0.5 * rock, 0.35 * r_feed_out_);
  if (r_feed_out_ <= r_feed_in_) throw std::invalid_argument("dem.feed.rock_size_mm: rocks do not fit the chamber top");
  if (p_.sieves_m.empty()) throw std::invalid_argument("dem.sieves_mm: at least one sieve");
  screened_kg_.assign(p_.sieves_m.size() + 1, 0.0);  // last class: above the largest sieve
  if (p_.fines_flow) {  // one chamber model: the flow model (src/chamber) carries the crushed fines
    fines_ = std::make_unique<chamber::FlowModel>(chamber::fines_only(p_.fines), p_.chamber.mantle, p_.chamber.concave);
    to_flow_ = chamber::SizeClassMap(p_.sieves_m, p_.fines.sieves_m);
    from_flow_ = chamber::SizeClassMap(p_.fines.sieves_m, p_.sieves_m);
  }
}

namespace {
Eigen::Isometry3d isometry(const dem::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = p.orientation.toRotationMatrix();
  T.translation() = p.position;
  return T;
}
}  // namespace

void ChamberDem::set_liners(const BodyMotion& m, const BodyMotion& c, double tau) {
  auto apply = [tau](dem::MeshContact& mc, const BodyMotion& b, double com_z, Eigen::Vector3d* origin_out) {
    const Eigen::Quaterniond q = extrapolate(b.orientation, b.angular_velocity, tau);
    const Eigen::Vector3d com = b.com + b.velocity * tau;
    const Eigen::Vector3d origin = com - q * Eigen::Vector3d(0, 0, com_z);
    mc.set_pose({origin, q});
    mc.set_twist({b.velocity + b.angular_velocity.cross(origin - com), b.angular_velocity});
    if (origin_out) *origin_out = origin;
  };
  apply(*mantle_, m, p_.mantle_com_z_m, nullptr);
  apply(*cap_, m, p_.mantle_com_z_m, nullptr);
  apply(*concave_, c, p_.concave_com_z_m, &concave_origin_);
  apply(*hopper_, c, p_.concave_com_z_m, nullptr);
}

std::pair<BodyWrench, BodyWrench> ChamberDem::advance(const BodyMotion& m, const BodyMotion& c, double duration) {
  if (!(duration > 0)) throw std::invalid_argument("ChamberDem::advance: duration must be > 0");
  // Whole DEM steps per coupling interval, each no longer than the stable step chosen at start.
  const long n = std::max(1L, static_cast<long>(std::ceil(duration / dt_max_ - 1e-9)));
  const double h = duration / n;
  using clk = std::chrono::steady_clock;
  auto t1 = clk::now();
  auto lap = [this, &t1](int k) {  // phase_seconds()
    const auto now = clk::now();
    phase_s_[k] += std::chrono::duration<double>(now - t1).count();
    t1 = now;
  };
  if (p_.feed.prefill && !prefilled_) {  // at the liners' first pose
    set_liners(m, c, 0.0);
    prefill();
    prefilled_ = true;
    lap(5);
  }
  if (make_engine_ && !decomposed_) start_engine();
  for (int j = 0; j < engine_->parts(); ++j) {
    dem::World& w = engine_->part(j);
    if (std::abs(h - w.dt()) > 1e-15 * h) w.set_dt(h);
  }
  // Per part: mantle and concave force and torque (12) integrated over the interval, then the force map's regions;
  // summed over the parts in order and over the processes (DomainEngine::sum) at the end.
  const std::size_t nr = force_avg_.sums().size();
  std::vector<std::vector<double>> acc(engine_->parts(), std::vector<double>(12 + (decomposed_ ? nr : 0), 0.0));
  auto add3 = [](double* to, const Eigen::Vector3d& v, double h) {
    for (int q = 0; q < 3; ++q) to[q] += v[q] * h;
  };
  for (long k = 0; k < n; ++k) {
    const double tau = (k + 1) * h;  // positions at the end of the drift of this step
    for (int j = 0; j < engine_->parts(); ++j) {
      focus(engine_->part(j));
      set_liners(m, c, tau);
    }
    lap(1);
    step_parts();
    focus(engine_->part(0));
    if (!growing_.empty()) grow_fragments(h);
    if (progress_) progress_();
    lap(0);
    const Eigen::Vector3d com_m = m.com + m.velocity * tau, com_c = c.com + c.velocity * tau;
    for (int j = 0; j < engine_->parts(); ++j) {
      focus(engine_->part(j));
      double* a = acc[j].data();
      for (const auto* mc : {mantle_, cap_, concave_, hopper_})
        deepest_liner_overlap_ = std::max(deepest_liner_overlap_, mc->worst_overlap().first);
      for (const auto* mc : {mantle_, cap_}) {
        const auto w = mc->wrench_about(com_m);
        add3(a, w.force, h), add3(a + 3, w.torque, h);
      }
      for (const auto* mc : {concave_, hopper_}) {
        const auto w = mc->wrench_about(com_c);
        add3(a + 6, w.force, h), add3(a + 9, w.torque, h);
      }
      if (decomposed_) {
        const auto& f = concave_->region_normal_force();
        for (std::size_t r = 0; r < nr && r < f.size(); ++r) a[12 + r] += f[r] * h;
      }
    }
    focus(engine_->part(0));
    lap(1);
    if (fines_ && engine_->root()) {  // the root's part carries the fines' wrench
      const auto f = fines_->step(isometry(mantle_->mesh().pose()), isometry(concave_->mesh().pose()), com_m, com_c,
                                  h, gravity_);
      double* a = acc[0].data();
      add3(a, f.f_mantle, h), add3(a + 3, f.t_mantle, h), add3(a + 6, f.f_concave, h), add3(a + 9, f.t_concave, h);
      fines_force_ = f.normal_force;
      lap(2);
    }
    if (!decomposed_) force_avg_.add(concave_->region_normal_force(), h);
    force_window_s_ += h;
    lap(1);
    if (p_.crushing.enabled) crush_squeezed(k + 1 == n);
    lap(3);
    if (time() >= next_bookkeeping_ - 1e-12) {
      edit_whole([this] {
        bookkeeping();
        prune_growing();
        if (decomposed_) take_snapshot();
      });
      next_bookkeeping_ = time() + p_.bookkeeping_s;
    }
    lap(4);
  }
  std::vector<double> total = acc[0];
  for (std::size_t j = 1; j < acc.size(); ++j)
    for (std::size_t q = 0; q < total.size(); ++q) total[q] += acc[j][q];
  if (decomposed_) {
    engine_->sum(total);
    force_avg_.add_integral(std::vector<double>(total.begin() + 12, total.end()), duration);
    deepest_liner_overlap_ = engine_->max(deepest_liner_overlap_);
  }
  BodyWrench wm, wc;
  wm.force = Eigen::Vector3d(total[0], total[1], total[2]) / duration;
  wm.torque = Eigen::Vector3d(total[3], total[4], total[5]) / duration;
  wc.force = Eigen::Vector3d(total[6], total[7], total[8]) / duration;
  wc.torque = Eigen::Vector3d(total[9], total[10], total[11]) / duration;
  return {wm, wc};
}

void ChamberDem::bookkeeping() {
  harvest_breaks();
  discharge();
  if (fines_) {  // fines that fell out of the bed's bottom band
    const auto out = from_flow_.map(fines_->take_discharged());
    double kg = 0;
    for (std::size_t k = 0; k < out.size(); ++k) screened_kg_[k] += out[k], kg += out[k];
    if (kg > 0) {
      discharged_kg_ += kg;
      discharge_log_.emplace_back(world_->time(), kg);
    }
  }
  feed();
  // The throughput window is all the discharge log is for.
  const double keep_from = world_->time() - p_.throughput_window_s;
  auto old = std::find_if(discharge_log_.begin(), discharge_log_.end(), [&](const auto& e) { return e.first > keep_from; });
  discharge_log_.erase(discharge_log_.begin(), old);
  if (tracked_ids_.empty() && world_->particles().size() > 0) {  // follow a few particles of the first rock
    for (int i = 0; i < p_.tracked_particles && i < static_cast<int>(world_->particles().size()); ++i)
      tracked_ids_.push_back(world_->particles().id[i * 7 % world_->particles().size()]);
  }
  const auto& P = world_->particles();
  for (uint64_t id : tracked_ids_) {
    long i = world_->index_of(id);
    if (i >= 0) tracks_.push_back({id, world_->time(), {P.x[i], P.y[i], P.z[i]}});
  }
}

bool ChamberDem::place_rock(int shape, const Eigen::Vector3d& centre, const Eigen::Quaterniond& q) {
  const auto& rk = rocks_[shape];
  const auto& P = world_->particles();
  // The spot must be free: every sphere clear of the liners, and no particle within the rock's bounding sphere
  // plus its own radius.
  double reach = 0;
  for (std::size_t i = 0; i < rk.size(); ++i) reach = std::max(reach, rk.positions[i].norm() + rk.radii[i]);
  for (std::size_t i = 0; i < rk.size(); ++i)
    if (!clear_of_liners(centre + q * rk.positions[i], rk.radii[i])) return false;
  for (std::size_t j = 0; j < P.size(); ++j) {
    const double dx = P.x[j] - centre.x(), dy = P.y[j] - centre.y(), dz = P.z[j] - centre.z();
    const double lim = reach + P.r[j];
    if (dx * dx + dy * dy + dz * dz < lim * lim) return false;
  }
  add_rock(shape, centre, q, Eigen::Vector3d(0, 0, -p_.feed.drop_speed_m_s));
  return true;
}

void ChamberDem::add_rock(int shape, const Eigen::Vector3d& centre, const Eigen::Quaterniond& q,
                          const Eigen::Vector3d& v) {
  const auto& rk = rocks_[shape];
  const std::size_t first = world_->particles().size();
  const double va[3] = {v.x(), v.y(), v.z()};
  for (std::size_t i = 0; i < rk.size(); ++i) {
    const Eigen::Vector3d x = centre + q * rk.positions[i];
    const double xa[3] = {x.x(), x.y(), x.z()};
    world_->add_particle(xa, rk.radii[i], kRock, sphere_density_[shape], va, nullptr);
  }
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  pairs.reserve(rk.bonds.size());
  for (auto [i, j] : rk.bonds) pairs.emplace_back(first + i, first + j);
  world_->bond_pairs(pairs, bond_);
  fed_kg_ += rock_mass_[shape];
}

void ChamberDem::add_rock_at(int shape, const Eigen::Vector3d& centre, const Eigen::Vector3d& velocity) {
  if (shape < 0 || shape >= rock_shapes())
    throw std::invalid_argument("ChamberDem::add_rock_at: shape " + std::to_string(shape) + " not in [0, " +
                                std::to_string(rock_shapes()) + ")");
  add_rock(shape, centre, Eigen::Quaterniond::Identity(), velocity);
}

Eigen::Quaterniond ChamberDem::random_orientation() {
  Eigen::Quaterniond q(rng_.uniform() - 0.5, rng_.uniform() - 0.5, rng_.uniform() - 0.5, rng_.uniform() - 0.5);
  return q.normalized();
}

bool ChamberDem::clear_of_liners(const Eigen::Vector3d& x, double r) const {
  const Eigen::Vector3d xc = concave_->mesh().to_body(x), xm = mantle_->mesh().to_body(x);
  // The concave's and hopper's flat facets lie inside their circle by up to r (1 - cos(pi / sectors)).
  const double sag = 1.0 - std::cos(kPi / p_.liner_sectors);
  const double rho_c = std::hypot(xc.x(), xc.y());
  if (core::signed_distance_inside(outer_, {xc.z(), rho_c}, nullptr) < r + sag * (rho_c + r)) return false;
  return core::signed_distance_inside(inner_, {xm.z(), std::hypot(xm.x(), xm.y())}, nullptr) <= -r;
}

// Pre-filled chamber: the feed's rocks, at rest and randomly oriented, placed bottom up in rings of trial
// positions between the liners (mantle and its cap inside, concave and hopper outside) up to the choke level.
// A rock goes in when each of its spheres clears both walls and every sphere already placed (random
// sequential placement: a loose bed, no overlaps). Stops at prefill_max_kg or max_fed_kg.
void ChamberDem::prefill() {
  const double limit = std::min(p_.feed.max_fed_kg, p_.feed.prefill_max_kg);
  const double rock = p_.feed.rock_size_m;
  const auto& cm = concave_->mesh();
  const auto& mm = mantle_->mesh();
  double rmax = 0;
  for (const auto& rk : rocks_)
    for (double r : rk.radii) rmax = std::max(rmax, r);
  // Hash grid over the spheres placed so far (the world holds nothing else at t = 0).
  const double cell = 2.0 * rmax;
  auto key = [cell](const Eigen::Vector3d& x, int dx, int dy, int dz) { return cell_key(x, cell, dx, dy, dz); };
  std::unordered_map<long long, std::vector<std::pair<Eigen::Vector3d, double>>> grid;
  auto clear = [&](const Eigen::Vector3d& x, double r) {
    const Eigen::Vector3d xc = cm.to_body(x), xm = mm.to_body(x);
    if (xc.z() > z_top_ + p_.feed.choke_height_m - r || xm.z() < inner_.z.front() + r) return false;
    if (!clear_of_liners(x, r)) return false;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = grid.find(key(x, dx, dy, dz));
          if (it == grid.end()) continue;
          for (const auto& [y, ry] : it->second)
            if ((x - y).squaredNorm() < (r + ry) * (r + ry)) return false;
        }
    return true;
  };
  const double dz = 0.2 * rock;
  std::vector<Eigen::Vector3d> xs;
  for (double zc = inner_.z.front() + 0.5 * rock; zc < z_top_ + p_.feed.choke_height_m; zc += dz) {
    const double r_in = inner_.radius_at(zc) + 0.3 * rock, r_out = outer_.radius_at(zc) - 0.3 * rock;
    if (r_out <= r_in) continue;
    const int tries = static_cast<int>(std::ceil(kPi * (r_in + r_out) / (0.1 * rock)));
    for (int k = 0; k < tries; ++k) {
      const int shape = static_cast<int>(rng_.uniform() * rocks_.size()) % static_cast<int>(rocks_.size());
      const double phi = 2 * kPi * rng_.uniform(), rr = r_in + (r_out - r_in) * rng_.uniform();
      const Eigen::Vector3d centre = cm.to_world({rr * std::cos(phi), rr * std::sin(phi), zc + dz * (rng_.uniform() - 0.5)});
      const Eigen::Quaterniond q = random_orientation();
      const auto& rk = rocks_[shape];
      xs.clear();
      bool ok = true;
      for (std::size_t i = 0; i < rk.size() && ok; ++i) {
        xs.push_back(centre + q * rk.positions[i]);
        ok = clear(xs.back(), rk.radii[i]);
      }
      if (!ok) continue;
      if (fed_kg_ + rock_mass_[shape] > limit) return;
      add_rock(shape, centre, q, Eigen::Vector3d::Zero());
      prefilled_kg_ += rock_mass_[shape];
      for (std::size_t i = 0; i < rk.size(); ++i) grid[key(xs[i], 0, 0, 0)].emplace_back(xs[i], rk.radii[i]);
    }
  }
}

// Choke feeding: keep the hopper zone above the chamber top filled, within the feeder's rate.
void ChamberDem::feed() {
  feed_credit_kg_ = std::min(feed_credit_kg_ + p_.feed.max_rate_kg_s * p_.bookkeeping_s, 4.0 * rock_mass_[0] + 1.0);
  const auto& P = world_->particles();
  const double z_lo = concave_origin_.z() + z_top_, z_hi = z_lo + p_.feed.choke_height_m;
  // Solid volume held in the choke zone versus the zone's annular volume at the feed radii.
  double solid = 0;
  for (std::size_t i = 0; i < P.size(); ++i)
    if (P.z[i] > z_lo && P.z[i] < z_hi + p_.feed.rock_size_m) solid += 4.0 / 3.0 * kPi * P.r[i] * P.r[i] * P.r[i];
  const double zone = kPi * r_feed_out_ * r_feed_out_ * (p_.feed.choke_height_m + p_.feed.rock_size_m);
  const double target = 0.35 * zone;  // a loose bed of rocks fills about a third of the zone
  int tries = 0;
  while (solid < target && fed_kg_ < p_.feed.max_fed_kg && tries < 12) {
    const int shape = static_cast<int>(rng_.uniform() * rocks_.size()) % static_cast<int>(rocks_.size());
    if (feed_credit_kg_ < rock_mass_[shape]) break;
    ++tries;
    const double phi = 2 * kPi * rng_.uniform();
    const double rr = std::sqrt(r_feed_in_ * r_feed_in_ + rng_.uniform() * (r_feed_out_ * r_feed_out_ - r_feed_in_ * r_feed_in_));
    const Eigen::Vector3d centre(concave_origin_.x() + rr * std::cos(phi), concave_origin_.y() + rr * std::sin(phi),
                                 z_hi + 1.2 * p_.feed.rock_size_m);
    if (place_rock(shape, centre, random_orientation())) {
      feed_credit_kg_ -= rock_mass_[shape];
      solid += rocks_[shape].solid_volume();
    }
  }
}

// Fragments whose centre has fallen below the chamber are screened and removed (section 4.1.3). Fragments
// outside the concave and hopper (spilled over the rim or thrown out) or far away are removed as lost:
// they never passed the discharge, so they are not product.
void ChamberDem::discharge() {
  const auto& P = world_->particles();
  if (P.size() == 0) return;
  const auto frags = dem::Fragments::from_bonds(P, world_->bonds());
  const double z_out = concave_origin_.z() + z_bottom_ - p_.discharge_below_m;
  const double far = 4.0 * (r_feed_out_ + p_.feed.rock_size_m) + 1.0;
  std::vector<uint64_t> remove;
  for (const auto& f : frags.info(P)) {
    const Eigen::Vector3d d = f.centre - concave_origin_;
    const double rho = std::hypot(d.x(), d.y());
    const bool outside = d.z() > outer_.z.front() && d.z() < outer_.z.back() && rho > outer_.radius_at(d.z()) + 1e-3;
    const bool lost = outside || rho > far || f.centre.z() < z_out - 5.0;
    if (f.centre.z() >= z_out && !lost) continue;
    const auto members = frags.members(f.label);
    remove.insert(remove.end(), members.begin(), members.end());
    if (lost) {
      lost_kg_ += f.mass;
      continue;
    }
    discharged_kg_ += f.mass;
    ++fragments_out_;
    discharge_log_.emplace_back(world_->time(), f.mass);
    double sieve = f.sieve_size;
    if (members.size() == 1) {  // a crushed sphere's fragment stands for a lump of its mass (metaparticle_crushing.hpp)
      const long i = world_->index_of(members.front());
      if (i >= 0) sieve = std::max(sieve, sieve * equivalent_diameter(P.m[i], rock_density_) / (2.0 * P.r[i]));
    }
    std::size_t k = std::lower_bound(p_.sieves_m.begin(), p_.sieves_m.end(), sieve * (1 - 1e-12)) -
                    p_.sieves_m.begin();
    screened_kg_[k] += f.mass;
  }
  if (!remove.empty()) world_->remove_particles_by_id(remove);
}

// Metaparticles pressed against a liner beyond their strength break (metaparticle_crushing.hpp): into four
// fragments that stay in the bed (crushing.fragments, while a fragment is at least min_fragment_m and its sphere
// keeps the stable step), else into fines that leave at once. Each removal compacts the particle arrays, so
// spheres found crushed within crushing.batch_s go together (flush: now, e.g. at the end of a coupling
// interval, so that no pending crush crosses a checkpoint).
void ChamberDem::crush_squeezed(bool flush) {
  const CrushingStrength strength(p_.crushing);
  for (int j = 0; j < engine_->parts(); ++j) {  // each part's owned particles: all their contacts are there
    focus(engine_->part(j));
    const auto& P = world_->particles();
    const std::vector<char>* owned = engine_->owned(j);
    const std::vector<const dem::MeshContact*> liners{mantle_, cap_, concave_, hopper_};
    if (p_.crushing.stress_criterion) world_->contact_stress(stress_);
    for (std::size_t i : p_.crushing.stress_criterion ? crushed_by_stress(P, stress_, liners, strength, rock_density_)
                                                      : crushed_particles(P, liners, strength, rock_density_)) {
      if (owned && !(*owned)[i]) continue;
      if (pending_crush_.empty()) first_crush_t_ = world_->time();
      pending_crush_.push_back(P.id[i]);
    }
  }
  focus(engine_->part(0));
  // The batch starts at the first crush found on any process.
  const double first = engine_->min(pending_crush_.empty() ? std::numeric_limits<double>::infinity() : first_crush_t_);
  if (std::isinf(first) || (!flush && time() - first < p_.crushing.batch_s - 1e-15)) return;
  std::sort(pending_crush_.begin(), pending_crush_.end());
  pending_crush_.erase(std::unique(pending_crush_.begin(), pending_crush_.end()), pending_crush_.end());
  // Where each crushed sphere presses a liner, from the part that owns it (the fragments' obstacles at birth).
  LinerPlanes planes;
  for (int j = 0; j < engine_->parts(); ++j) {
    focus(engine_->part(j));
    const auto& P = world_->particles();
    for (const auto* mc : {mantle_, cap_, concave_, hopper_})
      for (const auto& c : mc->contacts())
        if (contact_is_current(P, c) && std::binary_search(pending_crush_.begin(), pending_crush_.end(), c.particle_id))
          planes.push_back({c.particle_id, {c.point, c.normal}});
  }
  std::vector<uint64_t> ids;
  gather_crushed(pending_crush_, planes, ids);
  pending_crush_.clear();
  edit_whole([&] {
    harvest_breaks();
    crush(ids, planes);
    prune_growing();
  });
}

void ChamberDem::crush(const std::vector<uint64_t>& ids, const LinerPlanes& planes) {
  const auto& P = world_->particles();
  std::vector<std::size_t> idx;
  for (uint64_t id : ids) {
    const long i = world_->index_of(id);
    if (i >= 0) idx.push_back(static_cast<std::size_t>(i));
  }
  std::sort(idx.begin(), idx.end());
  if (idx.empty()) return;
  std::vector<char> remove(P.size(), 0);
  for (std::size_t i : idx) remove[i] = 1;
  // Intact bonds of a crushed metaparticle go with it: logged as breaks of their own kind.
  for (const auto& b : world_->bonds()) {
    if (!b.alive || !(remove[b.i] || remove[b.j])) continue;
    dem::BondBreak br;
    br.t = world_->time();
    br.x[0] = 0.5 * (P.x[b.i] + P.x[b.j]);
    br.x[1] = 0.5 * (P.y[b.i] + P.y[b.j]);
    br.x[2] = 0.5 * (P.z[b.i] + P.z[b.j]);
    br.id_i = P.id[b.i];
    br.id_j = P.id[b.j];
    br.crushed = true;
    breaks_.push_back(br);
    ++broken_total_;
  }
  struct Fragment {
    Eigen::Vector3d x, v, w;
    double r, rho, r_end;
  };
  std::vector<Fragment> born;
  double mass = 0;
  const bool grow = p_.crushing.fragment_growth_s > 0;
  // Which spheres break into fragments, with their tetrahedron turns drawn in batch order; then all are placed.
  std::vector<CrushedSphere> batch(idx.size());
  std::vector<double> r_end(idx.size()), rho_f(idx.size());
  for (std::size_t n = 0; n < idx.size(); ++n) {
    const std::size_t i = idx[n];
    batch[n].x = Eigen::Vector3d(P.x[i], P.y[i], P.z[i]);
    batch[n].r = P.r[i];
    const double r_f = fragment_radius(P.r[i]);
    rho_f[n] = 0.25 * P.m[i] / (4.0 / 3.0 * kPi * r_f * r_f * r_f);
    const double d_f = equivalent_diameter(P.m[i], rock_density_) / std::cbrt(4.0);  // a fragment's mass-equiv. size
    r_end[n] = grow ? std::max(r_f, 0.5 * d_f) : r_f;  // at the rock's density when grown
    // The Rayleigh step grows with r sqrt(rho): a heavy fragment is as stable as a rock sphere that much larger; a
    // growing one ends at the rock's density.
    const double stable_r = grow ? r_end[n] : r_f * std::sqrt(rho_f[n] / rock_density_);
    if (p_.crushing.fragments && d_f >= p_.crushing.min_fragment_m && stable_r >= fragment_min_radius_) {
      batch[n].turns.resize(kFragmentOrientations);
      for (auto& t : batch[n].turns) t = random_orientation().toRotationMatrix();
    }
  }
  if (p_.crushing.fragments) birth_obstacles(idx, remove, planes, batch);
  const auto placed_all = place_crushed_batch(batch, grow);
  for (std::size_t n = 0; n < idx.size(); ++n) {
    const std::size_t i = idx[n];
    if (!batch[n].turns.empty()) {
      const Eigen::Vector3d& x = batch[n].x;
      const Eigen::Vector3d v(P.vx[i], P.vy[i], P.vz[i]), w(P.wx[i], P.wy[i], P.wz[i]);
      const auto& placed = placed_all[n];
      deepest_birth_overlap_ = std::max(deepest_birth_overlap_, placed.deepest);
      for (int k = 0; k < 4; ++k) {
        const Eigen::Vector3d& o = placed.set.offset[k];
        const double rb = placed.birth_radius[k];
        if (rb < placed.set.radius) ++shrunk_at_birth_;
        born.push_back({x + o, v + w.cross(o), w, rb, rho_f[n] * std::pow(placed.set.radius / rb, 3), r_end[n]});
      }
      ++fragmented_count_;
      continue;
    }
    const double d = equivalent_diameter(P.m[i], rock_density_);
    const auto cls = progeny_by_class(P.m[i], d, p_.sieves_m, p_.crushing.progeny_exponent);
    crushed_kg_ += P.m[i];
    ++crushed_count_;
    if (fines_) {
      fines_->deposit(concave_->mesh().to_body(batch[n].x), to_flow_.map(cls));
      continue;
    }
    for (std::size_t k = 0; k < cls.size(); ++k) screened_kg_[k] += cls[k];
    mass += P.m[i];
  }
  if (mass > 0) {
    discharged_kg_ += mass;
    discharge_log_.emplace_back(world_->time(), mass);
  }
  world_->remove_particles(remove);
  for (const auto& f : born) {
    const std::size_t k = world_->add_particle(f.x.data(), f.r, kRock, f.rho, f.v.data(), f.w.data());
    if (f.r_end > f.r) growing_.push_back({P.id[k], f.r_end, (f.r_end - f.r) / p_.crushing.fragment_growth_s});
  }
}

void ChamberDem::birth_obstacles(const std::vector<std::size_t>& idx, const std::vector<char>& crushed,
                                 const LinerPlanes& planes, std::vector<CrushedSphere>& batch) const {
  const auto& P = world_->particles();
  if (idx.empty()) return;
  double r_max = 0;
  for (std::size_t j = 0; j < P.size(); ++j) r_max = std::max(r_max, P.r[j]);
  std::vector<long> slot(P.size(), -1);
  for (std::size_t n = 0; n < idx.size(); ++n) slot[idx[n]] = static_cast<long>(n);
  // Crushed spheres hashed by cells of 2 r_max (cell_key).
  const double cell = 2 * r_max;
  auto at = [&P](std::size_t i) { return Eigen::Vector3d(P.x[i], P.y[i], P.z[i]); };
  std::unordered_map<long long, std::vector<std::size_t>> grid;
  for (std::size_t n = 0; n < idx.size(); ++n) grid[cell_key(at(idx[n]), cell, 0, 0, 0)].push_back(n);
  for (std::size_t j = 0; j < P.size(); ++j) {
    const Eigen::Vector3d xj = at(j);
    for (int a = -1; a <= 1; ++a)
      for (int b = -1; b <= 1; ++b)
        for (int c = -1; c <= 1; ++c) {
          const auto it = grid.find(cell_key(xj, cell, a, b, c));
          if (it == grid.end()) continue;
          for (std::size_t n : it->second) {
            if (idx[n] == j || (xj - at(idx[n])).norm() >= P.r[idx[n]] + P.r[j]) continue;
            if (crushed[j])
              batch[n].crushed_neighbours.push_back(static_cast<std::size_t>(slot[j]));
            else
              batch[n].obstacles.push_back({xj, Eigen::Vector3d::Zero(), P.r[j]});
          }
        }
  }
  for (const auto& [id, plane] : planes) {
    const long i = world_->index_of(id);
    if (i >= 0 && slot[i] >= 0) batch[slot[i]].obstacles.push_back({plane.first, plane.second, 0.0});
  }
}

// Growing fragments (crush_squeezed) swell at constant mass by rate x h per step until their rock-density radius, in
// every part that holds them (owner and ghosts alike). A fragment no part here holds stays listed until the root's
// next edit (prune_growing): it may be on another process.
void ChamberDem::grow_fragments(double h) {
  std::size_t keep = 0;
  for (const Growing& g : growing_) {
    double r = -1;
    for (int j = 0; j < engine_->parts(); ++j) {
      dem::World& w = engine_->part(j);
      const long i = w.index_of(g.id);
      if (i < 0) continue;
      r = std::min(g.r_end, w.particles().r[i] + g.rate * h);
      if (r != w.particles().r[i]) w.set_radius(static_cast<std::size_t>(i), r);
    }
    if (r < 0 ? decomposed_ : r < g.r_end) growing_[keep++] = g;  // one World: absent = crushed again or discharged
  }
  growing_.resize(keep);
}

ProductState ChamberDem::product() const {
  ProductState s;
  s.sieve_m = p_.sieves_m;
  double cum = 0;
  for (std::size_t k = 0; k < p_.sieves_m.size(); ++k) {
    cum += screened_kg_[k];
    s.passing_pct.push_back(discharged_kg_ > 0 ? 100.0 * cum / discharged_kg_ : 0.0);
  }
  if (screened_kg_.back() > 0) {  // fragments above the largest sieve: report the top size too
    s.sieve_m.push_back(2.0 * p_.sieves_m.back());
    s.passing_pct.push_back(100.0);
  }
  s.fed_kg = fed_kg_;
  s.discharged_kg = discharged_kg_;
  s.lost_kg = lost_kg_;
  s.crushed_kg = crushed_kg_;
  s.metaparticles_crushed = crushed_count_;
  s.metaparticles_fragmented = fragmented_count_;
  std::vector<double> kg{0.0};  // per part, summed in part order, then over the processes (as DomainEngine::sum)
  for (int j = 0; j < engine_->parts(); ++j) {
    const auto& P = engine_->part(j).particles();
    const std::vector<char>* owned = engine_->owned(j);
    double part = 0;
    for (std::size_t i = 0; i < P.size(); ++i)
      if (!owned || (*owned)[i]) part += P.m[i];
    kg[0] = j == 0 ? part : kg[0] + part;
  }
  engine_->sum(kg);
  s.in_chamber_kg = kg[0];
  if (fines_) {
    s.fines_bed_kg = fines_->mass_kg() + fines_->untaken_kg();  // what left its bottom joins the discharge later
    s.in_chamber_kg += s.fines_bed_kg;
  }
  const double t = world_->time(), w = std::min(p_.throughput_window_s, t);
  double recent = 0;
  for (auto it = discharge_log_.rbegin(); it != discharge_log_.rend() && it->first > t - w; ++it) recent += it->second;
  s.throughput_kg_s = w > 0 ? recent / w : 0.0;
  s.fragments_discharged = fragments_out_;
  return s;
}

std::vector<dem::BondBreak> ChamberDem::take_breaks() {
  std::vector<dem::BondBreak> out;
  out.swap(breaks_);
  return out;
}

std::vector<int> ChamberDem::fragment_labels() const { return decomposed_ ? snapshot_labels_ : labels_of(*world_); }

std::vector<int> ChamberDem::labels_of(const dem::World& w) {
  const auto& P = w.particles();
  const auto frags = dem::Fragments::from_bonds(P, w.bonds());
  std::vector<int> out(P.size());
  for (std::size_t i = 0; i < P.size(); ++i) out[i] = frags.fragment_of(P.id[i]);
  return out;
}

double ChamberDem::rock_mass_kg(int shape) const { return rock_mass_.at(shape); }

}  // namespace coupling
