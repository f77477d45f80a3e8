#include "analysis/inputs_report.hpp"
#include "analysis/json_text.hpp"

#include <cmath>
#include <iomanip>
#include <sstream>

namespace analysis {
namespace {
using json::esc;
using json::num;
}  // namespace

std::string inputs_json(const std::vector<const Dataset*>& datasets) {
  std::ostringstream o;
  o << "[";
  for (std::size_t i = 0; i < datasets.size(); ++i) {
    const Dataset& d = *datasets[i];
    o << (i ? ",\n    " : "\n    ") << "{\"dataset\": \"" << esc(d.label) << "\", \"samples\": " << d.rec.size()
      << ", \"channels\": {";
    bool first = true;
    for (int c = 0; c < kNumChannels; ++c) {
      const ChannelUse& u = d.use[c];
      if (!d.rec.has(c)) continue;
      o << (first ? "" : ", ") << "\"" << kChannelNames[c] << "\": {\"use\": \""
        << (u.compared ? "compared" : u.why_not) << "\"";
      if (!u.compared && u.why_not == "set point") o << ", \"setpoint_value\": " << num(u.setpoint_value);
      if (u.compared && is_displacement(c) && !u.mean_compared) o << ", \"mean\": \"not compared (sensor zero unknown)\"";
      o << ", \"resolution\": " << num(u.resolution) << ", \"resolution_from\": \""
        << (u.resolution_estimated ? "data" : "stated") << "\"";
      if (u.compared)
        o << ", \"noise_std\": " << num(std::sqrt(d.sigma2[c])) << ", \"quantisation_std\": "
          << num(std::sqrt(u.quantisation_var)) << ", \"undithered_quantisation_std\": "
          << num(std::sqrt(u.quantisation_systematic));
      o << "}";
      first = false;
    }
    o << "}, \"not_recorded\": [";
    first = true;
    for (int c = 0; c < kNumChannels; ++c)
      if (!d.rec.has(c)) {
        o << (first ? "" : ", ") << "\"" << kChannelNames[c] << "\"";
        first = false;
      }
    o << "], \"notes\": [";
    for (std::size_t k = 0; k < d.rec.notes.size(); ++k) o << (k ? ", " : "") << "\"" << esc(d.rec.notes[k]) << "\"";
    o << "]}";
  }
  o << "]";
  return o.str();
}

std::string inputs_markdown(const std::vector<const Dataset*>& datasets) {
  std::ostringstream o;
  o << "## Inputs\n\n| data set | compared | set points (not fitted) | not recorded |\n|---|---|---|---|\n";
  for (const Dataset* d : datasets) {
    std::string cmp, sp, nr;
    for (int c = 0; c < kNumChannels; ++c) {
      const ChannelUse& u = d->use[c];
      std::ostringstream v;
      if (!d->rec.has(c)) {
        nr += (nr.empty() ? "" : ", ") + std::string(kChannelNames[c]);
      } else if (u.compared) {
        v << kChannelNames[c] << " (noise " << std::setprecision(3) << std::sqrt(d->sigma2[c]);
        if (u.resolution > 0) v << ", resolution " << u.resolution << (u.resolution_estimated ? " from data" : "");
        if (is_displacement(c) && !u.mean_compared) v << ", zero unknown: mean not compared";
        v << ")";
        cmp += (cmp.empty() ? "" : ", ") + v.str();
      } else {
        v << kChannelNames[c] << " = " << std::setprecision(8) << u.setpoint_value;
        sp += (sp.empty() ? "" : ", ") + v.str();
      }
    }
    o << "| " << d->label << " | " << cmp << " | " << (sp.empty() ? "-" : sp) << " | " << (nr.empty() ? "-" : nr)
      << " |\n";
  }
  bool any = false;
  for (const Dataset* d : datasets)
    for (const auto& n : d->rec.notes) {
      if (!any) o << "\n";
      any = true;
      o << "- " << d->label << ": " << n << "\n";
    }
  o << "\nA set point is a channel constant within its resolution (e.g. the drive speed logged at its set value): "
       "it carries no waveform and is not compared.\n\n";
  return o.str();
}

}  // namespace analysis
