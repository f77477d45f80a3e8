// mbd_node: the crusher mechanism (src/mbd) as a ROS node. Parameters in, topics and a bag out.
//   ~config (path, required), ~out (dir for run.bag and summary.json), ~load (none|bed|flow|dem), ~duration (s),
//   ~max_rtf (at most this many times real time, e.g. 1 to watch in rviz; 0 = as fast as possible),
//   ~resume (true: continue a coupled (dem) or fast (flow) run in ~out from its newest checkpoint, see
//   coupling/checkpoint_files.hpp)
// With run.checkpoint_every_s > 0 in a coupled or fast run the state is saved every so many simulated seconds and at
// the end (also when stopped by a signal), and the bag is written in segments run.seg<step>.bag, one per checkpoint
// interval (scripts/crusher run joins them into run.bag). A fast run's checkpoint holds the mechanism, the flow model
// and what the node's outputs depend on (samples, product window, throughput history): the resumed run is the
// uninterrupted one bit for bit.
// Sim time: this node is the clock (/clock). In `dem` load mode it leads the lockstep coupling.
#include <inertia_crusher/DriveState.h>
#include <inertia_crusher/GeometryState.h>
#include <inertia_crusher/GeometryWrench.h>
#include <inertia_crusher/ProductStream.h>
#include <inertia_crusher/TestPoint.h>
#include <rosgraph_msgs/Clock.h>
#include <std_msgs/UInt64.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <memory>
#include <optional>
#include <sys/stat.h>

#include "analysis/run_metrics.hpp"
#include "chamber/flow_config.hpp"
#include "chamber/flow_load.hpp"
#include "core/cli_args.hpp"
#include "core/run_config.hpp"
#include "coupling/checkpoint_files.hpp"
#include "coupling/lockstep.hpp"
#include "mbd/mechanism.hpp"
#include "mbd/mechanism_params.hpp"
#include "mbd/power_partition.hpp"
#include "nodes/mbd_node_flow.hpp"
#include "nodes/ros_common.hpp"

