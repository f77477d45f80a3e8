#pragma once
// Continuum flow model of the whole charge between the liners (the fast mode's load; chamber_models.md). ROS-free.
//
// Cells are fixed in the concave's liner frame: `bands` in z over the height the mantle and the concave share x
// `sectors` in azimuth. Each holds rock by size class (breakage.hpp), its mean fall speed, the memory of the
// hysteretic bed law (mbd/bed_law.hpp) and the mean number of compressions its rock has had. Per step, at the
// liners' pose:
//  - Gap: g of the cell's concave point to the mantle, along the mantle normal (the mantle's real motion).
//  - Compression: the rock of mass m fills A g; loose it takes m / rho0 (rho0 = loose_fraction x solid density),
//    so the compression ratio is s = 1 - A g rho0 / m (the piston-die kinematics rho = rho0 / (1 - s)). s presses
//    the rock along the hysteretic law: virgin loading p = E (s - s0)^n, unloading recovers `rebound` of the
//    compression; the loop's loss is the crushing work. Past max_compression the bed cannot compact: the excess is
//    extruded into the cell below (out from the bottom band), broken as by the pressing that took it to the limit;
//    pressed out into a cell in the same pressing, it is not broken by that pressing again (once per pressing).
//  - Breakage: each completed compression event (one loading-unloading loop, ratio s = (smax - s0) / (1 - s0)) breaks
//    every class of the cell by the selection and breakage functions (breakage.hpp); mass conserved. The crushing
//    energy is the liners' work on the rock, p A dg, booked step by step: over a loop the law's loss
//    (1 - rebound) E s^(n+1) / (n + 1) per loose volume, plus the work of extrusion at the compaction limit.
//  - Flow (Evertsson 1999): rock is held while the gap closes on it and while it is pressed; while the gap opens it
//    falls under gravity into the cell below as far as that cell has room (its rock would still be loose) and a lump
//    only through a gap wider than itself (classes above the gap below are retained); rock resting on falling rock
//    moves with it; from the bottom band it is discharged as product. So the fall per cycle is bounded by the
//    opening time, and the capacity falls with the speed (chamber_models.md section 1).
//  - Feed: choke feed; the top band takes feed of the given size distribution up to its loose capacity whenever it
//    is free, so the feed rate is an output (effects.feed_limited: at most a feeder's rate).
//  - Liners: new, or the concave worn over the lower chamber (effects.worn_liners, liner_wear.hpp).
//  - Refill: with material.refill_length_m > 0, a released bed fills the opening gap only as its rock falls, so the
//    next pressing starts where the liner meets it (bed_refill.hpp); 0: at once, from the widest gap.
//  - Scatter: with material.lump_std > 0, each pressing of a cell has its own strength, a factor of mean 1 on the
//    bed law's pressure whose std falls with the number of lumps the cell holds (bed_scatter.hpp).
//  - Load: p A acts on both liners along the mantle normal (action and reaction, forces and torques); with
//    effects.liner_friction, the rock's friction against the mantle's slip as well.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "chamber/bed_compaction.hpp"
#include "chamber/bed_refill.hpp"
#include "chamber/bed_scatter.hpp"
#include "chamber/breakage.hpp"
#include "chamber/mixture_packing.hpp"
#include "chamber/liner_friction.hpp"
#include "core/binary_io.hpp"
#include "core/chamber_geometry.hpp"
#include "mbd/bed_law.hpp"

