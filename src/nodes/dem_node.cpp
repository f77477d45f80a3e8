// dem_node: the ore as a bonded-particle DEM (coupling::ChamberDem) as a ROS node, the follower of the
// lockstep coupling. Parameters: ~config (path, required), ~out (dir for dem.bag and breaks.csv; scripts/crusher
// run merges dem.bag into mbd_node's run.bag with merge_bags), ~duration (s, overrides run.duration_s).
// Answers each /crusher/geometry_state with the time-averaged liner wrench for the same step, and publishes
// particles (markers, and /crusher/particle_state with fragment, velocity and force), liners, the concave force map
// and the screened product at run.tf_hz of sim time.
// ~resume (true): continue the run in ~out from the newest checkpoint both nodes wrote. With
// run.checkpoint_every_s > 0 the state is saved at the same coupling steps as mbd_node's, and the bag is
// written in segments dem.seg<step>.bag (scripts/crusher run joins them).
// While it advances a coupling step it publishes the step on /crusher/dem_heartbeat (std_msgs/UInt64) every
// heartbeat interval of wall time (a quarter of coupling.timeout_s, at most 1 s), from inside the DEM loop: mbd_node's
// timeout then bounds the DEM's silence, not the wall time of one step on a busy machine.
#include <inertia_crusher/ConcaveForceMap.h>
#include <inertia_crusher/GeometryState.h>
#include <inertia_crusher/GeometryWrench.h>
#include <inertia_crusher/ProductStream.h>
#include <std_msgs/UInt64.h>
#include <visualization_msgs/MarkerArray.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <fstream>
#include <memory>
#include <numeric>
#include <optional>
#include <sstream>
#include <thread>
#include <sys/stat.h>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <unistd.h>

#include "core/cli_args.hpp"
#include "core/run_config.hpp"
#include "coupling/chamber_dem.hpp"
#include "core/duration_text.hpp"
#include "core/heap_policy.hpp"
#include "core/openmp_wait.hpp"
#include "coupling/checkpoint_files.hpp"
#include "coupling/lockstep.hpp"
#include "mbd/mechanism_params.hpp"
#include "nodes/dem_node_cloud.hpp"
#include "nodes/dem_node_ranks.hpp"
#include "nodes/ros_common.hpp"
#include "nodes/ros_common_force_map.hpp"