namespace {

using mbd::BodyId;
using nodes::to_msg;

const BodyId kBodies[] = {BodyId::FixedCone, BodyId::FloatingCone, BodyId::Vibrator,
                          BodyId::GlobeBearing, BodyId::ConnectingShaft, BodyId::DriveShaft};

struct Config {
  core::RunOptions run;
  core::CouplingOptions coupling;
  mbd::MechanismParams mech;
  chamber::FlowParams flow;  // run.load flow: the chamber flow model (the `flow:` section)
};

Config load_config(const std::string& path, const std::string& load_override, double duration_override) {
  auto root = core::ConfigNode::load_file(path);
  Config c;
  c.run = core::load_run_options(root.child("run"));
  c.coupling = core::load_coupling_options(root.child_or_empty("coupling"));
  c.mech = mbd::load_mechanism_params(root.child("mbd"));
  c.flow = chamber::load_flow_params(root.child_or_empty("flow"));  // checked in every mode
  root.ignore("dem");  // read by dem_node
  root.ignore("diagnosis");  // crusher diagnose's uncertain values
  root.finish();
  if (!load_override.empty()) {
    if (load_override != "none" && load_override != "bed" && load_override != "flow" && load_override != "dem")
      throw core::ConfigError("parameter ~load: '" + load_override +
                              "' is not accepted; accepted: none, bed, flow, dem");
    c.run.load = load_override;
  }
  if (c.run.load == "flow") chamber::FlowModel(c.flow, c.mech.chamber.mantle, c.mech.chamber.concave);  // checks
  if (duration_override > 0) c.run.duration_s = duration_override;
  core::apply_coupled_overrides(c.run);
  mbd::validate(c.mech, c.run.load == "bed");
  if (c.run.load == "dem") core::coupling_steps(c.coupling.dt_s, c.mech.dt_s);  // throws if not whole steps
  return c;
}

class MbdNode {
 public:
  MbdNode(ros::NodeHandle& nh, Config cfg, std::string out_dir, std::string config_path, double max_rtf, bool resume)
      : cfg_(std::move(cfg)), out_(std::move(out_dir)), config_path_(std::move(config_path)), max_rtf_(max_rtf),
        leader_({cfg_.coupling.timeout_s, 0.5, cfg_.coupling.first_timeout_s}) {
    // In `dem` mode the particles are the load; `bed` is the equivalent material-bed model; `none` idles.
    mech_ = std::make_unique<mbd::Mechanism>(cfg_.mech, cfg_.run.load == "bed" ? mbd::LoadModel::Bed
                                                                                : mbd::LoadModel::None);
    const bool coupled = cfg_.run.load == "dem", checkpointed = coupled || cfg_.run.load == "flow";
    // A checkpoint step: a coupling step (coupled), a mechanism step (flow).
    ck_steps_ = checkpointed && cfg_.run.checkpoint_every_s > 0 && !out_.empty()
                    ? coupling::checkpoint_interval_steps(cfg_.run.checkpoint_every_s,
                                                          coupled ? cfg_.coupling.dt_s : cfg_.mech.dt_s)
                    : 0;
    if (checkpointed && cfg_.run.checkpoint_every_s > 0 && out_.empty())
      ROS_WARN("mbd_node: no ~out: run.checkpoint_every_s is ignored (checkpoints go into the run's folder)");
    if (cfg_.run.load == "flow") {
      flow_ = std::make_unique<chamber::FlowLoad>(cfg_.flow, cfg_.mech);
      flow_out_ = std::make_unique<nodes::FlowOutputs>(nh, cfg_.mech);
    }
    if (resume) {
      if (!checkpointed || out_.empty() || !ck_steps_)
        throw std::invalid_argument("~resume needs a coupled (run.load dem) or fast (flow) run with "
                                    "run.checkpoint_every_s > 0 and ~out, the run's folder");
      resume_from_checkpoint();
    } else if (cfg_.run.warm_start_s > 0) {  // before any topic: the run's clock starts after it
      mech_->warm_start(cfg_.run.warm_start_s, cfg_.run.load == "bed" ? mbd::LoadModel::Bed : mbd::LoadModel::None);
      ROS_INFO("mbd_node: warm start, %.2f s of the mechanism alone before t = 0", cfg_.run.warm_start_s);
    }
    pub_clock_ = nh.advertise<rosgraph_msgs::Clock>("/clock", 10);
    pub_tp_ = nh.advertise<inertia_crusher::TestPoint>("/crusher/test_point", 1000);
    pub_drive_ = nh.advertise<inertia_crusher::DriveState>("/crusher/drive", 1000);
    pub_tf_ = nh.advertise<tf2_msgs::TFMessage>("/tf", 100);
    pub_geom_ = nh.advertise<inertia_crusher::GeometryState>("/crusher/geometry_state", 10);
    if (cfg_.run.load == "dem") {
      sub_wrench_ = nh.subscribe("/crusher/geometry_wrench", 10, &MbdNode::on_wrench, this,
                                 ros::TransportHints().tcpNoDelay());
      sub_product_ = nh.subscribe("/crusher/product", 100, &MbdNode::on_product, this);
      // dem_node's heartbeat while it works on a step: the timeout bounds its silence (coupling::Leader::alive)
      sub_heartbeat_ = nh.subscribe<std_msgs::UInt64>(
          "/crusher/dem_heartbeat", 10,
          [this](const std_msgs::UInt64::ConstPtr& m) { leader_.alive(m->data, nodes::wall_now()); });
    }
    if (!out_.empty()) {
      if (!ck_steps_) {
        bag_.open(out_ + "/run.bag");
      } else {
        if (!resume) clear_own_files();
        coupling::remove_bag_segments_from(out_, "run", resume_step_);  // written after the checkpoint
        bag_.reopen(coupling::bag_segment_path(out_, "run", resume_step_));
      }
    }
  }

