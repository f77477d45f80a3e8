#pragma once
// Virtual piston-die test on the calibrated bonded-particle rock, and the fit of the chamber flow model's
// material parameters from it (chamber_models.md sections 2-3).
//
// Test (run_piston_die): a rigid steel die (vertical cylinder, axis z, faceted mesh) on a steel floor is filled
// by loose pouring: irregular bonded rocks (rocks::make_irregular_rock packed with the BPM's metaparticles, paper
// section 2.4.1) are placed bottom-up without overlap and settle under gravity. The bed height H0 is the top of
// the highest sphere (where a flat piston first touches). For each maximum compression ratio s_max (each on a
// copy of the same settled bed) a flat steel piston moves down at constant speed to s = stroke / H0 = s_max,
// then back up until the bed no longer pushes it. Pressure p = piston force / die area (pi D^2 / 4).
// Fragments (connected components over intact bonds, dem::Fragments) are screened by their square-mesh sieve
// size (dem::square_sieve_size) before pressing (the feed) and after each unloading.
//
// Fit (fit_flow_material), the flow model's law:
//   virgin loading  p = E s^n                      least squares of ln p on ln s over loading points s > kDieBedOnset
//                   (a laboratory curve's from s > 0.02)
//                   (PressureLaw::solid_divergence: p = E u^n, u = s / (1 - s / s_solid), ln p on ln u)
//   hysteresis      mbd::bed_hysteretic: loss per loop (1 - rebound) E D^(n+1) / (n + 1), D = s_max;
//                   rebound by least squares of the measured loop energies (closed integral of p ds)
//   selection       S_j(s) = 1 - exp(-(s / s_cj)^m),  s_cj = s_c (x_j / x_ref)^(-q), x_ref = 10 mm,
//                   x_j = geometric mean of class j's bounds
//   progeny         B(x; y) = phi (x/y)^gamma + (1 - phi) (x/y)^beta (cumulative, Austin), y = class top size
//   one event       p = [B S + I - S] f  (f: feed mass fractions per class)
// The breakage parameters are fitted (Nelder-Mead on the cumulative passing, %) only over the sieves the
// metaparticles resolve (>= resolve_diameters x their volume-mean diameter); those the data cannot support
// keep documented defaults (s_c 0.25, m 2, q 0.5, phi 0.4, gamma 0.8, beta 3).
// SI inside: m, Pa, kg; the yaml and CSV files carry mm and MPa.
#include <string>
#include <vector>

#include "chamber/breakage.hpp"
#include "chamber/flow_model.hpp"
#include "rocks/bpm_config.hpp"