namespace {

struct Config {
  core::RunOptions run;
  core::CouplingOptions coupling;
  coupling::ChamberParams chamber;
};

Config load_config(const std::string& path) {
  auto root = core::ConfigNode::load_file(path);
  Config c;
  c.run = core::load_run_options(root.child("run"));
  c.run.load = "dem";  // this node runs only in coupled runs (the config may name the fast load): run.coupled applies
  core::apply_coupled_overrides(c.run);
  c.coupling = core::load_coupling_options(root.child_or_empty("coupling"));
  auto mech = mbd::load_mechanism_params(root.child("mbd"));  // the liner geometry is the mechanism's
  const auto flow = root.child_or_empty("flow");  // the chamber flow model: dem.fines: flow carries the fines in it
  c.chamber = coupling::load_chamber_params(root.child("dem"), mech.chamber, mech.floating_cone.com_z_m,
                                            mech.fixed_cone.com_z_m, &flow);
  root.ignore("diagnosis");  // crusher diagnose's
  root.finish();
  return c;
}

coupling::BodyMotion motion(const geometry_msgs::Pose& pose, const geometry_msgs::Twist& tw) {
  coupling::BodyMotion b;
  nodes::from_pose(pose, &b.com, &b.orientation);
  b.velocity = nodes::from_msg(tw.linear);
  b.angular_velocity = nodes::from_msg(tw.angular);
  return b;
}

std_msgs::ColorRGBA colour_of(int label) {  // distinct, stable colours per fragment
  std_msgs::ColorRGBA c;
  const double h = std::fmod(label * 0.61803398875, 1.0) * 6.0;
  const double x = 1.0 - std::abs(std::fmod(h, 2.0) - 1.0);
  double r = 0, g = 0, b = 0;
  switch (static_cast<int>(h)) {
    case 0: r = 1, g = x; break;
    case 1: r = x, g = 1; break;
    case 2: g = 1, b = x; break;
    case 3: g = x, b = 1; break;
    case 4: r = x, b = 1; break;
    default: r = 1, b = x;
  }
  c.r = 0.25 + 0.75 * r;
  c.g = 0.25 + 0.75 * g;
  c.b = 0.25 + 0.75 * b;
  c.a = 1.0;
  return c;
}

// dem_node could not start: mbd_node, already waiting for its first answer, stops now instead of after
// coupling.first_timeout_s.
void tell_leader_early(ros::NodeHandle& nh, const std::string& why) {
  auto pub = nh.advertise<inertia_crusher::GeometryWrench>("/crusher/geometry_wrench", 10);
  const double until = nodes::wall_now() + 2.0;
  while (pub.getNumSubscribers() == 0 && nodes::wall_now() < until) ros::WallDuration(0.05).sleep();
  nodes::publish_stopped<inertia_crusher::GeometryWrench>(pub, "could not start: " + why, 0.0);
}

class DemNode {
 public:
  DemNode(ros::NodeHandle& nh, Config cfg, std::string out, bool resume)
      : cfg_(std::move(cfg)), out_(std::move(out)) {
    ros::NodeHandle pnh("~");
    force_scale_N_ = nodes::force_scale_N(pnh);
    ROS_INFO("dem_node: packing %d rock shapes...", cfg_.chamber.feed.shapes);
    if (!out_.empty()) cfg_.chamber.blowup_dump_path = out_ + "/dem_blowup.csv";  // a blow-up's state, in the run's folder
    dem_ = std::make_unique<coupling::ChamberDem>(cfg_.chamber);
    if (nodes::ranks() > 1) {
      nodes::decompose_over_ranks(*dem_);
      ROS_INFO("dem_node: the charge on %d MPI ranks (azimuthal sectors; ghosts within %.1f mm; feed, discharge and "
               "crushing on rank 0, which talks to mbd_node)", nodes::ranks(), 3e3 * dem_->largest_sphere_radius());
    }
    for (int k = 0; k < dem_->rock_shapes(); ++k) {
      ROS_INFO("dem_node: rock %d: %zu metaparticles, %.3f kg, packing density %.2f, spheres at %.0f kg/m^3", k,
               dem_->rock_particles(k), dem_->rock_mass_kg(k), dem_->packing_density(k), dem_->sphere_density(k));
    }
    ROS_INFO("dem_node: ready, DEM step %.3g s; OpenMP threads wait %s", dem_->dt(),
             core::openmp_wait_policy().c_str());
    const auto& cr = cfg_.chamber.crushing;
    if (cr.enabled && cr.fragments)
      ROS_INFO("dem_node: crushed spheres break into 4 fragments while these are >= %.1f mm (mass-equivalent) and "
               "their spheres stable at the step (as a rock sphere >= %.2f mm in radius); finer ones leave as fines",
               cr.min_fragment_m * 1e3, dem_->fragment_min_radius() * 1e3);
    if (cr.enabled && cr.size_exponent > 0)
      ROS_INFO("dem_node: crushing strength with size effect: %.2f MPa at %.0f mm, %.2f MPa at 10 mm (exponent %.2f)",
               cr.tensile_strength * 1e-6, cr.reference_size * 1e3,
               coupling::CrushingStrength(cr).sigma(0.01) * 1e-6, cr.size_exponent);
    pub_wrench_ = nh.advertise<inertia_crusher::GeometryWrench>("/crusher/geometry_wrench", 10);
    pub_heartbeat_ = nh.advertise<std_msgs::UInt64>("/crusher/dem_heartbeat", 10);
    beat_s_ = std::min(1.0, 0.25 * cfg_.coupling.timeout_s);
    dem_->set_progress_hook([this] { heartbeat(); });
    pub_particles_ = nh.advertise<visualization_msgs::MarkerArray>("/crusher/particles", 2, true);
    pub_state_ = nh.advertise<sensor_msgs::PointCloud2>("/crusher/particle_state", 2, true);
    pub_liners_ = nh.advertise<visualization_msgs::MarkerArray>("/crusher/liners", 2, true);
    pub_product_ = nh.advertise<inertia_crusher::ProductStream>("/crusher/product", 100, true);
    pub_map_ = nh.advertise<inertia_crusher::ConcaveForceMap>("/crusher/concave_forces", 100, true);
    pub_map_markers_ = nh.advertise<visualization_msgs::MarkerArray>("/crusher/concave_force_markers", 2, true);
    sub_ = nh.subscribe("/crusher/geometry_state", 100, &DemNode::on_state, this, ros::TransportHints().tcpNoDelay());
    ck_steps_ = cfg_.run.checkpoint_every_s > 0 && !out_.empty()
                    ? coupling::checkpoint_interval_steps(cfg_.run.checkpoint_every_s, cfg_.coupling.dt_s) : 0;
    if (cfg_.run.checkpoint_every_s > 0 && out_.empty())
      ROS_WARN("dem_node: no ~out: run.checkpoint_every_s is ignored (checkpoints go into the run's folder)");
    if (resume && out_.empty()) throw std::invalid_argument("~resume needs ~out, the run's folder");
    std::streamoff breaks_size = 0;
    if (resume) breaks_size = resume_from_checkpoint();
    log_estimate();  // after a resume: from the checkpoint's particles
    if (!out_.empty()) {
      if (!ck_steps_) {
        bag_.open(out_ + "/dem.bag");
      } else {
        if (!resume) {  // checkpoints and segments of an earlier run in ~out
          if (!coupling::checkpoint_steps(out_, "dem").empty())
            ROS_INFO("dem_node: a fresh run (no ~resume): removing the checkpoints of the earlier run in %s",
                     out_.c_str());
          coupling::remove_checkpoints_after(out_, "dem", 0);  // checkpoints are taken after step 0 only
        }
        coupling::remove_bag_segments_from(out_, "dem", resume_step_);
        bag_.reopen(coupling::bag_segment_path(out_, "dem", resume_step_));
      }
      const std::string bp = out_ + "/breaks.csv";
      if (resume) {  // the log as it was at the checkpoint, then appended
        struct stat st {};
        if (::stat(bp.c_str(), &st) != 0 || st.st_size < breaks_size)
          throw std::runtime_error("~resume: " + bp + " is missing or shorter than at the checkpoint (" +
                                   std::to_string(breaks_size) + " bytes): the run's folder is not the one checkpointed");
        if (::truncate(bp.c_str(), breaks_size) != 0)
          throw std::runtime_error("~resume: cannot truncate " + bp + ": " + std::strerror(errno));
        breaks_.open(bp, std::ios::app);
      } else {
        breaks_.open(bp);
        breaks_ << "t_s,x_m,y_m,z_m,mode,id_i,id_j,sigma_Pa,tau_Pa\n";
      }
    }
  }