  // Runs to the end (or until stopped); returns the exit status.
  int run() {
    const double t0 = nodes::wall_now();
    wall_start_ = t0;
    const auto flows0 = mech_->flows();
    const double sim0 = mech_->time();
    int status = 0;
    try {
      loop();
      // The end: a resumed run extends it (what follows, the last product, belongs after the checkpoint).
      if (ck_steps_ && step_index() != last_checkpoint_) checkpoint_and_rotate();
      if (!stopped_.empty()) status = nodes::stop_requested() ? nodes::stop_exit_status() : 1;
    } catch (const std::exception& e) {
      char t[32];
      std::snprintf(t, sizeof t, "%.4f", mech_->time());
      nodes::log_error(std::string("mbd_node: ") + e.what() + " (t = " + t + " s); stopping");
      const bool write_error = dynamic_cast<const nodes::WriteError*>(&e) != nullptr;
      status = nodes::stop_requested() && peer_stopped_.empty() && !write_error ? nodes::stop_exit_status() : 1;
      stopped_ = e.what();
      // Stopped while waiting for an answer (a signal, or dem_node stopped): the mechanism has not moved since
      // it asked for that step, so its state is the one at the step dem_node checkpoints when it stops. Not after a
      // write error: the bag segment since the last checkpoint is broken, and a resume from that checkpoint
      // rewrites it.
      if (ck_steps_ && waiting_ && !write_error && step_index() != last_checkpoint_) {
        try {
          checkpoint_and_rotate();
        } catch (const std::exception& e2) {
          ROS_ERROR("mbd_node: final checkpoint failed: %s", e2.what());
        }
      }
    }
    wall_s_ = nodes::wall_now() - t0;
    if (mech_->time() > sim0)
      ROS_INFO("mbd_node: power, t = %.3f-%.3f s: %s", sim0, mech_->time(),
               mbd::describe(mbd::power_partition(flows0, sim0, mech_->flows(), mech_->time())).c_str());
    finish(status);
    return status;
  }

 private:
  void loop() {
    const double dt = cfg_.mech.dt_s;
    const double t_end = cfg_.run.duration_s;
    const double pub_dt = 1.0 / cfg_.run.publish_hz, tf_dt = 1.0 / cfg_.run.tf_hz;
    const bool coupled = cfg_.run.load == "dem";
    const long steps_per_coupling = coupled ? core::coupling_steps(cfg_.coupling.dt_s, dt) : 1;
    // Samples at t = k / publish_hz, k >= 1 (a bag cannot hold time 0, and sim time 0 means 'no clock yet').
    if (next_pub_ == 0) next_pub_ = pub_dt, next_tf_ = tf_dt;  // a resumed run has them from its checkpoint
    double next_progress = 0;
    while (mech_->time() < t_end - 0.5 * dt) {
      if (nodes::stop_requested() || !ros::ok()) {
        stopped_ = nodes::stop_requested() ? nodes::stop_reason() : nodes::kShutdownFromOutside;
        ROS_WARN("mbd_node: %s at t = %.4f s; closing the bag (the run is incomplete)", stopped_.c_str(), mech_->time());
        break;
      }
      if (ck_steps_ && step_index() % ck_steps_ == 0 && step_index() != last_checkpoint_) checkpoint_and_rotate();
      if (coupled) exchange(steps_per_coupling * dt);
      for (long i = 0; i < steps_per_coupling; ++i) {
        if (flow_) {  // the summary's product window opens at the settle time (t = 0 when settle_s is 0)
          if (!flow_window_ && mech_->time() >= cfg_.run.settle_s - 0.5 * dt)
            flow_window_ = chamber::snapshot(flow_->model(), mech_->time());
          flow_->step(*mech_);
          ++flow_steps_;
        } else {
          mech_->step();
        }
        check_finite();
        const double t = mech_->time();
        if (t >= next_pub_ - 1e-9) {
          bool with_tf = t >= next_tf_ - 1e-9;
          publish_samples(with_tf);
          next_pub_ += pub_dt;
          if (with_tf) next_tf_ += tf_dt;
          if (max_rtf_ > 0) {
            double ahead = t / max_rtf_ - (nodes::wall_now() - wall_start_);
            if (ahead > 0) ros::WallDuration(ahead).sleep();
          }
        }
      }
      if (mech_->time() >= next_progress) {
        ROS_INFO_THROTTLE(5.0, "mbd_node: t = %.2f / %.2f s", mech_->time(), t_end);
        next_progress += 1.0;
      }
    }
  }

