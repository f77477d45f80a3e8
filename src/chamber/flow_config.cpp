#include "chamber/flow_config.hpp"

#include <cmath>
#include <sstream>

#include "core/units.hpp"

namespace chamber {

namespace u = core::units;
using core::ConfigNode;

// Plausible bands (core::Schema::plausible, issue 22): sizes in mm that are ~1000x too small were given in metres.
// Sieves from 20 um, reference sizes from 0.1 mm, liner wear from 0.5 mm (0 is accepted: no wear).
using core::kMetresForMm;

const core::Schema<FlowMaterial>& flow_material_schema() {
  using M = FlowMaterial;
  static const core::Schema<FlowMaterial> s = [] {
    core::Schema<FlowMaterial> k;
    k.number("solid_density_kg_m3", "kg/m^3", 1, 500, 20000, [](M& m) -> double& { return m.solid_density; },
             "density of the solid rock")
        .number("loose_solid_fraction", "", 1, 0.2, 0.8, [](M& m) -> double& { return m.loose_fraction; },
                "solid fraction of the loose (poured) bed")
        .number("pressure.modulus_MPa", "MPa", u::MPa, 0.01, 1e5, [](M& m) -> double& { return m.modulus_Pa; },
                "virgin loading p = E u^n: E")
        .number("pressure.exponent", "", 1, 1, 6, [](M& m) -> double& { return m.exponent; },
                "virgin loading p = E u^n: n")
        .number("pressure.rebound", "", 1, 0.01, 1, [](M& m) -> double& { return m.rebound; },
                "recovered fraction of each compression")
        .number("pressure.max_compression", "", 1, 0.05, 0.8, [](M& m) -> double& { return m.max_compression; },
                "compaction limit, at most the solid's 1 - loose_solid_fraction")
        .choice(
            "pressure.law", {"power", "solid_divergence"},
            [](const M& m) { return std::string(m.solid_divergence ? "solid_divergence" : "power"); },
            [](M& m, const std::string& v) { m.solid_divergence = v == "solid_divergence"; },
            "virgin loading p = E u^n in u = s (power) or u = s / (1 - s / (1 - loose_solid_fraction)) (solid_divergence: "
            "the pressure diverges at the solid's density; max_compression below that limit)")
        .choice(
            "pressure.at_limit", {"extrude", "elastic"},
            [](const M& m) { return std::string(m.elastic_limit ? "elastic" : "extrude"); },
            [](M& m, const std::string& v) { m.elastic_limit = v == "elastic"; },
            "rock pressed past max_compression: extrude (pressed out into the cell below at the limit's pressure) or "
            "elastic (held; the pressure rises along the law's reloading stiffness at the limit, without loss: "
            "src/chamber/bed_limit.hpp)")
        .number("scatter.lump_std", "", 1, 0, kMaxLumpStd, [](M& m) -> double& { return m.lump_std; },
                "relative std of one lump's share of a bed's pressure, from replicate piston-die tests (0: the "
                "pressings do not scatter)")
        .number("refill.length_mm", "mm", u::mm, 0, 1000, [](M& m) -> double& { return m.refill_length_m; },
                "a released bed refills the opening gap as its rock falls, the share 1 - exp(-g t^2 / (2 d)) after t "
                "seconds: d (0: at once, the hysteretic law; src/chamber/bed_refill.hpp)")
        .plausible(0.5, 1000, kMetresForMm, "")
        .number("packing.compaction_index", "", 1, 0, 20, [](M& m) -> double& { return m.packing_index; },
                "the mixture's packing: compaction index K of de Larrard's packing model (4.1: a simple pour; 0: one "
                "loose fraction for every size mixture; src/chamber/mixture_packing.hpp)")
        .number("packing.reference_min_mm", "mm", u::mm, 0.01, 1000,
                [](M& m) -> double& { return m.packing_ref_min_m; },
                "smallest size of the bed that packs to loose_solid_fraction (the piston die's rocks)")
        .plausible(0.1, 1000, kMetresForMm, "")
        .number("packing.reference_max_mm", "mm", u::mm, 0.01, 1000,
                [](M& m) -> double& { return m.packing_ref_max_m; },
                "largest size of the bed that packs to loose_solid_fraction (the piston die's rocks)")
        .plausible(0.1, 1000, kMetresForMm, "")
        .number("selection.s_c", "", 1, 1e-3, 10, [](M& m) -> double& { return m.breakage.s_c; },
                "compression at which a class of size x_ref is 63 % selected")
        .number("selection.exponent", "", 1, 0.1, 10, [](M& m) -> double& { return m.breakage.m; },
                "selection exponent")
        .number("selection.size_exponent", "", 1, 0, 5, [](M& m) -> double& { return m.breakage.q; },
                "size exponent of s_c")
        .number("selection.x_ref_mm", "mm", u::mm, 0.01, 1000, [](M& m) -> double& { return m.breakage.x_ref; },
                "reference size of s_c")
        .plausible(0.1, 1000, kMetresForMm, "")
        .number("selection.resolved_mm", "mm", u::mm, 0, 1000, [](M& m) -> double& { return m.breakage.x_resolved; },
                "smallest size the selection law was measured at (0: it holds at every size)")
        .plausible(0.1, 1000, kMetresForMm, "")
        .number("selection.size_exponent_below", "", 1, 0, 5, [](M& m) -> double& { return m.breakage.q_below; },
                "size exponent of s_c below resolved_mm: the ISRM point-load strength's 0.45 over the pressure exponent n")
        .number("progeny.phi", "", 1, 0, 1, [](M& m) -> double& { return m.breakage.phi; },
                "progeny: weight of the fine part")
        .number("progeny.gamma", "", 1, 0.01, 10, [](M& m) -> double& { return m.breakage.gamma; },
                "progeny: exponent of the fine part")
        .number("progeny.beta", "", 1, 0.01, 20, [](M& m) -> double& { return m.breakage.beta; },
                "progeny: exponent of the coarse part");
    return k;
  }();
  return s;
}


const core::Schema<FlowParams>& flow_schema() {
  using P = FlowParams;
  static const core::Schema<FlowParams> s = [] {
    core::Schema<FlowParams> k;
    k.text("material_file", [](P& p) -> std::string& { return p.material_file; },
           "flow_material file (relative to the config); keys under material override it", false,
           [](const ConfigNode& n, const std::string& key, P& p) {
             p.material = load_flow_material(n.path_beside(key, p.material_file));
           })
        .load_only()
        .include<FlowMaterial>("material", flow_material_schema(), [](P& p) -> FlowMaterial& { return p.material; })
        .integer("bands", 2, 400, [](P& p) -> int& { return p.bands; }, "height bands over the chamber")
        .integer("sectors", 1, 360, [](P& p) -> int& { return p.sectors; }, "azimuth sectors")
        .numbers("sieves_mm", "mm", u::mm, 0.01, 1000, [](P& p) -> std::vector<double>& { return p.sieves_m; },
                 "product sieves, strictly ascending", false,
                 [](const ConfigNode& n, const std::string& key, P& p) {
                   for (std::size_t i = 1; i < p.sieves_m.size(); ++i)
                     if (p.sieves_m[i] <= p.sieves_m[i - 1]) n.fail(key, "sizes must be strictly ascending");
                   p.feed_passing = default_feed_passing(p.sieves_m);  // on the new sieves, unless given
                 })
        .plausible(0.02, 1000, kMetresForMm, "")
        .numbers("feed_passing_pct", "%", 0.01, 0, 100, [](P& p) -> std::vector<double>& { return p.feed_passing; },
                 "feed passing each sieve, not falling (default: -50 mm, (x / 50 mm)^2.5)", false,
                 [](const ConfigNode& n, const std::string& key, P& p) {
                   if (p.feed_passing.size() != p.sieves_m.size())
                     n.fail(key, "must have exactly " + std::to_string(p.sieves_m.size()) + " numbers, has " +
                                     std::to_string(p.feed_passing.size()));
                   for (std::size_t i = 1; i < p.feed_passing.size(); ++i)
                     if (p.feed_passing[i] < p.feed_passing[i - 1]) n.fail(key, "must not fall from sieve to sieve");
                 })
        .text("calibration_unknowns", [](P& p) -> std::string& { return p.calibration_unknowns; },
              "machine values `crusher calibrate --flow` fits at 400 rpm: up to three of static_moment, discharge, "
              "feed, bearing_mu, comma separated (default static_moment,discharge,feed)")
        .boolean("prefill", [](P& p) -> bool& { return p.prefill; }, "start with the chamber full of loose feed")
        .integer("seed", 0, 2147483647, [](P& p) -> int& { return p.seed; },
                 "seed of the pressings' scatter (material scatter.lump_std > 0)")
        .boolean("compaction_memory", [](P& p) -> bool& { return p.compaction_memory; },
                 "the rock keeps its compaction between pressings (on the GYP1200, calibrated at 400 rpm, the 600 rpm "
                 "chamber fails: extrude overruns the bed, elastic chokes it; src/chamber/README.md)")
        // Chamber candidates of the diagnosis (flow_model.hpp FlowEffects), off by default.
        .boolean("effects.feed_limited.enabled", [](P& p) -> bool& { return p.effects.feed_limited.enabled; },
                 "at most a feeder's rate enters the chamber (choke feed below it)")
        .number("effects.feed_limited.max_feed_tph", "t/h", 1.0 / 3.6, 0.1, 1e4,
                [](P& p) -> double& { return p.effects.feed_limited.max_feed_kg_s; },
                "feeder rate into the top band (main parameter; below the choke-fed throughput to matter)")
        .boolean("effects.worn_liners.enabled", [](P& p) -> bool& { return p.effects.worn_liners.enabled; },
                 "the concave worn over the lower chamber: the setting wider toward the discharge")
        .number("effects.worn_liners.setting_increase_mm", "mm", u::mm, 0.0, 100.0,
                [](P& p) -> double& { return p.effects.worn_liners.setting_increase_m; },
                "wear depth at the discharge (main parameter; a liner is replaced after ~10-30 mm)")
        .plausible(0.5, 100, kMetresForMm, "")
        .number("effects.worn_liners.worn_height_fraction", "", 1, 0.01, 1.0,
                [](P& p) -> double& { return p.effects.worn_liners.worn_height_fraction; },
                "height of the worn zone over the chamber's height, from the discharge up (wear 0 at its top)")
        .boolean("effects.squeeze_flow.enabled", [](P& p) -> bool& { return p.effects.squeeze_flow.enabled; },
                 "rock at the compaction limit is pressed out along the liners against their friction")
        .number("effects.squeeze_flow.wall_friction", "", 1, 0.0, 2.0,
                [](P& p) -> double& { return p.effects.squeeze_flow.wall_friction; },
                "Coulomb friction of the pressed rock on both liners (rock on steel 0.7, Table 4)")
        .number("effects.squeeze_flow.escape_length_mm", "mm", u::mm, 0.0, SqueezeFlow::kMaxEscapeLength_mm,
                [](P& p) -> double& { return p.effects.squeeze_flow.escape_length_m; },
                "path along the liners from the nip to where the pressed-out rock is free (main parameter; "
                "30 mm blows up the mechanism's explicit coupling)")
        .plausible(0.5, SqueezeFlow::kMaxEscapeLength_mm, kMetresForMm, "")
        .boolean("effects.liner_friction.enabled", [](P& p) -> bool& { return p.effects.liner_friction.enabled; },
                 "the pressed rock's Coulomb friction against the mantle's slip over it")
        .number("effects.liner_friction.wall_friction", "", 1, 0.0, 2.0,
                [](P& p) -> double& { return p.effects.liner_friction.wall_friction; },
                "Coulomb friction of the pressed rock on the liners (main parameter; rock on steel 0.7, Table 4)")
        .number("effects.liner_friction.regularisation_mm_s", "mm/s", u::mm, 0.001, 1000.0,
                [](P& p) -> double& { return p.effects.liner_friction.regularisation_m_s; },
                "slip speed over which the friction rises to mu N (tanh; 20 mm/s chatters at a 1 ms step)");
    k.flow_style("effects.feed_limited");
    k.flow_style("effects.liner_friction");
    k.flow_style("effects.squeeze_flow");
    k.flow_style("effects.worn_liners");
    return k;
  }();
  return s;
}

FlowMaterial flow_material_from_config(const ConfigNode& n, const FlowMaterial& base) {
  FlowMaterial m = base;
  flow_material_schema().read(n, m);
  return m;
}

FlowMaterial load_flow_material(const std::string& file) {
  auto root = ConfigNode::load_file(file);
  FlowMaterial m = flow_material_from_config(root.child("flow_material"));
  root.finish();
  return m;
}

FlowParams load_flow_params(const ConfigNode& f) {
  FlowParams p;
  flow_schema().read(f, p);
  return p;
}

FlowRunConfig load_flow_run_config(const std::string& file) {
  auto root = ConfigNode::load_file(file);
  FlowRunConfig c;
  c.mech = mbd::load_mechanism_params(root.child("mbd"));
  c.flow = load_flow_params(root.child_or_empty("flow"));
  c.run = core::load_run_options(root.child("run"));
  core::load_coupling_options(root.child_or_empty("coupling"));
  root.ignore("dem");
  root.ignore("diagnosis");  // crusher diagnose's uncertain values
  root.finish();
  return c;
}

std::string flow_material_yaml(const FlowMaterial& m) {
  YAML::Node root;
  root["flow_material"] = flow_material_schema().write(m);
  YAML::Emitter e;
  e << root;
  return std::string(e.c_str()) + "\n";
}

}  // namespace chamber