namespace chamber {

// The rock as the flow model sees it (flow_material.yaml, from the virtual piston-die test).
struct FlowMaterial {
  double solid_density = 2600;   // kg/m^3 (Table 4)
  double loose_fraction = 0.55;  // solid fraction of the loose bed
  double modulus_Pa = 50e6;      // virgin loading p = E u^n, u the compaction coordinate (bed_compaction.hpp)
  double exponent = 2.0;
  bool solid_divergence = false; // u = s / (1 - s / s_solid) (the pressure diverges at the solid's density); false: u = s
  double rebound = 0.15;         // recovered fraction of each compression
  double max_compression = 0.40; // compaction limit (rho0 -> rho0 / (1 - s_max)), at most the solid's (below)
  bool elastic_limit = false;    // past the limit the rock is held, elastic (bed_limit.hpp); false: pressed out
  double lump_std = 0.0;         // relative std of one lump's share of a bed's pressure (bed_scatter.hpp); 0: none
  double refill_length_m = 0.0;  // a released bed refills the opened gap over its free fall / this (bed_refill.hpp); 0: at once
  // The mixture's packing (mixture_packing.hpp): compaction index K of the chamber's pour; 0: one loose fraction for
  // every size mixture. The bed of sizes evenly between packing_ref_min_m and _max_m packs to loose_fraction (the die's).
  double packing_index = 0.0;
  double packing_ref_min_m = 28e-3, packing_ref_max_m = 40e-3;
  BreakageParams breakage;
};

// What a checkpoint of the flow model must match of its material, in one place for both the flow model's own state and
// the coupled chamber's (coupling/chamber_checkpoint.cpp); each list keeps the order of the states already written.
// The rock and its breakage: density, loose fraction, pressure law, selection and progeny.
std::vector<double> material_fingerprint(const FlowMaterial& m);
// The laws chosen by a tag each, appended only when on, so that states written before a law existed still load:
// -2 the diverging pressure law, -4 the rock held elastic past the limit, -6 and its length the bed's refill, -7 and
// its index and reference sizes the mixture's packing. A new law adds its tag here.
std::vector<double> law_fingerprint(const FlowMaterial& m);

// The compaction limit of a bed: its solid density (rho0 / (1 - s) = solid density, s = 1 - loose fraction). No bed
// is denser; the piston-die fit takes it as the flow material's max_compression and extrapolates its pressure law
// from the deepest pressing to it, rather than capping the pressure where the die stopped.
inline double solid_compaction_limit(double loose_fraction) { return 1.0 - loose_fraction; }

// The law's compaction coordinate: diverging at the solid limit, or the plain compression ratio.
inline CompactionScale compaction_scale(const FlowMaterial& m) {
  return m.solid_divergence ? CompactionScale{solid_compaction_limit(m.loose_fraction)} : CompactionScale{};
}

// Where a diverging law's rock is pressed out of the nip: 98 % of the solid limit, a guard that keeps the pressure
// finite (p = E (49 s_solid)^n there: 92 MPa for the eight pourings' fit).
inline double diverging_compaction_limit(double loose_fraction) { return 0.98 * solid_compaction_limit(loose_fraction); }

// The paper's -50 mm marble feed (section 3.2), taken as P(x) = (x / 50 mm)^2.5 below 50 mm: fraction passing.
std::vector<double> default_feed_passing(const std::vector<double>& sieves_m);

// Chamber candidates of the diagnosis (flow.effects.<name>; off by default, the shipped model is choke fed on new
// liners). feed_limited: the feeder, not the chamber, sets the rate: at most max_feed_kg_s enters the top band's free
// cells (shared by their room; what they cannot take in a step is not carried over). worn_liners: the concave worn over
// the lower part of the chamber (liner_wear.hpp): the setting wider by setting_increase_m at the discharge, the wear
// falling linearly to 0 at worn_height_fraction of the chamber's height above it.
struct FeedLimited {
  bool enabled = false;
  double max_feed_kg_s = 0.0;  // config: max_feed_tph
};
struct WornLiners {
  bool enabled = false;
  double setting_increase_m = 0.0;    // config: setting_increase_mm (normal wear depth at the discharge)
  double worn_height_fraction = 0.5;  // of the shared height of mantle and concave, from the bottom
};
// squeeze_flow: rock at the compaction limit is pressed out of the nip along both liners against their friction
// to where it is free (squeeze_flow.hpp): a cell pressed out at gap g holds E s_max^n exp(2 mu x / g), x the escape
// length (unknown: the diagnosis fits it; the model's cells do not resolve the path). Only while the rock slides (a
// step that presses rock out); when the gap stops closing, the bed law's pressure again.
struct SqueezeFlow {
  // From ~20 mm the friction hill is too stiff for the mechanism's explicit coupling (30 mm blows up at both speeds).
  static constexpr double kMaxEscapeLength_m = 0.02;
  static constexpr double kMaxEscapeLength_mm = 1e3 * kMaxEscapeLength_m;
  bool enabled = false;
  double wall_friction = 0.7;    // rock on steel, static (Table 4)
  double escape_length_m = 0.0;  // config: escape_length_mm
};
// liner_friction: the pressed rock's Coulomb friction on the liners (liner_friction.hpp); acts where step() is given
// the liners' twists (the fast mode; not the coupled run's fines, whose coarse rock is the DEM's with its own friction).
struct FlowEffects {
  FeedLimited feed_limited;
  WornLiners worn_liners;
  SqueezeFlow squeeze_flow;
  LinerFriction liner_friction;
};

struct FlowParams {
  int bands = 30, sectors = 16;
  std::vector<double> sieves_m{1e-3, 2e-3, 4e-3, 8e-3, 12e-3, 16e-3, 22.4e-3, 31.5e-3, 40e-3, 50e-3, 63e-3};
  // Cumulative fraction of the feed passing each sieve (same length, ascending, in [0, 1]); the rest is above the
  // largest sieve. Default: default_feed_passing(sieves_m).
  std::vector<double> feed_passing;
  bool prefill = true;     // the chamber starts full of loose feed (at the first step's gap)
  bool choke_feed = true;  // false: no feed (the chamber runs empty)
  // false (shipped): every release forgets the compaction and the next pressing starts a virgin curve where the rock
  // is (mbd::bed_hysteretic). true: the rock keeps it until re-poured (mbd::bed_compacted; breakage by the hazard's
  // rise). Not shipped: calibrated at 400 rpm, the GYP1200's 600 rpm chamber fails with either limit law (overrun
  // with extrude, choked with elastic; src/chamber/README.md).
  bool compaction_memory = false;
  int seed = 1;               // of the pressings' scatter (material.lump_std > 0)
  std::string material_file;  // config: flow.material_file as given ("" none); its values are in `material`
  // config: flow.calibration_unknowns, the machine values `crusher calibrate --flow` fits at 400 rpm, comma separated
  // ("": the default three); read by analysis/flow_calibration.hpp, not by the model
  std::string calibration_unknowns;
  FlowMaterial material;
  FlowEffects effects;
  FlowParams();
};

// The parameters of a model that carries only what is deposited into it (the coupled run's fines, whose coarse rock
// is the DEM's): no choke feed, no prefill, no scatter of the pressings (the DEM's particles have their own).
FlowParams fines_only(FlowParams p);

using FlowLoads = core::LinerLoads;  // on each liner, about the given centres of mass (world frame)

class FlowModel {
 public:
  // mantle, concave: liner profiles in their liner frames. Throws std::invalid_argument for a bad parameter.
  FlowModel(const FlowParams& p, const core::Profile& mantle, const core::Profile& concave);