  // Lockstep: send liner poses for this step, wait for the DEM's time-averaged wrench, apply it.
  void exchange(double coupling_dt) {
    std::uint64_t step = leader_.request(nodes::wall_now());
    send_geometry(step, coupling_dt);
    waiting_ = true;
    while (leader_.pending()) {
      nodes::wait_for_callbacks(0.01);
      if (!leader_.pending()) break;
      const double now = nodes::wall_now();
      if (!peer_stopped_.empty()) throw std::runtime_error("dem_node has stopped: " + peer_stopped_);
      if (!ros::ok()) throw std::runtime_error(std::string(nodes::kShutdownFromOutside) + " while waiting for dem_node");
      // A stop while the DEM works on this step: let it finish the step (it stops between steps), apply it, and
      // stop at the top of the loop, so both nodes checkpoint the same step. Before its first answer (it may still
      // be packing) or when it does not answer within kStopGrace_s, stop now.
      if (nodes::stop_requested()) {
        if (!answered_any_) throw std::runtime_error(nodes::stop_reason() + " while waiting for dem_node's first answer");
        if (stop_noted_ == 0) {
          stop_noted_ = now;
          ROS_WARN("mbd_node: stopping after the step dem_node is working on");
        } else if (now - stop_noted_ > kStopGrace_s) {
          throw std::runtime_error(nodes::stop_reason() + "; dem_node did not finish its step within " +
                                   std::to_string(static_cast<int>(kStopGrace_s)) + " s");
        }
      }
      leader_.check_timeout(now);
      if (leader_.should_resend(now)) send_geometry(step, coupling_dt);
    }
    waiting_ = false;
    // The bag holds each completed step's state once (resends are not new samples). Recorded only now: a run
    // stopped while waiting checkpoints at this step, and its resume sends and records it again.
    bag_.write("/crusher/geometry_state", geom_sent_.header.stamp, geom_sent_);
    mech_->set_particle_wrench(BodyId::FloatingCone, wrench_.mantle_force, wrench_.mantle_torque);
    mech_->set_particle_wrench(BodyId::FixedCone, wrench_.concave_force, wrench_.concave_torque);
  }

  void send_geometry(std::uint64_t step, double coupling_dt) {
    inertia_crusher::GeometryState g;
    g.header.stamp = ros::Time(mech_->time());
    g.header.frame_id = "world";
    g.step = step;
    g.time = mech_->time();
    g.dt = coupling_dt;
    auto m = mech_->body(BodyId::FloatingCone), c = mech_->body(BodyId::FixedCone);
    g.mantle_pose = nodes::to_pose(m.position, m.orientation);
    g.mantle_twist = nodes::to_twist(m.linear_velocity, m.angular_velocity);
    g.concave_pose = nodes::to_pose(c.position, c.orientation);
    g.concave_twist = nodes::to_twist(c.linear_velocity, c.angular_velocity);
    pub_geom_.publish(g);
    geom_sent_ = g;  // recorded once the step is answered (exchange)
  }

  void on_wrench(const inertia_crusher::GeometryWrench::ConstPtr& w) {
    if (!w->stopped.empty()) {
      peer_stopped_ = w->stopped;
      return;
    }
    if (!leader_.answer(w->step, nodes::wall_now())) return;  // a duplicate of an answered step
    answered_any_ = true;
    wrench_.mantle_force = nodes::from_msg(w->mantle.force);
    wrench_.mantle_torque = nodes::from_msg(w->mantle.torque);
    wrench_.concave_force = nodes::from_msg(w->concave.force);
    wrench_.concave_torque = nodes::from_msg(w->concave.torque);
    bag_.write("/crusher/geometry_wrench", ros::Time(mech_->time()), *w);
  }

