#pragma once
// Parameters of the DEM side of a coupled crusher run: the chamber between the liners, the feed of
// breakable rocks, the discharge and its screening, and the concave force map (section 4.2.3).
// Read from the `dem:` section of a run config; the liner profiles come from the `mbd:` section so
// both solvers use one geometry.
#include <string>
#include <vector>

#include "core/chamber_geometry.hpp"
#include "core/config.hpp"
#include "core/config_schema.hpp"
#include "chamber/flow_model.hpp"
#include "coupling/metaparticle_crushing.hpp"
#include "rocks/bpm_config.hpp"

namespace coupling {

struct FeedParams {
  int shapes = 4;                  // irregular rock shapes (section 2.4.1: four)
  double rock_size_m = 0.05;       // -50 mm feed (section 3.2)
  unsigned long long seed = 7;
  double choke_height_m = 0.08;    // keep rock up to this height above the chamber top (choke feeding)
  double max_rate_kg_s = 40.0;     // upper bound of the feeder
  double drop_speed_m_s = 1.0;     // initial downward speed of a fed rock
  double max_fed_kg = 1e9;         // stop feeding after this mass (short test cases)
  // Pre-filled chamber: at t = 0, rocks at rest fill the chamber between the liners bottom up to the choke
  // level (or to prefill_max_kg / max_fed_kg), so crushing starts at once; counted as fed.
  bool prefill = false;
  double prefill_max_kg = 1e9;
  // Solid density of the fed rock (kg/m^3). A rock packed to solid fraction phi with spheres of the material's
  // density rho weighs phi rho V; with rock_density set, its spheres are made heavier (rock_density V / their
  // volume, ~rock_density / phi) so that it weighs rock_density V. Sizes stay the spheres' (crushing strength,
  // screening), and a crushed sphere's grown fragments keep its volume. 0: spheres at the material's density
  // (Table 4: 2600).
  double rock_density = 0;
};

struct ChamberParams {
  core::ChamberGeometry chamber;      // liner profiles in the liner frames (origin at O1)
  double mantle_com_z_m = 0;          // floating cone COM on its axis, liner frame
  double concave_com_z_m = 0;         // fixed cone COM on its axis, liner frame
  int liner_sectors = 72;             // azimuthal tessellation of both liners
  double dt_s = 0;                    // DEM step; 0: 0.8 x the engine's stable bound (Rayleigh, bonds)
  int threads = 0;                    // 0: all cores
  FeedParams feed;
  // The calibrated bonded-particle model: metaparticle sizes, packing and bonds (Eq. 20-25) belong
  // together (coarse-graining: the smallest fragment is one metaparticle, which bounds the finest product).
  rocks::BpmModel bpm;
  double discharge_below_m = 0.05;    // fragments whose centre falls this far below the chamber bottom leave
  std::vector<double> sieves_m{1e-3, 2e-3, 4e-3, 8e-3, 12e-3, 16e-3, 22.4e-3, 31.5e-3, 40e-3, 50e-3, 63e-3};
  int rings = 13, sectors = 9;        // concave force map (section 4.2.3)
  double bookkeeping_s = 2e-3;        // feed / discharge / fragment update interval
  double throughput_window_s = 0.5;   // discharged-mass rate averaged over this window
  int tracked_particles = 4;          // trajectories of a few particles (section 4.2.2)
  CrushingParams crushing;            // metaparticles crushed to fines against the liners (off: the paper's model)
  // dem.fines: flow: crushed fines stay in the chamber, carried by the chamber flow model (src/chamber) with the
  // `flow:` section's material, cells and sieves, as fines only (chamber::fines_only); discharge: they leave at once.
  bool fines_flow = false;
  chamber::FlowParams fines;          // when fines_flow
  std::string bpm_file;               // config: dem.bpm_file as given ("" none: the bpm mapping); its model is in bpm
  // Not a config key: the blow-up's state dump (dem::WorldParams::blowup_dump_path), set by the caller to a file in
  // the run's folder (dem_node: ~out/dem_blowup.csv); "": an unguessable name in the temporary folder.
  std::string blowup_dump_path;
};

// The keys of the `dem:` section (config_schema.hpp) but `bpm:` (rocks/bpm_config.hpp) and what the mechanism gives.
const core::Schema<ChamberParams>& chamber_schema();

// Reads the `dem:` mapping; `chamber` and the COM heights come from the mechanism parameters.
// The BPM is `dem.bpm` (inline, rocks/bpm_config.hpp format) or `dem.bpm_file` (a file such as
// bpm_calibrated.yaml written by the calibration, relative to the config's folder). flow: the config's `flow:`
// mapping, read for dem.fines: flow (null: the flow model's defaults). The retired `dem.fines_bed` is refused,
// naming what replaced it.
ChamberParams load_chamber_params(const core::ConfigNode& dem, const core::ChamberGeometry& chamber,
                                  double mantle_com_z_m, double concave_com_z_m,
                                  const core::ConfigNode* flow = nullptr);

}  // namespace coupling
