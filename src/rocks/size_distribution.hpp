#pragma once
// Metaparticle size distributions (section 2.4.1): a mixture of truncated normal modes in radius.
// The paper's bimodal one: coarse mean radius 3 mm, sd 0.525 mm; fine mean radius 1 mm,
// sd 0.225 mm. Coarser presets exist for crusher-scale runs (coarse-graining; see README of rocks).
#include <string>
#include <vector>

#include "core/config.hpp"
#include "core/config_schema.hpp"
#include "rocks/rng.hpp"

namespace rocks {

struct SizeMode {
  double mean_radius = 0.0;      // m
  double sd = 0.0;               // m
  double volume_fraction = 1.0;  // share of the solid volume carried by this mode
};

// The keys of bpm.metaparticles as read (core/config_schema.hpp): a preset, or one or two modes. Lengths in m;
// negative: not given.
struct MetaparticleKeys {
  std::string preset;
  double truncate_sd = 2.0;
  double coarse_mean_radius = -1, coarse_sd = -1, fine_mean_radius = -1, fine_sd = -1;
  double coarse_volume_fraction = -1;
};
const core::Schema<MetaparticleKeys>& metaparticles_schema();
MetaparticleKeys metaparticle_keys_from_config(const core::ConfigNode& node);

class SizeDistribution {
 public:
  // Modes' volume fractions must sum to 1; each mode is truncated at +-truncate_sd standard
  // deviations and never below min_radius. Throws std::invalid_argument on bad input.
  SizeDistribution(std::vector<SizeMode> modes, double truncate_sd = 2.0, double min_radius = 0.0);

  // Named presets: "paper_bimodal" (Cheng et al. 2020, section 2.4.1, 70 % of the volume coarse),
  // "crusher_coarse" (radii x2: 6 mm / 2 mm), "crusher_coarse3" (radii x3), "mono3" (3 mm +-0.3 mm).
  static SizeDistribution preset(const std::string& name);
  static std::vector<std::string> preset_names();
  // From config: either {preset: NAME} or {coarse: {mean_radius_mm, sd_mm}, fine: {...},
  // coarse_volume_fraction, truncate_sd}; "fine" may be left out for a single mode.
  static SizeDistribution from_config(const core::ConfigNode& node);

  // One radius drawn from the mode chosen with probability proportional to number fraction.
  double sample(Rng& rng) const;
  // Radii whose total sphere volume reaches solid_volume (the last one may overshoot by one
  // sphere), drawn so each mode carries its volume fraction. Sorted from large to small.
  std::vector<double> sample_volume(double solid_volume, Rng& rng) const;

  const std::vector<SizeMode>& modes() const { return modes_; }
  double truncate_sd() const { return truncate_sd_; }
  double min_radius() const;   // smallest radius this distribution can produce
  double max_radius() const;   // largest radius this distribution can produce
  std::string describe() const;

 private:
  double sample_mode(std::size_t m, Rng& rng) const;
  std::vector<SizeMode> modes_;
  double truncate_sd_;
  double min_radius_;
};

}  // namespace rocks