  // The DEM's screened product (cumulative): the latest one goes into summary.json.
  void on_product(const inertia_crusher::ProductStream::ConstPtr& p) {
    analysis::ProductSummary s;
    s.throughput_tph = p->throughput_tph;
    s.mass_discharged_kg = p->mass_discharged_kg;
    s.mass_lost_kg = p->mass_lost_kg;
    s.mass_crushed_kg = p->mass_crushed_kg;
    s.sieve_mm = p->sieve_mm;
    s.passing_pct = p->passing_pct;
    product_ = s;
    bag_.write("/crusher/product", p->header.stamp, *p);
  }

  // Tells the DEM the run is over (it closes its bag and exits).
  void send_finished() {
    inertia_crusher::GeometryState g;
    g.header.stamp = ros::Time(mech_->time());
    g.time = mech_->time();
    g.finished = true;
    for (int i = 0; i < 5; ++i) {
      pub_geom_.publish(g);
      ros::WallDuration(0.05).sleep();
    }
  }

  void check_finite() {
    for (auto id : kBodies) {
      auto b = mech_->body(id);
      if (!b.position.allFinite() || !b.linear_velocity.allFinite()) {
        throw std::runtime_error(std::string("numerical blow-up: body ") + mbd::body_name(id) + " has a non-finite state at step " +
                                 std::to_string(std::lround(mech_->time() / cfg_.mech.dt_s)));
      }
    }
  }

  void publish_samples(bool with_tf) {
    const ros::Time stamp(mech_->time());
    if (with_tf) {  // sim time ticks with /tf: every /clock wakes each node's time subscription (this one's too)
      rosgraph_msgs::Clock clk;
      clk.clock = stamp;
      pub_clock_.publish(clk);
    }

    auto tp = mech_->test_point();
    inertia_crusher::TestPoint m;
    m.header.stamp = stamp;
    m.header.frame_id = "world";
    m.displacement = to_msg(tp.displacement);
    m.velocity = to_msg(tp.velocity);
    m.acceleration = to_msg(tp.acceleration);
    pub_tp_.publish(m);
    bag_.write("/crusher/test_point", stamp, m);

    auto d = mech_->drive();
    inertia_crusher::DriveState ds;
    ds.header = m.header;
    ds.speed = d.speed;
    ds.torque = d.torque;
    ds.power = d.power;
    ds.nutation_angle = mech_->nutation_angle();
    ds.mantle_spin = mech_->mantle_spin();
    pub_drive_.publish(ds);
    bag_.write("/crusher/drive", stamp, ds);

    sig_.t_s.push_back(mech_->time());
    sig_.x_m.push_back(tp.displacement.x());
    sig_.y_m.push_back(tp.displacement.y());
    sig_.z_m.push_back(tp.displacement.z());
    sig_.power_W.push_back(d.input_power);  // the run summary: the logged motor power (effects.drive_efficiency)
    sig_.speed_rad_s.push_back(d.speed);

    if (with_tf) {
      tf2_msgs::TFMessage tf;
      for (auto id : kBodies) {
        auto b = mech_->body(id);
        geometry_msgs::TransformStamped ts;
        ts.header.stamp = stamp;
        ts.header.frame_id = "world";
        ts.child_frame_id = mbd::body_name(id);
        ts.transform.translation = to_msg(b.position);
        ts.transform.rotation = nodes::to_pose(b.position, b.orientation).orientation;
        tf.transforms.push_back(ts);
      }
      geometry_msgs::TransformStamped tp_frame;  // the test point, fixed on the frame (TestPoint.msg)
      tp_frame.header.stamp = stamp;
      tp_frame.header.frame_id = mbd::body_name(mbd::BodyId::FixedCone);
      tp_frame.child_frame_id = "test_point";
      tp_frame.transform.translation = to_msg(mech_->test_point_offset());
      tp_frame.transform.rotation.w = 1;
      tf.transforms.push_back(tp_frame);
      pub_tf_.publish(tf);
      bag_.write("/tf", stamp, tf);
      if (flow_) flow_out_->publish(stamp, *mech_, flow_->model(), bag_);
    }
  }