  const FlowParams& params() const { return p_; }
  const Breakage& breakage() const { return breakage_; }
  int bands() const { return p_.bands; }
  int sectors() const { return p_.sectors; }
  std::size_t cells() const { return speed_.size(); }
  std::size_t classes() const { return breakage_.classes(); }
  double loose_density() const { return rho0_; }  // of the reference bed (material.loose_fraction)
  // Of cell k's rock as it lies (its mixture's packing, material.packing_index > 0; else loose_density()), kg/m^3,
  // and its compaction limit, the solid's (at most material.max_compression).
  double cell_loose_density(std::size_t k) const { return loose_rho_[k]; }
  double cell_compaction_limit(std::size_t k) const { return s_max_[k]; }
  double cell_area(std::size_t k) const { return cells_.area[k / p_.sectors]; }  // m^2 of concave
  Eigen::Vector3d cell_point(std::size_t k) const;  // on the concave, concave liner frame (band 0 = bottom)
  double band_bottom(int b) const { return cells_.z_lo + b * cells_.dz; }  // z (m, liner frame) where band b starts
  double band_height() const { return cells_.dz; }                         // m; sector s spans [s, s + 1] 2 pi / sectors

  // Presses, breaks, moves and feeds the rock at the liners' pose (liner frame -> world) over h seconds. twists: the
  // liners' velocities (effects.liner_friction acts only with them).
  FlowLoads step(const Eigen::Isometry3d& mantle, const Eigen::Isometry3d& concave, const Eigen::Vector3d& com_mantle,
                 const Eigen::Vector3d& com_concave, double h, double gravity, const LinerTwists* twists = nullptr);

  // Adds rock to cell k (kg per class; no compressions yet), counted as fed. Tests.
  void deposit(std::size_t k, const std::vector<double>& class_kg);
  // The coupled run's fines (flow_model_deposit.cpp; fines_only below). Cell of a point in the concave's liner frame
  // (band-major; points above the top band belong to it); -1 below the bottom band.
  long cell_of(const Eigen::Vector3d& xc) const;
  // Adds rock at xc (concave liner frame, kg per class) to the cell holding it, counted as fed; below the bottom
  // band it is discharged at once.
  void deposit(const Eigen::Vector3d& xc, const std::vector<double>& class_kg);
  std::vector<double> take_discharged();  // kg per class discharged since the last take
  double untaken_kg() const;              // kg discharged but not taken yet
  double cell_mass(std::size_t k) const { return total_[k]; }
  const double* cell_classes(std::size_t k) const { return &mass_[k * classes()]; }
  double cell_pressure(std::size_t k) const { return pressure_[k]; }  // Pa at the last step
  double cell_gap(std::size_t k) const { return gap_[k]; }            // m at the last step
  double cell_compressions(std::size_t k) const { return count_[k]; }  // mean events of its rock
  // Time integral of each cell's normal force p A on the liners since the start (N s): its change over a window over
  // the window's length is the window's mean force (the concave force map, force_map.hpp).
  const std::vector<double>& normal_impulse() const { return impulse_; }
  double mass_kg() const;                                              // in the chamber
  double fed_kg() const { return fed_; }
  double discharged_kg() const;
  const std::vector<double>& discharged_by_class() const { return out_; }  // kg, cumulative
  // The liners' work on the rock so far (J): the loops' losses (and what the pressed cells hold elastically now),
  // including the work of pressing rock out of the nip at the compaction limit (extrusion_energy_J, a part of it).
  double crushing_energy_J() const { return energy_; }
  double extrusion_energy_J() const { return extrusion_; }
  // Rock discharged so far that was pressed out of the bottom band's nip at the compaction limit (kg; the rest fell
  // out as the gap opened), and the sum of its kg x the gap it left through (kg m): how the product leaves.
  double extruded_out_kg() const { return extruded_out_; }
  double extruded_out_gap_kg_m() const { return extruded_gap_; }
  // Work of the liners against the rock's friction so far (J; effects.liner_friction), not in crushing_energy_J.
  double friction_energy_J() const { return friction_; }
  long events() const { return events_; }  // compression events of at least 2 % so far
  double product_compressions() const;  // mean compression events of the discharged rock
  // Cumulative fraction passing each sieve of a mass-by-class vector (0..1).
  std::vector<double> passing(const std::vector<double>& by_class) const;

