#pragma once
// The DEM side of the coupled crusher run (paper section 3.1, Figure 13): breakable rocks fed into the
// chamber between the two moving liners, crushed, discharged below the chamber and screened.
// ROS-free; dem_node is a thin adapter around it.
//
// Liner frames: origin at the centre of O1, z along the body's axis (core/chamber_geometry.hpp). The
// mechanism reports each body by its centre of mass; the liner origin is com - R (0, 0, com_z).
// Over one coupling interval the liners move rigidly with the twist given at its start (pose
// extrapolated every DEM step), and the wrench on each liner is averaged over the interval.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "core/binary_io.hpp"
#include "coupling/chamber_params.hpp"
#include "chamber/flow_model.hpp"
#include "chamber/size_classes.hpp"
#include "dem/domain_engine.hpp"
#include "dem/mesh_contact.hpp"
#include "dem/region_map.hpp"
#include "dem/world.hpp"
#include "rocks/packing.hpp"
#include "rocks/rng.hpp"

namespace coupling {

struct BodyMotion {  // centre of mass pose and twist, world frame
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero(), angular_velocity = Eigen::Vector3d::Zero();
};

struct BodyWrench {  // about the body's centre of mass, world frame
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), torque = Eigen::Vector3d::Zero();
};

struct ProductState {
  std::vector<double> sieve_m, passing_pct;  // cumulative mass passing, ascending sieves
  double fed_kg = 0, discharged_kg = 0, in_chamber_kg = 0, lost_kg = 0;
  double crushed_kg = 0;  // metaparticles crushed to fines (metaparticle_crushing.hpp): discharged, or held in the chamber (dem.fines: flow)
  double fines_bed_kg = 0;  // part of in_chamber_kg: crushed fines held in the chamber (dem.fines: flow)
  long metaparticles_crushed = 0;     // crushed to fines (their mass is crushed_kg)
  long metaparticles_fragmented = 0;  // crushed into four fragments that stayed in the chamber (crushing.fragments)
  double throughput_kg_s = 0;  // discharged mass rate over the last window
  long fragments_discharged = 0;
};

struct TrackedPoint {
  uint64_t id;
  double t;
  Eigen::Vector3d x;
};

class ChamberDem {
 public:
  explicit ChamberDem(const ChamberParams& p);

  // Advances by `duration` (s) with the liners moving from the given states; returns the wrenches
  // (mantle, concave) averaged over the interval, each about its body's centre of mass.
  std::pair<BodyWrench, BodyWrench> advance(const BodyMotion& mantle, const BodyMotion& concave, double duration);
  // Called after every DEM step inside advance() (dem_node's heartbeat to mbd_node: a sign of progress within a
  // coupling step that takes long on a busy machine). Keep it cheap; empty: none.
  void set_progress_hook(std::function<void()> hook) { progress_ = std::move(hook); }

  // Runs the DEM decomposed (issue 25; dem/domain_engine.hpp): from the next advance after the prefill (at once when
  // there is none or a checkpoint was loaded) the charge lives in the engine's parts, made by `make` from the whole
  // charge. The liner wrenches, region forces and deepest overlap are reduced over the parts once per advance; the
  // crushing criterion runs on each part's owned particles; feed, discharge, screening, trajectories, fragment
  // placement and the fines' flow model run on the whole charge on the root process, between two steps
  // (DomainEngine::edit), at each bookkeeping interval and crushing batch. Decomposed, world() and the liner
  // accessors are this process's first part, and product(), trajectories() and take_breaks() are the root's; advance(),
  // product() and save_state() are collective. A checkpoint holds the whole charge; a decomposed run resumes it cut
  // anew (save_state cuts the saving run anew too, so both continue alike).
  void decompose(dem::EngineFactory make);
  bool decomposed() const { return decomposed_; }
  // Collective, on every process but the root of a decomposed run resumed from a checkpoint, while the root calls
  // load_state: takes the root's charge and bookkeeping.
  void follow_load();
  // The largest sphere of the feed's rocks (m): a decomposition's ghost reach must exceed twice it (bonds, contacts).
  double largest_sphere_radius() const;
  const dem::DomainEngine& engine() const { return *engine_; }

  double time() const { return world_->time(); }
  double dt() const { return world_->dt(); }
  const dem::World& world() const { return *world_; }
  // The whole charge's particles (and fragment_labels()): world()'s; decomposed, on the root, as at the last
  // bookkeeping (every bookkeeping_s).
  const dem::Particles& charge_particles() const { return decomposed_ ? snapshot_ : world_->particles(); }
  // Every particle of the charge this process owns, by id: x, y, z, vx, vy, vz, wx, wy, wz (dem::kGhostDoubles each).
  void owned_state(std::vector<uint64_t>& ids, std::vector<double>& state) const;
  const dem::MeshContact& mantle() const { return *mantle_; }
  const dem::MeshContact& concave() const { return *concave_; }
  const dem::MeshContact& mantle_cap() const { return *cap_; }
  const dem::MeshContact& hopper() const { return *hopper_; }
  const ChamberParams& params() const { return p_; }