  // Closes the bag and writes summary.json; a write error in either makes `status` non-zero. After a failed or
  // stopped run it says what the run's folder holds.
  void finish(int& status) {
    if (cfg_.run.load == "dem") {
      // Collect the DEM's last product message: 1 s, or half the peer's silence limit when that is shorter (dem_node
      // waits for the end at most coupling.timeout_s).
      const double until = nodes::wall_now() + std::min(1.0, 0.5 * cfg_.coupling.timeout_s);
      while (nodes::wall_now() < until) {
        ros::spinOnce();
        ros::WallDuration(0.01).sleep();
      }
      send_finished();
    }
    bag_.close();  // a failure is logged by name
    if (!bag_.error().empty()) {
      if (stopped_.empty()) stopped_ = bag_.error();
      if (!status) status = 1;
    }
    if (out_.empty()) return;
    auto s = analysis::summarize(sig_, cfg_.mech.drive_speed_rad_s, cfg_.run.settle_s);
    s.wall_s = wall_s_;
    s.config = config_path_;
    s.load = cfg_.run.load;
    s.stopped = stopped_;
    if (product_) s.product = product_;
    if (flow_ && flow_window_) {  // the product discharged after the settle time
      auto w = *flow_window_;
      chamber::close_window(w, flow_->model(), mech_->time());
      s.product = nodes::flow_product(flow_->model(), w.by_class(), w.throughput_tph());
    }
    std::vector<std::string> non_finite;
    const std::string summary_error = nodes::write_file(out_ + "/summary.json", analysis::to_json(s, &non_finite));
    for (const auto& f : non_finite)
      ROS_WARN("mbd_node: summary.json: %s is not a finite number, written as null", f.c_str());
    if (!summary_error.empty()) {
      nodes::log_error("mbd_node: " + summary_error + "; there is no summary of this run");
      if (!status) status = 1;
    }
    if (status) report_kept(summary_error.empty());
    ROS_INFO("mbd_node: %.2f s simulated in %.2f s wall (%.3gx real time); amplitude x %.3f mm, power %.2f kW",
             s.simulated_s, wall_s_, s.simulated_s / std::max(wall_s_, 1e-9), s.amplitude_x_mm.mean,
             s.power_kW.mean);
  }

  // What a failed or stopped run leaves in ~out, said plainly (scripts/crusher run says it again for the folder).
  void report_kept(bool summary_written) {
    char t[48];
    std::snprintf(t, sizeof t, "summary.json (to t = %.3f s)", mech_->time());
    std::string kept = summary_written ? t : "";
    if (ck_steps_ && last_checkpoint_ > 0)
      kept += (kept.empty() ? "" : ", ") + std::string("its checkpoint at step ") + std::to_string(last_checkpoint_) +
              " (--resume continues from it)";
    kept += kept.empty() ? "" : ", ";
    if (bag_.error().empty()) kept += ck_steps_ ? "its bag segments" : "run.bag";
    else if (ck_steps_) kept += "its bag segments, the newest ending at the write error (a resume rewrites it)";
    else kept += "run.bag up to the write error (unindexed: `rosbag reindex` mends it)";
    nodes::log_warn("mbd_node: the run in " + out_ + " is incomplete; kept: " + kept);
  }

  // ---- checkpoints (coupled and fast runs with run.checkpoint_every_s > 0)
  // The step a checkpoint is named by: coupling steps completed (coupled), mechanism steps taken (flow).
  std::uint64_t step_index() const { return flow_ ? flow_steps_ : leader_.completed(); }
  const std::vector<std::string>& run_nodes() const { return flow_ ? coupling::fast_nodes() : coupling::coupled_nodes(); }

