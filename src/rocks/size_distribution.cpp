#include "rocks/size_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/units.hpp"

namespace rocks {

using core::units::mm;

SizeDistribution::SizeDistribution(std::vector<SizeMode> modes, double truncate_sd, double min_radius)
    : modes_(std::move(modes)), truncate_sd_(truncate_sd), min_radius_(min_radius) {
  if (modes_.empty()) throw std::invalid_argument("SizeDistribution: needs at least one mode");
  if (!(truncate_sd_ > 0.0 && truncate_sd_ <= 5.0))
    throw std::invalid_argument("SizeDistribution: truncate_sd must be in (0, 5]");
  double sum = 0.0;
  for (const auto& m : modes_) {
    if (!(m.mean_radius > 0.0) || !(m.sd >= 0.0) || !(m.volume_fraction > 0.0))
      throw std::invalid_argument(
          "SizeDistribution: each mode needs mean_radius > 0, sd >= 0, volume_fraction > 0");
    if (m.mean_radius - truncate_sd_ * m.sd <= 0.0)
      throw std::invalid_argument("SizeDistribution: mode with mean radius " +
                                  std::to_string(m.mean_radius) +
                                  " m reaches radius <= 0 at its truncation; lower sd or truncate_sd");
    sum += m.volume_fraction;
  }
  if (std::abs(sum - 1.0) > 1e-9)
    throw std::invalid_argument("SizeDistribution: volume fractions must sum to 1 (got " +
                                std::to_string(sum) + ")");
}

SizeDistribution SizeDistribution::preset(const std::string& name) {
  auto bimodal = [](double scale) {
    // Section 2.4.1; the paper does not give the mixing ratio: 70 % of the solid volume in the
    // coarse end is near the densest random packing of a 3:1 binary mixture.
    return SizeDistribution({{3.0 * mm * scale, 0.525 * mm * scale, 0.7},
                             {1.0 * mm * scale, 0.225 * mm * scale, 0.3}},
                            2.0);
  };
  if (name == "paper_bimodal") return bimodal(1.0);
  if (name == "crusher_coarse") return bimodal(2.0);
  if (name == "crusher_coarse3") return bimodal(3.0);
  if (name == "mono3") return SizeDistribution({{3.0 * mm, 0.3 * mm, 1.0}}, 2.0);
  std::string list;
  for (const auto& n : preset_names()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument("SizeDistribution: unknown preset '" + name + "'; accepted: " + list);
}

std::vector<std::string> SizeDistribution::preset_names() {
  return {"paper_bimodal", "crusher_coarse", "crusher_coarse3", "mono3"};
}

const core::Schema<MetaparticleKeys>& metaparticles_schema() {
  using K = MetaparticleKeys;
  static const core::Schema<K> s = [] {
    constexpr double mm = 1e-3;
    auto modes = [](const K& k) { return k.preset.empty(); };
    auto two = [](const K& k) { return k.preset.empty() && k.fine_mean_radius >= 0; };
    core::Schema<K> k;
    k.choice("preset", SizeDistribution::preset_names(), [](K& o) -> std::string& { return o.preset; },
             "a named distribution (src/rocks/README.md); else the modes below")
        .number("truncate_sd", "sd", 1, 0.5, 5.0, [](K& o) -> double& { return o.truncate_sd; },
                "each mode cut at this many standard deviations")
        .applies_if(modes, "modes (no preset)", "no preset")
        .number("coarse.mean_radius_mm", "mm", mm, 0.05, 100.0, [](K& o) -> double& { return o.coarse_mean_radius; },
                "mean radius of the (coarse) mode", true)
        .plausible(0.05, 100, core::kMetresForMm, "")  // the range: names the slip of 0.006
        .applies_if(modes, "modes (no preset)", "no preset")
        .number("coarse.sd_mm", "mm", mm, 0.0, 50.0, [](K& o) -> double& { return o.coarse_sd; },
                "its standard deviation", true)
        .plausible(0.01, 50, core::kMetresForMm, "")  // 0 or from 10 um: a 0.7 mm sd given in metres is caught
        .applies_if(modes, "modes (no preset)", "no preset")
        .number("fine.mean_radius_mm", "mm", mm, 0.05, 100.0, [](K& o) -> double& { return o.fine_mean_radius; },
                "mean radius of the fine mode (unset: one mode)")
        .plausible(0.05, 100, core::kMetresForMm, "")  // the range: names the slip of 0.006
        .applies_if(modes, "modes (no preset)", "no preset")
        .number("fine.sd_mm", "mm", mm, 0.0, 50.0, [](K& o) -> double& { return o.fine_sd; },
                "its standard deviation", true)
        .plausible(0.01, 50, core::kMetresForMm, "")
        .applies_if(two, "two modes (fine.mean_radius_mm given)", "fine.mean_radius_mm is given")
        .number("coarse_volume_fraction", "", 1, 0.01, 0.99, [](K& o) -> double& { return o.coarse_volume_fraction; },
                "share of the solid volume in the coarse mode", true)
        .applies_if(two, "two modes (fine.mean_radius_mm given)", "fine.mean_radius_mm is given");
    return k;
  }();
  return s;
}

MetaparticleKeys metaparticle_keys_from_config(const core::ConfigNode& node) { return metaparticles_schema().read(node); }

SizeDistribution SizeDistribution::from_config(const core::ConfigNode& node) {
  const MetaparticleKeys k = metaparticle_keys_from_config(node);
  if (!k.preset.empty()) return preset(k.preset);
  try {
    if (k.fine_mean_radius < 0) return SizeDistribution({{k.coarse_mean_radius, k.coarse_sd, 1.0}}, k.truncate_sd);
    return SizeDistribution({{k.coarse_mean_radius, k.coarse_sd, k.coarse_volume_fraction},
                             {k.fine_mean_radius, k.fine_sd, 1.0 - k.coarse_volume_fraction}},
                            k.truncate_sd);
  } catch (const std::invalid_argument& e) {
    throw core::ConfigError("config " + node.file() + ": '" + node.path() + "': " + e.what());
  }
}

double SizeDistribution::sample_mode(std::size_t m, Rng& rng) const {
  const SizeMode& s = modes_[m];
  const double lo = std::max(min_radius_, s.mean_radius - truncate_sd_ * s.sd);
  const double hi = s.mean_radius + truncate_sd_ * s.sd;
  for (;;) {  // rejection keeps the normal shape inside the truncation
    const double r = s.mean_radius + s.sd * rng.normal();
    if (r >= lo && r <= hi) return r;
  }
}

double SizeDistribution::sample(Rng& rng) const {
  // Number fraction of a mode ~ volume fraction / mean cube of radius.
  std::vector<double> w(modes_.size());
  double sum = 0.0;
  for (std::size_t m = 0; m < modes_.size(); ++m) {
    const double r = modes_[m].mean_radius, s = modes_[m].sd;
    w[m] = modes_[m].volume_fraction / (r * r * r + 3.0 * r * s * s);
    sum += w[m];
  }
  double u = rng.uniform() * sum;
  for (std::size_t m = 0; m < modes_.size(); ++m) {
    if (u < w[m]) return sample_mode(m, rng);
    u -= w[m];
  }
  return sample_mode(modes_.size() - 1, rng);
}

std::vector<double> SizeDistribution::sample_volume(double solid_volume, Rng& rng) const {
  if (!(solid_volume > 0.0)) throw std::invalid_argument("sample_volume: solid volume must be > 0");
  std::vector<double> radii;
  const double k = 4.0 / 3.0 * core::units::kPi;
  for (std::size_t m = 0; m < modes_.size(); ++m) {
    const double target = modes_[m].volume_fraction * solid_volume;
    double v = 0.0;
    while (v < target) {
      const double r = sample_mode(m, rng);
      // stop at the sphere that brings the mode closest to its target
      const double dv = k * r * r * r;
      if (v + dv - target > target - v && v > 0.0) break;
      radii.push_back(r);
      v += dv;
    }
  }
  std::sort(radii.begin(), radii.end(), [](double a, double b) { return a > b; });
  return radii;
}

double SizeDistribution::min_radius() const {
  double r = 1e300;
  for (const auto& m : modes_) r = std::min(r, std::max(min_radius_, m.mean_radius - truncate_sd_ * m.sd));
  return r;
}

double SizeDistribution::max_radius() const {
  double r = 0.0;
  for (const auto& m : modes_) r = std::max(r, m.mean_radius + truncate_sd_ * m.sd);
  return r;
}

std::string SizeDistribution::describe() const {
  std::ostringstream s;
  for (std::size_t m = 0; m < modes_.size(); ++m)
    s << (m ? " + " : "") << modes_[m].volume_fraction * 100 << "% vol N(" << modes_[m].mean_radius / mm << " mm, "
      << modes_[m].sd / mm << " mm)";
  s << " truncated at +-" << truncate_sd_ << " sd";
  return s.str();
}

}  // namespace rocks