  int run() {
    int status = 0;
    last_heard_ = nodes::wall_now();
    try {
      while (!finished_) {
        if (nodes::stop_requested()) {
          ROS_WARN("dem_node: %s; closing the bag (the run is incomplete)", nodes::stop_reason().c_str());
          status = nodes::stop_exit_status();
          break;
        }
        if (!ros::ok()) throw std::runtime_error(nodes::kShutdownFromOutside);
        nodes::wait_for_callbacks(0.01);
        if (error_) throw std::runtime_error(*error_);
        const double limit = requested_ ? cfg_.coupling.timeout_s : cfg_.coupling.first_timeout_s;
        if (nodes::wall_now() - last_heard_ > limit) {
          throw std::runtime_error("no geometry state from mbd_node for " + std::to_string(limit) +
                                   " s; is mbd_node running with run.load = dem on the same master?");
        }
      }
      // The end (or a stop between steps): the state before the next step, so that the run can be extended.
      // The final outputs below belong after the checkpoint (a resumed run rewrites them).
      if (ck_steps_ && follower_.last_answered() && *follower_.last_answered() + 1 != last_checkpoint_)
        checkpoint_and_rotate(*follower_.last_answered() + 1);
    } catch (const std::exception& e) {
      nodes::log_error(std::string("dem_node: ") + e.what() + "; stopping");
      status = 1;
      tell_leader(e.what());
    }
    if (status > 1) tell_leader(nodes::stop_reason());  // stopped by a signal
    try {  // the last sample; after a write error the bag and the break log take nothing more
      publish_outputs(true);
    } catch (const std::exception& e) {
      nodes::log_error(std::string("dem_node: ") + e.what());
      status = status ? status : 1;
    }
    bag_.close();  // a failure is logged by name
    if (!bag_.error().empty() && !status) status = 1;
    if (!write_trajectories() && !status) status = 1;
    const auto p = product();
    ROS_INFO("dem_node: %.3f s simulated, %zu particles, %ld broken bonds, fed %.2f kg, discharged %.2f kg; "
             "%.2f kg in %ld metaparticles crushed to fines (%.2f kg of them still in the chamber, dem.fines: flow), %ld crushed into "
             "fragments that stayed; %.1f %% of the wall time in coupling waits",
             dem_->time(), dem_->charge_particles().size(), dem_->broken_bonds(), p.fed_kg, p.discharged_kg,
             p.crushed_kg, p.metaparticles_crushed, p.fines_bed_kg, p.metaparticles_fragmented,
             100.0 * wait_s_ / std::max(1e-9, busy_s_ + wait_s_));
    if (const auto* f = dem_->fines()) {  // dem.fines: flow: the fines' own load over the run
      const auto& J = f->normal_impulse();
      ROS_INFO("dem_node: fines in the flow model: %.3f kg deposited, %.3f kg held, %.3f kg discharged, mean normal "
               "force on the liners %.2f kN over %.3f s", f->fed_kg(), f->mass_kg(), f->discharged_kg(),
               1e-3 * std::accumulate(J.begin(), J.end(), 0.0) / std::max(1e-12, dem_->time()), dem_->time());
    }
    if (p.metaparticles_fragmented > 0)
      ROS_INFO("dem_node: fragment birth (this process): deepest overlap %.2f of the smaller radius in the best "
               "orientation, %ld fragments born smaller to stay within %.2f", dem_->deepest_birth_overlap(),
               dem_->fragments_shrunk_at_birth(), coupling::kFragmentBirthOverlap);
    nodes::tell_ranks(nodes::RankCall::Stop);
    return status;
  }