  void save_state(core::BinaryWriter& w) const;
  void load_state(core::BinaryReader& r);  // same parameters; throws naming what differs
  // The parameters a state belongs to (saved with it, so its order is part of the file format).
  std::vector<double> fingerprint() const;

 private:
  double break_fresh(double* f, const double* pressed, double s0, double s1);
  FlowParams p_;
  core::ProfileDistance mantle_;  // the gap of a concave point to the mantle
  Breakage breakage_;
  double rho0_ = 0;
  // Per cell: the loose density of its rock's mixture and its compaction limit (constant without the mixture's
  // packing), refreshed at the start of a step where the rock changed (mixed_).
  std::shared_ptr<const MixturePacking> packing_;  // null: one loose fraction
  std::vector<double> loose_rho_, s_max_;
  std::vector<char> mixed_;
  double locked_stiffness_ = 0;  // Pa per unit strain of a layer held past the limit (bed_limit.hpp); 0: extrude
  core::ConcaveCells cells_;  // the cells' concave points and areas
  std::vector<double> feed_share_;
  std::vector<double> mass_;                            // cells x classes, kg
  std::vector<double> speed_, pressure_, gap_, count_, total_;  // per cell (total_: kg, the sum of its classes)
  // cells x classes, kg: rock pressed out of the nip above into the cell's ongoing pressing (it has had that pressing);
  // fresh_, pressed_out_: scratch
  std::vector<double> pressed_, fresh_, pressed_out_;
  std::vector<double> impulse_;                                // per cell, N s
  std::vector<mbd::BedCell> memory_;     // the hysteretic law's (compaction_memory false)
  std::vector<mbd::CompactedBed> bed_;   // the compacted bed's (compaction_memory true)
  std::vector<BedRefill> refill_;        // the released beds' refill (material.refill_length_m > 0)
  std::vector<char> closing_;       // the gap closed in the last step (the rock is held)
  std::vector<double> out_, pass_, scratch_;  // discharged per class (cumulative); scratch
  std::vector<double> cx_, cy_, cz_;  // the cells' concave points (concave liner frame)
  // Per step (locate_cells): the cells' points in the mantle's liner frame, their distance to the mantle's axis and
  // signed distance to the mantle's profile, the closest segment of the profile.
  std::vector<double> xm_x_, xm_y_, xm_z_, rho_, dist_;
  std::vector<int> seg_;
  std::vector<double> taken_;       // out_ at the last take_discharged (empty: none yet)
  // The pressings' scatter (material.lump_std > 0, bed_scatter.hpp): a lump's mass per class, each cell's factor on
  // its bed pressure (drawn when a pressing starts), the draws.
  std::vector<double> lump_kg_, scatter_;
  ScatterDraws draws_;
  double fed_ = 0, energy_ = 0, extrusion_ = 0, out_count_ = 0, friction_ = 0, extruded_out_ = 0, extruded_gap_ = 0;
  long events_ = 0;
  bool prefilled_ = false;

  void locate_cells(const Eigen::Isometry3d& concave_to_mantle);
  void refresh_packing();  // loose_rho_ and s_max_ of the cells whose rock changed
  double locked_stiffness(std::size_t k) const;
  void move(std::size_t from, double* to, double kg, const double* class_share, double* to_count);
  void fill(std::size_t k, double kg);  // loose feed
  double sum_classes(std::size_t k) const;
  double loose_volume_mass(std::size_t k) const;
  void add(std::size_t k, const double* share, double scale, bool keep_speed);
};

}  // namespace chamber