  ProductState product() const;
  // Mean normal force on each concave region (N) since the last reset, ring-major (13 x 9).
  std::vector<double> force_map() const { return force_avg_.mean(); }
  void reset_force_map() { force_avg_.reset(); }
  double force_map_window_s() const { return force_window_s_; }
  // Break log since the last take (time, place, tensile or shear, particle ids).
  std::vector<dem::BondBreak> take_breaks();
  long broken_bonds() const { return broken_total_; }
  // Fragment label of each particle (index order), for colouring.
  std::vector<int> fragment_labels() const;
  const std::vector<TrackedPoint>& trajectories() const { return tracks_; }
  double rock_mass_kg(int shape) const;
  std::size_t rock_particles(int shape) const { return rocks_.at(shape).size(); }
  double sphere_density(int shape) const { return sphere_density_.at(shape); }  // kg/m^3 (feed.rock_density)
  double packing_density(int shape) const { return rocks_.at(shape).density(); }  // as packed
  int rock_shapes() const { return static_cast<int>(rocks_.size()); }
  double prefilled_kg() const { return prefilled_kg_; }
  double fines_normal_force() const { return fines_force_; }   // N, the fines' p A on the liners at the last step
  const chamber::FlowModel* fines() const { return fines_.get(); }  // dem.fines: flow; else null
  // Deepest sphere-liner overlap / sphere radius since the start: spheres larger than the liners' gap get
  // squeezed (coarse metaparticles at a narrow setting), inflating the liner forces.
  double deepest_liner_overlap() const { return deepest_liner_overlap_; }
  // Fragment birth (place_fragments), since this object was made (not checkpointed): the deepest overlap ratio of a
  // fragment at its set radius in the chosen orientation, and how many fragments were born smaller than that.
  double deepest_birth_overlap() const { return deepest_birth_overlap_; }
  long fragments_shrunk_at_birth() const { return shrunk_at_birth_; }
  // Smallest sphere of rock density the stable step allows; a heavy fragment (crushing.fragments without growth)
  // may be smaller by sqrt(its density / the rock's), a growing one must reach it when grown, else it leaves as fines.
  double fragment_min_radius() const { return fragment_min_radius_; }
  std::size_t growing_fragments() const { return growing_.size(); }  // still denser than rock (fragment_growth_s)
  // Wall-clock seconds inside advance() since construction (not checkpointed), for the benchmark: 0 the DEM
  // world's steps (World::phase_seconds splits them), 1 liner poses and wrenches, 2 the fines' flow model,
  // 3 crushing (crush_squeezed: criterion, fragments, removal), 4 bookkeeping (discharge, feed, tracks), 5 prefill.
  const std::array<double, 6>& phase_seconds() const { return phase_s_; }
  // Adds one rock of the feed (shape index) at a world position with a velocity, unrotated; counted as fed.
  void add_rock_at(int shape, const Eigen::Vector3d& centre, const Eigen::Vector3d& velocity);

  // Checkpoints (chamber_checkpoint.cpp): the whole evolving state (DEM world, feed, screening, force-map
  // window, trajectories, random generator). Written between advance() calls; it schedules a neighbour-list
  // rebuild, so this run and one restored from the file continue identically. load_state needs a ChamberDem
  // built from the same ChamberParams and throws std::runtime_error naming what does not match.
  void save_state(core::BinaryWriter& w);
  void load_state(core::BinaryReader& r);