  // Before it starts: the wall time at the full machine's measured rate (src/coupling/README.md: 8e6 particle-steps/s
  // on 2 cores) for the particles there are (resumed), or the pre-fill's when its mass is bounded (prefill_max_kg,
  // max_fed_kg); the progress lines' ETA then follows this run's own rate.
  void log_estimate() const {
    double n = static_cast<double>(dem_->charge_particles().size());
    const auto& feed = cfg_.chamber.feed;
    const double first_kg = std::min(feed.max_fed_kg, feed.prefill ? feed.prefill_max_kg : 0.0);
    if (n == 0 && feed.prefill && first_kg < 1e8) {  // the pre-fill comes with the first coupling step: its bound
      double kg = 0, count = 0;
      for (int k = 0; k < dem_->rock_shapes(); ++k) kg += dem_->rock_mass_kg(k), count += dem_->rock_particles(k);
      if (kg > 0) n = first_kg * count / kg;
    }
    if (n == 0) {
      ROS_INFO("dem_node: no particles yet (the pre-fill comes with the first coupling step): the progress lines give "
               "the wall time to expect");
      return;
    }
    const double steps = std::max(0.0, cfg_.run.duration_s - dem_->time()) / dem_->dt();
    const double threads = cfg_.chamber.threads > 0 ? cfg_.chamber.threads : std::thread::hardware_concurrency();
    ROS_INFO("dem_node: estimate %s of wall time for %.3f s simulated (%.0f particles now, %.3g DEM steps, at ~4e6 "
             "particle-steps/s per thread on %.0f threads); the progress lines' ETA follows the real rate",
             core::duration_text(n * steps / (4e6 * std::max(1.0, threads))).c_str(), cfg_.run.duration_s, n, steps,
             std::max(1.0, threads));
  }

 private:
  void on_state(const inertia_crusher::GeometryState::ConstPtr& g) {
    const double now = nodes::wall_now();
    wait_s_ += now - last_heard_;
    last_heard_ = now;
    requested_ = true;
    if (g->finished) {
      finished_ = true;
      return;
    }
    try {
      switch (follower_.on_request(g->step)) {
        case coupling::Follower::Action::Ignore:
          return;
        case coupling::Follower::Action::Resend:
          pub_wrench_.publish(last_);
          return;
        case coupling::Follower::Action::Advance:
          break;
      }
      if (ck_steps_ && g->step % ck_steps_ == 0 && g->step != last_checkpoint_) checkpoint_and_rotate(g->step);
      working_step_ = g->step;
      last_beat_ = nodes::wall_now();
      const auto mm = motion(g->mantle_pose, g->mantle_twist), mc = motion(g->concave_pose, g->concave_twist);
      nodes::tell_ranks_advance(mm, mc, g->dt);
      auto [wm, wc] = dem_->advance(mm, mc, g->dt);
      last_.header.stamp = ros::Time(g->time + g->dt);
      last_.header.frame_id = "world";
      last_.step = g->step;
      last_.time = g->time + g->dt;
      last_.mantle.force = nodes::to_msg(wm.force);
      last_.mantle.torque = nodes::to_msg(wm.torque);
      last_.concave.force = nodes::to_msg(wc.force);
      last_.concave.torque = nodes::to_msg(wc.torque);
      pub_wrench_.publish(last_);
      follower_.answered(g->step);
      bag_.write("/crusher/geometry_wrench", last_.header.stamp, last_);
      if (dem_->time() >= next_output_ - 1e-12) {
        publish_outputs(false);
        next_output_ += 1.0 / cfg_.run.tf_hz;
      }
      report_progress();
    } catch (const std::exception& e) {
      error_ = e.what();
    }
    const double done = nodes::wall_now();
    busy_s_ += done - now;
    last_heard_ = done;
  }

