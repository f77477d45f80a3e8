#pragma once
// The `flow:` section of a run configuration (the chamber flow model, run.load flow) and the material file the
// virtual piston-die test writes (flow_material.yaml). Units in the key names, SI after loading.
//
//   flow:
//     material_file: flow_material.yaml   # relative to the config's folder; keys of `material:` override it
//     material: {...}                     # optional, same keys as the file's flow_material mapping
//     bands: 30                           # height bands over the chamber (>= 2)
//     sectors: 16                         # azimuth sectors
//     sieves_mm: [1, 2, ..., 63]          # ascending
//     feed_passing_pct: [...]             # cumulative feed passing each sieve (default: -50 mm, (x/50)^2.5)
//     prefill: true                       # start with the chamber full of loose feed
//     seed: 1                             # of the pressings' scatter (material scatter.lump_std > 0)
//     effects:                            # chamber candidates of the diagnosis, off by default
//       feed_limited: {enabled: false, max_feed_tph: 60}
//       worn_liners: {enabled: false, setting_increase_mm: 10, worn_height_fraction: 0.5}
//
//   flow_material:                        # (the file; also the `material:` mapping above)
//     solid_density_kg_m3: 2600
//     loose_solid_fraction: 0.55
//     pressure: {modulus_MPa: 50, exponent: 2.0, rebound: 0.15, max_compression: 0.40}
//     scatter: {lump_std: 0}              # one lump's relative std (bed_scatter.hpp; piston_die --replicates)
//     selection: {s_c: 0.25, exponent: 2.0, size_exponent: 0.5, x_ref_mm: 10}
//     progeny: {phi: 0.4, gamma: 0.8, beta: 3.0}
#include <string>

#include "chamber/flow_model.hpp"
#include "core/config.hpp"
#include "core/config_schema.hpp"
#include "core/run_config.hpp"
#include "mbd/mechanism_params.hpp"

namespace chamber {

// The keys of a flow_material mapping and of the `flow:` section (its `material:` is the former).
const core::Schema<FlowMaterial>& flow_material_schema();
const core::Schema<FlowParams>& flow_schema();
// Reads a flow_material mapping over `base` (keys not given keep base's values); the caller runs finish().
FlowMaterial flow_material_from_config(const core::ConfigNode& node, const FlowMaterial& base = FlowMaterial());
FlowMaterial load_flow_material(const std::string& file);  // the file's `flow_material:` mapping, finish() checked
// Reads the `flow:` mapping (material file resolved against node.file()'s folder); the caller runs finish().
FlowParams load_flow_params(const core::ConfigNode& flow);
// A run config as a flow run reads it: the mechanism, the flow model and the run; coupling: checked too, dem: left
// to dem_node; finish() checked (an unknown key is refused by name). For the tools and tests that run flow mode
// without mbd_node.
struct FlowRunConfig {
  mbd::MechanismParams mech;
  FlowParams flow;
  core::RunOptions run;
};
FlowRunConfig load_flow_run_config(const std::string& file);
// `flow_material:` YAML text of m (with the top-level key), which load_flow_material reads back.
std::string flow_material_yaml(const FlowMaterial& m);

}  // namespace chamber