 private:
  void set_liners(const BodyMotion& m, const BodyMotion& c, double tau);
  // Liner contact planes (point, normal) of particles by id, in liner order (mantle, cap, concave, hopper).
  using LinerPlanes = std::vector<std::pair<uint64_t, std::pair<Eigen::Vector3d, Eigen::Vector3d>>>;
  void focus(dem::World& w);             // world_ and the liner pointers on w (its interactions 0-3)
  void add_liners(dem::World& w) const;  // copies of the liners for a new World of the engine
  void start_engine();
  void step_parts();  // one step of every part; a failure on any process thrown on all
  void edit_whole(const std::function<void()>& fn);  // fn on the whole charge (focus), then focus on part 0
  void harvest_breaks();                 // the World's break log into breaks_
  void prune_growing();                  // on the whole charge: fragments gone or grown leave growing_
  void share_root_state();               // growing_, next bookkeeping and prefill from the root to every process
  void take_snapshot();                  // the whole charge's particles and fragment labels (decomposed, root)
  static std::vector<int> labels_of(const dem::World& w);  // fragment label of each particle (intact bonds)
  // Every process's crushed ids (mine) and liner planes to the root: ids sorted without repeats, planes in rank order.
  void gather_crushed(const std::vector<uint64_t>& mine, LinerPlanes& planes, std::vector<uint64_t>& ids);
  void write_state(core::BinaryWriter& w);
  void put_growing(core::BinaryWriter& w) const;  // growing_ (checkpoints, share_root_state)
  void get_growing(core::BinaryReader& r);
  void bookkeeping();
  void feed();
  void discharge();
  void crush_squeezed(bool flush);
  void crush(const std::vector<uint64_t>& ids, const LinerPlanes& planes);  // on the whole charge
  void grow_fragments(double h);  // fragments growing to the rock's density (crushing.fragment_growth_s), one step h
  // Per crushed sphere (indices idx, batch[n] for idx[n]), what its fragments may touch at birth: the spheres it
  // overlaps and the liners it presses (their tangent planes) as obstacles, the overlapping spheres crushed with it
  // (`crushed`) as crushed_neighbours.
  void birth_obstacles(const std::vector<std::size_t>& idx, const std::vector<char>& crushed, const LinerPlanes& planes,
                       std::vector<CrushedSphere>& batch) const;
  bool place_rock(int shape, const Eigen::Vector3d& centre, const Eigen::Quaterniond& q);
  // A sphere at x (world) of radius r is clear of the liners at their present pose: inside the concave and the
  // hopper (allowing for their flat facets) and outside the mantle and its cap.
  bool clear_of_liners(const Eigen::Vector3d& x, double r) const;
  void add_rock(int shape, const Eigen::Vector3d& centre, const Eigen::Quaterniond& q, const Eigen::Vector3d& v);
  void prefill();
  Eigen::Quaterniond random_orientation();

  ChamberParams p_;
  dem::BondParams bond_;
  dem::WorldParams wp_;
  std::unique_ptr<dem::World> whole_;  // the charge (decomposed: as at the decomposition or last load)
  dem::World* world_ = nullptr;        // the World worked on: whole_, an engine's part, or the whole charge in an edit
  dem::MeshContact *mantle_ = nullptr, *concave_ = nullptr, *cap_ = nullptr, *hopper_ = nullptr;  // world_'s liners
  std::unique_ptr<dem::DomainEngine> engine_;  // WholeEngine on whole_ until decompose()
  dem::EngineFactory make_engine_;
  bool decomposed_ = false;
  dem::Particles snapshot_;  // take_snapshot()
  std::vector<int> snapshot_labels_;
  std::vector<rocks::RockPacking> rocks_;
  std::vector<double> rock_mass_, sphere_density_;  // per shape: kg, and its spheres' kg/m^3 (feed.rock_density)
  dem::RegionAverager force_avg_;
  double force_window_s_ = 0;
  double z_top_ = 0, z_bottom_ = 0, r_feed_in_ = 0, r_feed_out_ = 0;
  core::Profile inner_, outer_;  // chamber walls in the liner frames: mantle + cap, concave + hopper
  bool prefilled_ = false;
  double prefilled_kg_ = 0;
  double deepest_liner_overlap_ = 0, deepest_birth_overlap_ = 0;
  long shrunk_at_birth_ = 0;
  double dt_max_ = 0;
  double rock_density_ = 0, fragment_min_radius_ = 0;  // kg/m^3 of the rock spheres (mean), m
  double next_bookkeeping_ = 0, feed_credit_kg_ = 0;
  double fed_kg_ = 0, discharged_kg_ = 0, lost_kg_ = 0, crushed_kg_ = 0;
  long fragments_out_ = 0, broken_total_ = 0, crushed_count_ = 0, fragmented_count_ = 0;
  struct Growing {
    uint64_t id;
    double r_end, rate;  // m, m/s
  };
  std::vector<Growing> growing_;  // ascending ids
  std::vector<double> stress_;     // World::contact_stress scratch (crushing.stress_criterion)
  std::function<void()> progress_;       // set_progress_hook
  std::vector<uint64_t> pending_crush_;  // ids found crushed, removed together (crushing.batch_s); empty between advances
  double first_crush_t_ = 0;
  std::vector<double> screened_kg_;  // mass discharged per sieve class (<= sieve_m[k])
  std::vector<std::pair<double, double>> discharge_log_;  // (time, mass) for the throughput window
  std::vector<dem::BondBreak> breaks_;
  std::vector<uint64_t> tracked_ids_;
  std::vector<TrackedPoint> tracks_;
  Eigen::Vector3d concave_origin_ = Eigen::Vector3d::Zero();
  std::unique_ptr<chamber::FlowModel> fines_;    // dem.fines: flow: the crushed fines in the chamber
  chamber::SizeClassMap to_flow_, from_flow_;     // dem.sieves_mm classes <-> the flow model's
  double fines_force_ = 0, gravity_ = 0;  // N, m/s^2
  rocks::Rng rng_;  // reproducible feed positions, shapes and orientations
  std::array<double, 6> phase_s_{};  // phase_seconds()
};

}  // namespace coupling