  // ChamberDem::product, on every rank of a decomposed run (the other ranks add their parts' mass).
  coupling::ProductState product() {
    nodes::tell_ranks(nodes::RankCall::Product);
    return dem_->product();
  }

  // Called after every DEM step of advance(): the step being worked on, to mbd_node, every beat_s_ of wall time.
  void heartbeat() {
    const double now = nodes::wall_now();
    if (now - last_beat_ < beat_s_) return;
    last_beat_ = now;
    std_msgs::UInt64 m;
    m.data = working_step_;
    pub_heartbeat_.publish(m);
  }

  // Trajectories of a few tracked particles (section 4.2.2, Figure 20), one row per bookkeeping sample.
  // False when the file could not be written (said by name).
  bool write_trajectories() {
    if (out_.empty()) return true;
    std::ostringstream f;
    f << "particle_id,t_s,x_m,y_m,z_m\n";
    for (const auto& p : dem_->trajectories())
      f << p.id << "," << p.t << "," << p.x.x() << "," << p.x.y() << "," << p.x.z() << "\n";
    const std::string err = nodes::write_file(out_ + "/trajectories.csv", f.str());
    if (!err.empty()) nodes::log_error("dem_node: " + err);
    return err.empty();
  }

  // Progress for the person waiting: sim time, percent, ETA, particles, broken bonds (every 5 s of wall time).
  void report_progress() {
    const double now = nodes::wall_now();
    if (start_wall_ == 0) start_wall_ = now, start_sim_ = dem_->time();  // a resumed run's ETA: from its start
    if (now < next_progress_) return;
    next_progress_ = now + 5.0;
    const double t = dem_->time(), T = cfg_.run.duration_s, el = now - start_wall_, done = t - start_sim_;
    const auto p = product();
    // The first line of a (resumed) run has no rate yet.
    const std::string eta = core::duration_text(done > 0 ? el * (T - t) / done : NAN);
    ROS_INFO("dem_node: t %.3f / %.3f s (%.0f %%), ETA %s, %zu particles, %ld broken bonds, fed %.1f kg, "
             "discharged %.2f kg (crushed %.2f kg; fines held %.2f kg, %.0f kN)", t, T, 100.0 * t / T, eta.c_str(),
             dem_->charge_particles().size(), dem_->broken_bonds(), p.fed_kg, p.discharged_kg, p.crushed_kg,
             p.fines_bed_kg, 1e-3 * dem_->fines_normal_force());
    if (!warned_squeeze_ && dem_->deepest_liner_overlap() > 0.25) {
      warned_squeeze_ = true;
      if (cfg_.chamber.crushing.enabled)
        ROS_WARN("dem_node: spheres pressed %.2f of their radius into the liners with crushing on, deeper than one "
                 "contact at F_c presses them (loads from several sides under the stress criterion, fragments still "
                 "growing, or crushing.batch_s); liner forces may be inflated", dem_->deepest_liner_overlap());
      else
        ROS_WARN("dem_node: spheres pressed %.2f of their radius into the liners: metaparticles too coarse for the "
                 "chamber's setting (each is a rigid sphere that cannot break; dem.crushing breaks them); liner "
                 "forces and power are inflated", dem_->deepest_liner_overlap());
    }
  }

  void publish_outputs(bool final_sample) {
    const ros::Time stamp(dem_->time());
    log_breaks();
    // Product stream.
    const auto p = product();
    inertia_crusher::ProductStream ps;
    ps.header.stamp = stamp;
    for (double s : p.sieve_m) ps.sieve_mm.push_back(s * 1e3);
    ps.passing_pct = p.passing_pct;
    ps.throughput_tph = p.throughput_kg_s * 3.6;
    ps.mass_discharged_kg = p.discharged_kg;
    ps.mass_fed_kg = p.fed_kg;
    ps.mass_in_chamber_kg = p.in_chamber_kg;
    ps.mass_lost_kg = p.lost_kg;
    ps.mass_crushed_kg = p.crushed_kg;
    ps.mass_fines_bed_kg = p.fines_bed_kg;
    pub_product_.publish(ps);
    bag_.write("/crusher/product", stamp, ps);
    // Concave force map (mean over the window since the last output).
    inertia_crusher::ConcaveForceMap fm;
    fm.header.stamp = stamp;
    fm.rings = cfg_.chamber.rings;
    fm.sectors = cfg_.chamber.sectors;
    fm.window_s = dem_->force_map_window_s();
    fm.mean_normal_force = dem_->force_map();
    dem_->reset_force_map();
    pub_map_.publish(fm);
    bag_.write("/crusher/concave_forces", stamp, fm);
    if (final_sample) return;
    auto map_markers = force_map_markers(stamp, fm.mean_normal_force);
    pub_map_markers_.publish(map_markers);
    bag_.write("/crusher/concave_force_markers", stamp, map_markers);
    const auto labels = dem_->fragment_labels();
    auto parts = particle_markers(stamp, labels);
    pub_particles_.publish(parts);
    bag_.write("/crusher/particles", stamp, parts);
    auto state = nodes::particle_cloud(stamp, dem_->charge_particles(), labels);
    pub_state_.publish(state);
    bag_.write("/crusher/particle_state", stamp, state);
    auto liners = liner_markers(stamp);
    pub_liners_.publish(liners);
    bag_.write("/crusher/liners", stamp, liners);
  }