  // Old checkpoints and segments of this node in ~out belong to an earlier run: a fresh run removes them.
  void clear_own_files() {
    coupling::remove_checkpoints_after(out_, "mbd", 0);  // checkpoints are taken after step 0 only
    coupling::remove_bag_segments_from(out_, "run", 0);
  }

  // Checkpoint at the current step, then a new bag segment from it. The segment before it is closed first: a
  // checkpoint never follows a segment that could not be written whole (a resume rewrites from the one before).
  void checkpoint_and_rotate() {
    bag_.close_or_throw();
    write_checkpoint();
    bag_.open(coupling::bag_segment_path(out_, "run", step_index()));
  }

  void write_checkpoint() {
    const double w0 = nodes::wall_now();
    const std::uint64_t k = step_index();
    coupling::write_checkpoint(out_, {"mbd", k, mech_->time()}, [&](core::BinaryWriter& w) {
      mech_->save_state(w);
      w.tag("NODE");
      w.put_string(cfg_.run.load);
      w.put(next_pub_);
      w.put(next_tf_);
      for (const auto* v : {&sig_.t_s, &sig_.x_m, &sig_.y_m, &sig_.z_m, &sig_.power_W, &sig_.speed_rad_s}) w.put_vec(*v);
      w.put<char>(product_.has_value());
      if (product_) {
        w.put(product_->throughput_tph);
        w.put(product_->mass_discharged_kg);
        w.put(product_->mass_lost_kg);
        w.put(product_->mass_crushed_kg);
        w.put_vec(product_->sieve_mm);
        w.put_vec(product_->passing_pct);
      }
      if (flow_) {
        flow_->save_state(w);
        flow_out_->save_state(w);
        w.put<char>(flow_window_.has_value());
        if (flow_window_) {
          w.put(flow_window_->t0);
          w.put(flow_window_->t1);
          w.put_vec(flow_window_->discharged0);
          w.put_vec(flow_window_->discharged1);
          w.put(flow_window_->energy0);
          w.put(flow_window_->energy1);
        }
      }
    }, 2, run_nodes());
    last_checkpoint_ = k;
    ROS_INFO("mbd_node: checkpoint at step %llu (t = %.4f s) in %.2f s", static_cast<unsigned long long>(k),
             mech_->time(), nodes::wall_now() - w0);
  }

  void resume_from_checkpoint() {
    std::vector<std::string> damaged;
    const uint64_t k = coupling::resume_step(out_, &damaged, run_nodes());
    for (const auto& d : damaged) ROS_WARN("%s: %s", "mbd_node", d.c_str());
    auto h = coupling::read_checkpoint(out_, "mbd", k, [&](core::BinaryReader& r) {
      mech_->load_state(r);
      r.expect("NODE");
      const std::string load = r.get_string();
      if (load != cfg_.run.load)
        r.fail("the run it holds has load '" + load + "', this one '" + cfg_.run.load + "' (resume with the same load)");
      r.get(next_pub_);
      r.get(next_tf_);
      for (auto* v : {&sig_.t_s, &sig_.x_m, &sig_.y_m, &sig_.z_m, &sig_.power_W, &sig_.speed_rad_s}) r.get_vec(*v);
      if (r.get<char>()) {
        analysis::ProductSummary p;
        r.get(p.throughput_tph);
        r.get(p.mass_discharged_kg);
        r.get(p.mass_lost_kg);
        r.get(p.mass_crushed_kg);
        r.get_vec(p.sieve_mm);
        r.get_vec(p.passing_pct);
        product_ = p;
      }
      if (flow_) {
        flow_->load_state(r);
        flow_out_->load_state(r);
        if (r.get<char>()) {
          chamber::ProductWindow w;
          r.get(w.t0);
          r.get(w.t1);
          r.get_vec(w.discharged0);
          r.get_vec(w.discharged1);
          r.get(w.energy0);
          r.get(w.energy1);
          flow_window_ = w;
        }
      }
    });
    if (flow_) flow_steps_ = k;
    else leader_.resume_at(k);
    resume_step_ = last_checkpoint_ = k;
    coupling::remove_checkpoints_after(out_, "mbd", k);
    ROS_INFO("mbd_node: resumed from the checkpoint at step %llu (t = %.4f s)", static_cast<unsigned long long>(k),
             h.time);
  }