namespace chamber {

// Square-mesh sieves of the flow model (mm, ascending).
const std::vector<double>& flow_sieves_mm();

struct PistonDieOptions {
  double die_diameter = 0.16;        // m (>= 3 x rock_max)
  int rock_count = 45;               // rocks poured; 0: as many as fill bed_height
  double bed_height = 0.0;           // m, loose bed height to fill when rock_count == 0
  // m, nominal rock sizes (y extent), log-uniform; the calibrated BPM's metaparticles (up to 16.2 mm) need >= 28 mm
  double rock_min = 0.028, rock_max = 0.040;
  double rock_density = 2600.0;      // kg/m^3 of the rock (Table 4): spheres heavier by V_rock / sum v_sphere
  std::vector<double> compression_ratios{0.1, 0.2, 0.3};  // s_max of each test, ascending, in (0, 0.6]
  double piston_speed = 0.4;         // m/s, loading and unloading (the platen tests' closing speed)
  double settle_min_time = 0.03;     // s of settling at least
  double settle_max_time = 0.4;      // s of settling at most
  double settle_speed = 0.01;        // m/s: settled when sqrt(2 KE / M) falls below this
  double dt_safety = 0.8;            // dt = dt_safety x min(0.3 Rayleigh step, bond step) (as the platen test)
  // World's blow-up bound on contact overlap / smaller radius. A loose bed carries the piston load on a few chains:
  // a 1.6 mm fine between a coarse sphere and the floor took 850 N (the whole bed's load at 0.05 MPa) at 0.5 r
  // of Hertz overlap, which the default 0.5 calls a blow-up (the step is 1/20 of that sphere's Rayleigh step).
  double max_overlap_fraction = 0.9;
  double unload_stop_ratio = 0.002;  // unloading ends when p < this x peak p
  // Pressings of the same bed again to the same s_max after the first (each from where the piston let go of the bed,
  // nothing re-poured): what a compacted bed dissipates and breaks when it is reloaded (PressLoop::reloads).
  int reloads = 0;
  // m: before each reload the bed is pushed this far down the die (floor and piston move down together at
  // piston_speed, the bed sliding along the die wall, as the chamber's bed slides down the liners between pressings),
  // then left to come to rest; 0: reloaded where it lies. What a shift does to the reload measures how far a
  // compacted bed must move to loosen (src/chamber/README.md).
  double reload_shift = 0.0;
  // Sideways speed of the piston / its vertical speed in every pressing (+x loading, -x unloading): the bed is pressed
  // and sheared at once, as under the gyrating mantle, whose surface slides along the bed about as far as it closes
  // (src/chamber/README.md); the sideways work is booked apart (PressLoop::sweep_energy_per_kg). 0: a plain die.
  double sweep = 0.0;
  int record_every = 50;             // steps per recorded (averaged) point
  double resolve_diameters = 2.0;    // classes resolved: lower bound >= this x volume-mean metaparticle diameter
  unsigned long long seed = 1;
  int threads = 1;
  bool verbose = false;              // progress on stderr
  // A blow-up's state dump (dem::WorldParams::blowup_dump_path): set it to a file in the run's out dir; "": an
  // unguessable name in the temporary folder.
  std::string blowup_dump_path;
  // A loop that blows up (a bed jammed under the rigid piston: halving the step does not help, measured) ends the test
  // with the loops completed kept (PistonDieResult::blowup says where); false: the blow-up is thrown. Either way a
  // blow-up before the first loop completes is thrown.
  bool keep_loops_on_blowup = false;
  void validate() const;             // std::invalid_argument naming the option and what is accepted
};

// One load-unload loop.
struct PressLoop {
  double s_max = 0.0;                // requested
  double s_reached = 0.0;            // largest s recorded
  std::vector<double> s, p;          // -, Pa (averaged over record_every steps)
  std::vector<int> phase;            // 0 loading, 1 unloading
  double loading_work = 0.0;         // Pa: integral of p ds over the loading branch (per unit bed volume)
  double loop_energy = 0.0;          // Pa: closed integral of p ds (load + unload)
  double energy_per_kg = 0.0;        // J/kg absorbed: A H0 loop_energy / rock mass
  double loading_energy_per_kg = 0.0;  // J/kg: A H0 loading_work / rock mass
  std::size_t bonds_broken = 0;
  double mass_error = 0.0;           // |sum of fragment masses - rock mass| / rock mass
  std::vector<double> passing;       // product PSD: mass fraction passing each sieve of flow_sieves_mm()
  int fragments = 0;
  double wall_s = 0.0;
  double sweep_energy_per_kg = 0.0;  // J/kg: the piston's sideways work (PistonDieOptions::sweep), not in the loop
  double s_top = 0.0;                // 1 - (highest sphere top - floor) / H0 at the start: where a flat piston meets it
  double shift = 0.0;                // m the bed was pushed down the die before this pressing (reload_shift)
  double shift_peak_pressure = 0.0;  // Pa: the largest piston force / die area while pushing it (the wall's hold)
  // PistonDieOptions::reloads: the same bed pressed again to s_max, in order. Their s is 1 - (piston - floor) / H0,
  // their energies per the same bed volume and rock mass, their bonds_broken those of that pressing alone. Not used by
  // the fits (the flow model's law reloads without loss: src/chamber/README.md) and not in the pourings' record.
  std::vector<PressLoop> reloads;
};

struct PistonDieResult {
  unsigned long long seed = 0;       // the pouring's (PistonDieOptions::seed)
  int rocks = 0;
  std::size_t particles = 0, bonds = 0;
  double die_diameter = 0.0, die_area = 0.0;  // m, m^2 (pi D^2 / 4)
  double rock_min = 0.0, rock_max = 0.0;      // m, the poured rocks' nominal sizes (options)
  double piston_speed = 0.0;                  // m/s (options)
  double bed_height = 0.0;           // m, H0
  double rock_mass = 0.0;            // kg
  double solid_density = 0.0;        // kg/m^3
  double loose_solid_fraction = 0.0; // rock_mass / (A H0 solid_density)
  double dt = 0.0, settle_time = 0.0;
  double metaparticle_diameter = 0.0;  // m, volume-mean
  double min_resolved = 0.0;         // m, smallest class lower bound resolved
  std::vector<double> feed_passing;  // feed PSD (fragments of the settled bed) on flow_sieves_mm()
  std::vector<PressLoop> loops;      // the completed ones
  std::string blowup;                // keep_loops_on_blowup: the loop that blew up and why ("" when none did)
  double wall_s = 0.0;
};

// Runs the test on the BPM model (metaparticles, packing, bonds). Throws std::invalid_argument on bad options.
PistonDieResult run_piston_die(const rocks::BpmModel& bpm, const PistonDieOptions& o);

// ---- fits
struct PowerLawFit {
  double modulus = 0.0, exponent = 0.0;  // p = modulus s^exponent (Pa)
  double rms_log = 0.0;                  // rms residual of ln p
  int points = 0;
  double s_min = 0.0;                    // the points fitted have s > s_min
};
// Where the DEM die's loading branch is the bed's law. The die's H0 is the top of the highest rock, so the piston first
// presses the top rocks alone and bears on the whole bed from the top layer's mean surface, about half a rock lower:
// s = (d / 2) / H0 = 17 mm / 81-99 mm = 0.17-0.21 for the shipped die's pourings of 28-40 mm rocks. The chamber's s
// counts from a continuous bed's loose density, which has no such top. Measured on the eight pourings
// (src/chamber/README.md): fitted over (0.2, 0.42], the power law predicts the deep pressings (s 0.46-0.50, not
// fitted) to +0.04 in mean ln p (each pouring's own (d / 2) / H0: -0.08); fitted from 0.02, +0.51 (1.7x too soft).
constexpr double kDieBedOnset = 0.2;
// Least squares in log space over the points with s > s_min and p > 0; std::invalid_argument below 2 points.
// In the compaction coordinate u(s) of `scale` (bed_compaction.hpp): p = modulus u^exponent (the plain s by default).
PowerLawFit fit_power_law(const std::vector<double>& s, const std::vector<double>& p, double s_min = 0.02,
                          const CompactionScale& scale = {});

// Closed integral of p ds along the recorded path (trapezoids; positive for a clockwise loss loop).
double path_integral(const std::vector<double>& s, const std::vector<double>& p);
// Loss of one loop of mbd::bed_hysteretic from 0 to D and back: (1 - rebound) E D^(n+1) / (n + 1); in the diverging
// coordinate (the law in u, the work in s) by Simpson's rule.
double hysteretic_loop_loss(double E, double n, double rebound, double D, const CompactionScale& scale = {});
// rebound minimising sum (loss_model(D_i) - loss_i)^2, clipped to [0.01, 1] (the law needs some recovery); rms
// residual (Pa) in *rms.
double fit_rebound(double E, double n, const std::vector<double>& D, const std::vector<double>& loss,
                   double* rms = nullptr, const CompactionScale& scale = {});

// One breakage event (chamber::Breakage, breakage.hpp) on a cumulative-passing PSD over `sieves` (m, ascending;
// classes: below the first sieve, between sieves, above the last): returns the product's cumulative passing.
std::vector<double> breakage_event(const std::vector<double>& feed_passing, const std::vector<double>& sieves,
                                   double s, const BreakageParams& b);

// The pressings' scatter (bed_scatter.hpp) from replicate pourings of the same test (seeds differ): each pouring's
// peak pressure in the deepest loop all completed; N_eff of a die's bed from its feed by the flow model's size classes.
double loop_peak_pressure(const PressLoop& L);                      // Pa
// Each pouring's peak (Pa) at the deepest s_max every pouring completed (that s_max in *s_max); std::invalid_argument
// if a pouring holds no loop or the pourings share no s_max.
std::vector<double> common_depth_peaks(const std::vector<PistonDieResult>& pourings, double* s_max = nullptr);
double die_effective_lumps(const PistonDieResult& r);
// sigma_1 = relative std of the peaks x sqrt(mean N_eff); std::invalid_argument for fewer than two pourings.
double lump_std_of_pourings(const std::vector<PistonDieResult>& pourings);

// The fitted material (the flow model's FlowMaterial) with the fit's provenance.
struct MaterialFit {
  FlowMaterial material;
  PowerLawFit pressure_fit;          // the material's law (in u when it diverges)
  PowerLawFit power_fit;             // p = E s^n over the same points, for comparison
  double rebound_rms = 0.0;          // Pa
  double psd_rms_pct = 0.0;          // rms misfit of the cumulative passing over the fitted sieves (%)
  std::vector<std::string> fitted;   // names of the breakage parameters fitted (others default)
  std::string breakage_note;         // which classes the fit is valid for, or why it was not fitted
  std::vector<std::string> comments; // extra provenance lines for the yaml
};

// From a DEM run: all loading points of all loops for the pressure law, the loops for rebound, the PSDs for
// breakage (sieves >= min_resolved only).
enum class PressureLaw { power, solid_divergence };  // bed_compaction.hpp
MaterialFit fit_flow_material(const PistonDieResult& r, PressureLaw law = PressureLaw::power);
// Pooled over replicate pourings of one test (seeds differ): the pressure law on every pouring's deepest loading
// branch together, rebound on every loop, breakage on every loop from its own pouring's feed; loose fraction the
// pourings' total rock mass over their total solid mass at loose volume. std::invalid_argument if empty.
MaterialFit fit_flow_material(const std::vector<PistonDieResult>& pourings, PressureLaw law = PressureLaw::power);
// The same over pourings held elsewhere (the jackknife's subsets, without copying them).
MaterialFit fit_flow_material(const std::vector<const PistonDieResult*>& pourings,
                              PressureLaw law = PressureLaw::power);

// Laboratory piston-die data: points in order; phase 0 loading, 1 unloading (-1: from the direction of s).
struct LabPoint {
  double s = 0.0, p = 0.0;  // -, Pa
  int phase = -1;
};
// Reads CSV "s,p_MPa[,phase]" (phase: load/unload or 0/1); std::invalid_argument naming the line on bad input.
std::vector<LabPoint> read_lab_csv(const std::string& file);
// Pressure law and rebound from lab loops (a new loop starts where loading follows unloading); breakage and
// loose_solid_fraction keep their defaults (the lab file holds no PSD nor mass).
MaterialFit fit_flow_material_lab(const std::vector<LabPoint>& pts);

// Writes the flow_material yaml (format fixed: the flow model reads it), provenance as comments above.
void write_flow_material_yaml(const MaterialFit& m, const std::string& file,
                              const std::vector<std::string>& provenance);

}  // namespace chamber