  void log_breaks() {
    errno = 0;
    for (const auto& b : dem_->take_breaks()) {
      if (breaks_.is_open()) {
        const char* mode = b.crushed ? "crushed" : b.tensile ? "tensile" : "shear";
        breaks_ << b.t << "," << b.x[0] << "," << b.x[1] << "," << b.x[2] << "," << mode
                << "," << b.id_i << "," << b.id_j << "," << b.sigma << "," << b.tau << "\n";
      }
    }
    check_breaks_log();
  }

  // A write error in breaks.csv: the log is closed (it takes nothing more) and the error thrown, once.
  void check_breaks_log() {
    if (!breaks_.is_open() || breaks_.good()) return;
    const int err = errno;
    breaks_.close();
    throw nodes::WriteError(nodes::write_error_text(out_ + "/breaks.csv", "the break log", err));
  }

  // SPHERE_LIST per radius bin (a marker has one scale), coloured by fragment.
  visualization_msgs::MarkerArray particle_markers(const ros::Time& stamp, const std::vector<int>& labels) {
    const auto& P = dem_->charge_particles();
    constexpr int kBins = 6;
    double rmin = 1e9, rmax = 0;
    for (double r : P.r) rmin = std::min(rmin, r), rmax = std::max(rmax, r);
    visualization_msgs::MarkerArray arr;
    for (int b = 0; b < kBins; ++b) {
      visualization_msgs::Marker m;
      m.header.stamp = stamp;
      m.header.frame_id = "world";
      m.ns = "particles";
      m.id = b;
      m.type = visualization_msgs::Marker::SPHERE_LIST;
      m.action = visualization_msgs::Marker::ADD;
      m.pose.orientation.w = 1;
      const double r_b = rmin + (b + 0.5) * (rmax - rmin) / kBins;
      m.scale.x = m.scale.y = m.scale.z = 2 * (P.size() ? r_b : 0.001);
      m.color.a = 1;
      arr.markers.push_back(m);
    }
    for (std::size_t i = 0; i < P.size(); ++i) {
      int b = rmax > rmin ? std::min(kBins - 1, static_cast<int>((P.r[i] - rmin) / (rmax - rmin) * kBins)) : 0;
      arr.markers[b].points.push_back(nodes::to_point({P.x[i], P.y[i], P.z[i]}));
      arr.markers[b].colors.push_back(colour_of(labels[i]));
    }
    for (auto& m : arr.markers)
      if (m.points.empty()) m.action = visualization_msgs::Marker::DELETE;
    return arr;
  }

  // One sphere per concave area P_{ring,sector} at its centre, on the fixed scale ~force_scale_kN, with its legend.
  visualization_msgs::MarkerArray force_map_markers(const ros::Time& stamp, const std::vector<double>& force) {
    const auto& mesh = dem_->concave().mesh();
    const auto* regions = dem_->concave().regions();
    std::vector<Eigen::Vector3d> centre(force.size(), Eigen::Vector3d::Zero());
    std::vector<int> count(force.size(), 0);
    for (std::size_t t = 0; t < mesh.num_triangles(); ++t) {
      int r = regions->region_of(static_cast<int>(t));
      if (r < 0) continue;
      centre[r] += mesh.to_world(mesh.centroid(static_cast<int>(t)));
      ++count[r];
    }
    std::vector<Eigen::Vector3d> at;
    std::vector<double> f;
    for (std::size_t r = 0; r < force.size(); ++r)
      if (count[r]) at.push_back(centre[r] / count[r]), f.push_back(force[r]);
    return nodes::force_map_markers(stamp, at, f, force_scale_N_);
  }