  Config cfg_;
  std::string out_, config_path_;
  long ck_steps_ = 0;  // coupling steps per checkpoint (0: off)
  std::uint64_t last_checkpoint_ = 0, resume_step_ = 0;
  std::uint64_t flow_steps_ = 0;  // mechanism steps taken in a flow run (its checkpoints' step)
  double next_pub_ = 0, next_tf_ = 0;
  double max_rtf_ = 0, wall_start_ = 0;
  std::unique_ptr<mbd::Mechanism> mech_;
  std::unique_ptr<chamber::FlowLoad> flow_;        // run.load flow
  std::unique_ptr<nodes::FlowOutputs> flow_out_;
  std::optional<chamber::ProductWindow> flow_window_;  // opened at the settle time
  coupling::Leader leader_;
  ros::Publisher pub_clock_, pub_tp_, pub_drive_, pub_tf_, pub_geom_;
  ros::Subscriber sub_wrench_, sub_product_, sub_heartbeat_;
  nodes::BagRecorder bag_;
  analysis::RunSignals sig_;
  std::optional<analysis::ProductSummary> product_;
  inertia_crusher::GeometryState geom_sent_;  // the step's liner state last sent
  std::string peer_stopped_;  // dem_node's reason, when it has stopped
  bool waiting_ = false;  // inside exchange(): a step was requested and the mechanism has not moved since
  bool answered_any_ = false;  // dem_node has answered a step in this process
  double stop_noted_ = 0;      // wall time a stop was first seen while dem_node worked on a step
  static constexpr double kStopGrace_s = 5.0;
  std::string stopped_;        // why the run ended early ("" when it ran to its end)
  double wall_s_ = 0;
  struct {
    Eigen::Vector3d mantle_force = Eigen::Vector3d::Zero(), mantle_torque = Eigen::Vector3d::Zero();
    Eigen::Vector3d concave_force = Eigen::Vector3d::Zero(), concave_torque = Eigen::Vector3d::Zero();
  } wrench_;
};

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // progress lines reach a redirected log as they are written
  ros::init(argc, argv, "mbd_node", ros::init_options::NoSigintHandler);
  nodes::install_stop_handler();
  ros::NodeHandle nh, pnh("~");
  const std::string config_path = nodes::param_or(pnh, "config", std::string());
  const std::string out = nodes::param_or(pnh, "out", std::string());
  if (config_path.empty()) {
    std::fprintf(stderr, "mbd_node: parameter ~config is missing; usage: rosrun inertia_crusher mbd_node "
                         "_config:=launch_free_configs/gyp1200_400rpm.yaml [_out:=DIR] [_load:=none|bed|flow|dem]\n");
    return 2;
  }
  Config cfg;
  try {
    const auto d = nodes::param_text(pnh, "duration");  // s, overrides run.duration_s
    cfg = load_config(config_path, nodes::param_or(pnh, "load", std::string()),
                      d ? core::checked_duration("parameter ~duration", *d) : -1.0);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mbd_node: %s\n", e.what());
    return 2;
  }
  if (!out.empty()) ::mkdir(out.c_str(), 0755);
  bool resume = false;
  if (!nodes::bool_param(pnh, "resume", &resume)) {
    std::fprintf(stderr, "mbd_node: parameter ~resume is not accepted; accepted: true, false\n");
    return 2;
  }
  try {
    const auto rtf = nodes::param_text(pnh, "max_rtf");  // 0: as fast as possible
    MbdNode node(nh, std::move(cfg), out, config_path,
                 rtf ? core::parse_number("parameter ~max_rtf", *rtf, 0, 1e6, "(times real time; 0: as fast as possible)") : 0.0,
                 resume);
    nodes::mark_running();
    return node.run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mbd_node: %s\n", e.what());
    return 2;
  }
}
