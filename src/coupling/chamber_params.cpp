#include "coupling/chamber_params.hpp"

#include "chamber/flow_config.hpp"
#include "core/units.hpp"

namespace coupling {

namespace u = core::units;
using core::ConfigNode;

// Plausible bands (core::Schema::plausible, issue 22): a value inside a key's range but ~1000x off is a unit slip.
// A band equal to the range (rock_size_mm, rock_density_kg_m3, ...) only names the slip of a value it refuses.
using core::kMetresForMm;

const core::Schema<ChamberParams>& chamber_schema() {
  using P = ChamberParams;
  static const core::Schema<ChamberParams> s = [] {
    core::Schema<ChamberParams> k;
    k.integer("liner_sectors", 12, 720, [](P& p) -> int& { return p.liner_sectors; },
              "azimuthal facets of both liner meshes")
        .number("dt_s", "s (0: automatic)", 1, 0, 1e-3, [](P& p) -> double& { return p.dt_s; },
                "DEM step; 0: 0.8 x the engine's stable bound")
        .integer("threads", 0, 256, [](P& p) -> int& { return p.threads; }, "OpenMP threads (0: all cores)")
        .number("discharge_below_mm", "mm", u::mm, 0, 1000, [](P& p) -> double& { return p.discharge_below_m; },
                "fragments this far below the chamber bottom leave (screened)")
        .plausible(1, 1000, kMetresForMm, "")  // below the chamber: from 1 mm (0: at its edge)
        .numbers("sieves_mm", "mm", u::mm, 0.01, 1000, [](P& p) -> std::vector<double>& { return p.sieves_m; },
                 "product sieves, strictly ascending", false,
                 [](const ConfigNode& n, const std::string& key, P& p) {
                   for (std::size_t i = 1; i < p.sieves_m.size(); ++i)
                     if (p.sieves_m[i] <= p.sieves_m[i - 1]) n.fail(key, "sizes must be strictly ascending");
                 })
        .plausible(0.02, 1000, kMetresForMm, "")  // sieves from 20 um, as flow.sieves_mm
        .integer("force_map_rings", 1, 100, [](P& p) -> int& { return p.rings; }, "concave force map: rings")
        .integer("force_map_sectors", 1, 100, [](P& p) -> int& { return p.sectors; }, "concave force map: sectors")
        .number("bookkeeping_s", "s", 1, 1e-5, 0.1, [](P& p) -> double& { return p.bookkeeping_s; },
                "feed, discharge and fragment update interval")
        .number("throughput_window_s", "s", 1, 0.01, 100, [](P& p) -> double& { return p.throughput_window_s; },
                "discharged-mass rate averaged over this window")
        .integer("tracked_particles", 0, 100, [](P& p) -> int& { return p.tracked_particles; },
                 "particles whose paths go to trajectories.csv")
        .boolean("crushing.enabled", [](P& p) -> bool& { return p.crushing.enabled; },
                 "metaparticles crushed to fines against the liners (default true when crushing: is given)")
        .number("crushing.tensile_strength_MPa", "MPa", u::MPa, 0.01, 1000,
                [](P& p) -> double& { return p.crushing.tensile_strength; }, "rock tensile strength sigma_t (Eq. 26)")
        // Brazilian tensile strength of rock: ~0.1 MPa (weak shale, chalk) to ~30 MPa (basalt, quartzite); marble 3.77
        .plausible(0.1, 100, "GPa given for MPa?", "kPa given for MPa?")
        .number("crushing.progeny_exponent", "", 1, 0.1, 5, [](P& p) -> double& { return p.crushing.progeny_exponent; },
                "Gaudin-Schuhmann slope of the fines")
        .number("crushing.batch_s", "s", 1, 0, 0.01, [](P& p) -> double& { return p.crushing.batch_s; },
                "crushed spheres leave together at this interval")
        .choice("crushing.criterion", {"contact", "stress"},
                [](const P& p) { return std::string(p.crushing.stress_criterion ? "stress" : "contact"); },
                [](P& p, const std::string& v) { p.crushing.stress_criterion = v == "stress"; },
                "crush on the liner contacts, or on the sphere's whole load")
        .boolean("crushing.fragments", [](P& p) -> bool& { return p.crushing.fragments; },
                 "a crushed sphere becomes four fragments (else fines at once)")
        .number("crushing.min_fragment_mm", "mm", u::mm, 0.1, 1000,
                [](P& p) -> double& { return p.crushing.min_fragment_m; }, "fragments below this leave as fines")
        .plausible(0.1, 1000, kMetresForMm, "")
        .number("crushing.fragment_growth_s", "s", 1, 0, 1, [](P& p) -> double& { return p.crushing.fragment_growth_s; },
                "time a fragment takes to grow to the rock's density (0: none)")
        .number("crushing.reference_size_mm", "mm", u::mm, 1, 10000,
                [](P& p) -> double& { return p.crushing.reference_size; }, "size at which the strength was measured")
        .plausible(1, 10000, kMetresForMm, "")
        .number("crushing.size_exponent", "", 1, 0, 1.5, [](P& p) -> double& { return p.crushing.size_exponent; },
                "size effect of the strength (0: none)")
        .choice("fines", {"discharge", "flow"}, [](const P& p) { return std::string(p.fines_flow ? "flow" : "discharge"); },
                [](P& p, const std::string& v) { p.fines_flow = v == "flow"; },
                "crushed fines: leave at once (discharge), or stay in the chamber carried by the chamber flow model "
                "with the flow: section's material, cells and sieves (flow)")
        .integer("feed.shapes", 1, 16, [](P& p) -> int& { return p.feed.shapes; }, "irregular rock shapes")
        .number("feed.rock_size_mm", "mm", u::mm, 5, 300, [](P& p) -> double& { return p.feed.rock_size_m; },
                "feed top size", true)
        .plausible(5, 300, kMetresForMm, "")
        .integer("feed.seed", 0, 2147483647, [](P& p) -> unsigned long long& { return p.feed.seed; },
                 "random seed of the feed")
        .number("feed.choke_height_mm", "mm", u::mm, 0, 2000, [](P& p) -> double& { return p.feed.choke_height_m; },
                "rock kept up to this height above the chamber top")
        .plausible(5, 2000, kMetresForMm, "")  // at least the smallest feed rock (rock_size_mm from 5 mm); 0: none
        .number("feed.max_rate_kg_s", "kg/s", 1, 0.01, 1e4, [](P& p) -> double& { return p.feed.max_rate_kg_s; },
                "feeder's upper bound")
        .number("feed.drop_speed_m_s", "m/s", 1, 0, 20, [](P& p) -> double& { return p.feed.drop_speed_m_s; },
                "initial downward speed of a fed rock")
        .number("feed.max_fed_kg", "kg", 1, 0, 1e9, [](P& p) -> double& { return p.feed.max_fed_kg; },
                "stop feeding after this mass")
        .boolean("feed.prefill", [](P& p) -> bool& { return p.feed.prefill; },
                 "the chamber starts full of rock at rest")
        .number("feed.prefill_max_kg", "kg", 1, 0, 1e9, [](P& p) -> double& { return p.feed.prefill_max_kg; },
                "prefill at most this mass")
        .number("feed.rock_density_kg_m3", "kg/m^3", 1, 500, 20000, [](P& p) -> double& { return p.feed.rock_density; },
                "solid density of the fed rock (unset: the spheres' material density)")
        .plausible(500, 20000, "g/cm^3 given for kg/m^3?", "")
        .text("bpm_file", [](P& p) -> std::string& { return p.bpm_file; },
              "calibrated BPM file (relative to the config; else the bpm: mapping, src/rocks/README.md)", false,
              [](const ConfigNode& n, const std::string& key, P& p) {
                const std::string f = n.path_beside(key, p.bpm_file);
                try {
                  p.bpm = rocks::load_bpm_model(f);
                } catch (const std::exception& e) {
                  n.fail(key, e.what());
                }
              })
        .load_only();
    return k;
  }();
  return s;
}

ChamberParams load_chamber_params(const ConfigNode& dem, const core::ChamberGeometry& chamber,
                                  double mantle_com_z_m, double concave_com_z_m, const ConfigNode* flow) {
  ChamberParams p;
  p.chamber = chamber;
  p.mantle_com_z_m = mantle_com_z_m;
  p.concave_com_z_m = concave_com_z_m;
  if (dem.has("fines_bed"))
    dem.fail("fines_bed", "was replaced by dem.fines: flow (the crushed fines are carried by the chamber flow model, "
                          "its material, cells and sieves from the flow: section); remove dem.fines_bed");
  p.crushing.enabled = dem.has("crushing");  // a crushing: mapping turns it on unless it says not
  chamber_schema().read(dem, p);
  if (p.fines_flow && !p.crushing.enabled) dem.fail("fines", "flow carries the fines of dem.crushing, which is off");
  if (p.fines_flow && flow && !flow->has("material") && !flow->has("material_file"))
    dem.fail("fines", "flow takes the fines' material from the flow: section (flow.material or flow.material_file, as "
                      "the fast mode reads it); this config has neither");
  if (p.fines_flow) p.fines = chamber::fines_only(flow ? chamber::load_flow_params(*flow) : chamber::FlowParams());
  if (!dem.has("bpm_file")) p.bpm = rocks::bpm_model_from_config(dem.child("bpm"));
  return p;
}

}  // namespace coupling