  visualization_msgs::MarkerArray liner_markers(const ros::Time& stamp) {
    visualization_msgs::MarkerArray arr;
    int id = 0;
    for (const dem::MeshContact* mc : {&dem_->mantle(), &dem_->mantle_cap(), &dem_->concave(), &dem_->hopper()}) {
      const bool moving = mc == &dem_->mantle() || mc == &dem_->mantle_cap();
      visualization_msgs::Marker m;
      m.header.stamp = stamp;
      m.header.frame_id = "world";
      m.ns = mc->mesh().name();
      m.id = id++;
      m.type = visualization_msgs::Marker::TRIANGLE_LIST;
      m.pose.orientation.w = 1;
      m.scale.x = m.scale.y = m.scale.z = 1;
      m.color.r = moving ? 0.75 : 0.55;
      m.color.g = moving ? 0.55 : 0.6;
      m.color.b = moving ? 0.3 : 0.7;
      m.color.a = moving ? 1.0 : 0.35;
      const auto& wv = mc->mesh().world_vertices();
      for (const auto& tri : mc->mesh().triangles()) {
        for (int k : tri) {
          m.points.push_back(nodes::to_point(wv[k]));
        }
      }
      arr.markers.push_back(m);
    }
    return arr;
  }

  // mbd_node waits for each answer: tell it the run is over instead of leaving it to time out.
  void tell_leader(const std::string& why) {
    nodes::publish_stopped<inertia_crusher::GeometryWrench>(pub_wrench_, why, dem_->time());
  }

  // ---- checkpoints: the DEM state at the start of coupling step k, with what this node adds to it
  // Checkpoint at step k, then a new bag segment from it.
  void checkpoint_and_rotate(std::uint64_t k) {
    bag_.close_or_throw();  // as mbd_node: a checkpoint never follows a segment that is not whole
    write_checkpoint(k);
    bag_.open(coupling::bag_segment_path(out_, "dem", k));
  }

  void write_checkpoint(std::uint64_t k) {
    const double w0 = nodes::wall_now();
    errno = 0;
    breaks_.flush();
    check_breaks_log();  // the checkpoint must not name a length the log does not have
    const std::streamoff breaks_size = breaks_.is_open() ? static_cast<std::streamoff>(breaks_.tellp()) : 0;
    coupling::write_checkpoint(out_, {"dem", k, dem_->time()}, [&](core::BinaryWriter& w) {
      nodes::tell_ranks(nodes::RankCall::Save);
      dem_->save_state(w);
      w.tag("NODE");
      w.put(next_output_);
      w.put<int64_t>(breaks_size);
    });
    last_checkpoint_ = k;
    ROS_INFO("dem_node: checkpoint at step %llu (t = %.4f s, %zu particles) in %.2f s",
             static_cast<unsigned long long>(k), dem_->time(), dem_->charge_particles().size(),
             nodes::wall_now() - w0);
  }

  // Returns the break log's length at the checkpoint.
  std::streamoff resume_from_checkpoint() {
    std::vector<std::string> damaged;
    const uint64_t k = coupling::resume_step(out_, &damaged);
    for (const auto& d : damaged) ROS_WARN("%s: %s", "dem_node", d.c_str());
    std::streamoff breaks_size = 0;
    auto h = coupling::read_checkpoint(out_, "dem", k, [&](core::BinaryReader& r) {
      nodes::tell_ranks(nodes::RankCall::Load);
      dem_->load_state(r);
      r.expect("NODE");
      r.get(next_output_);
      breaks_size = r.get<int64_t>();
    });
    follower_.resume_at(k);
    resume_step_ = last_checkpoint_ = k;
    coupling::remove_checkpoints_after(out_, "dem", k);
    ROS_INFO("dem_node: resumed from the checkpoint at step %llu (t = %.4f s, %zu particles)",
             static_cast<unsigned long long>(k), h.time, dem_->charge_particles().size());
    return breaks_size;
  }

  Config cfg_;
  std::string out_;
  long ck_steps_ = 0;  // coupling steps per checkpoint (0: off)
  std::uint64_t last_checkpoint_ = 0, resume_step_ = 0;
  std::unique_ptr<coupling::ChamberDem> dem_;
  coupling::Follower follower_;
  ros::Publisher pub_heartbeat_;
  std::uint64_t working_step_ = 0;  // the coupling step advance() works on (heartbeat)
  double last_beat_ = 0, beat_s_ = 1.0;
  ros::Publisher pub_wrench_, pub_particles_, pub_state_, pub_liners_, pub_product_, pub_map_, pub_map_markers_;
  ros::Subscriber sub_;
  nodes::BagRecorder bag_;
  std::ofstream breaks_;
  inertia_crusher::GeometryWrench last_;
  std::optional<std::string> error_;
  bool finished_ = false;
  bool requested_ = false;  // a geometry state has arrived (until then the first-answer timeout applies)
  bool warned_squeeze_ = false;
  double force_scale_N_ = 20e3;  // the force map's red (~force_scale_kN)
  double start_sim_ = 0;
  double last_heard_ = 0, next_output_ = 0, wait_s_ = 0, busy_s_ = 0, start_wall_ = 0, next_progress_ = 0;
};

}  // namespace

int run_node(int argc, char** argv);

// A rank other than 0 of an MPI run: no ROS; the config from the same arguments (_config:=, _out:=); steps its part
// of the charge as rank 0 tells it. Stop signals are rank 0's to act on (it closes its bag, then tells the ranks).
int follow_on_rank(int argc, char** argv) {
  std::signal(SIGINT, SIG_IGN);
  std::signal(SIGTERM, SIG_IGN);
  std::string config_path, out;
  for (int k = 1; k < argc; ++k) {
    const std::string a = argv[k];
    if (a.rfind("_config:=", 0) == 0) config_path = a.substr(9);
    if (a.rfind("_out:=", 0) == 0) out = a.substr(6);
  }
  try {
    Config cfg = load_config(config_path);
    if (!out.empty()) cfg.chamber.blowup_dump_path = out + "/dem_blowup.rank" + std::to_string(nodes::rank()) + ".csv";
    coupling::ChamberDem dem(cfg.chamber);
    nodes::decompose_over_ranks(dem);
    const int status = nodes::follow_rank0(dem);
    nodes::finish_ranks();
    return status;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dem_node rank %d: %s; stopping every rank\n", nodes::rank(), e.what());
    nodes::abort_ranks(2);
  }
}

int main(int argc, char** argv) {
  core::prefer_passive_openmp_wait(argv);  // a shared machine: the DEM's threads sleep while they wait
  core::keep_freed_heap();                 // a decomposed charge's edits rebuild large buffers each time
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress lines reach a redirected log as they are written
  if (nodes::launched_by_mpirun()) {
    nodes::init_ranks(&argc, &argv);
    if (nodes::rank() > 0) return follow_on_rank(argc, argv);
  }
  const int status = run_node(argc, argv);
  if (nodes::ranks() > 1 && status == 2) nodes::abort_ranks(2);  // set-up failed: the ranks wait for a call
  nodes::finish_ranks();
  return status;
}

int run_node(int argc, char** argv) {
  ros::init(argc, argv, "dem_node", ros::init_options::NoSigintHandler);
  nodes::install_stop_handler();
  ros::NodeHandle nh, pnh("~");
  const std::string config_path = nodes::param_or(pnh, "config", std::string());
  const std::string out = nodes::param_or(pnh, "out", std::string());
  if (config_path.empty()) {
    std::fprintf(stderr, "dem_node: parameter ~config is missing; usage: rosrun inertia_crusher dem_node "
                         "_config:=launch_free_configs/quick_demo.yaml [_out:=DIR]\n");
    return 2;
  }
  Config cfg;
  double duration = -1;  // s; as mbd_node's, for progress and ETA
  try {
    if (const auto d = nodes::param_text(pnh, "duration")) duration = core::checked_duration("parameter ~duration", *d);
    cfg = load_config(config_path);
  } catch (const std::exception& e) {  // mbd_node, waiting for the first answer, stops now instead of timing out
    std::fprintf(stderr, "dem_node: %s\n", e.what());
    tell_leader_early(nh, e.what());
    return 2;
  }
  if (duration > 0) cfg.run.duration_s = duration;
  if (!out.empty()) ::mkdir(out.c_str(), 0755);
  try {
    bool resume = false;
    if (!nodes::bool_param(pnh, "resume", &resume)) {
      std::fprintf(stderr, "dem_node: parameter ~resume is not accepted; accepted: true, false\n");
      return 2;
    }
    DemNode node(nh, std::move(cfg), out, resume);
    nodes::mark_running();
    return node.run();
  } catch (const std::exception& e) {  // set-up failed (e.g. a checkpoint that does not fit): tell mbd_node
    std::fprintf(stderr, "dem_node: %s\n", e.what());
    tell_leader_early(nh, e.what());
    return 2;
  }
}
