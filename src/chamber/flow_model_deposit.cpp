// FlowModel as the carrier of the coupled run's fines (flow_model.hpp): deposits by position, the discharge since the
// last take.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "chamber/flow_model.hpp"

namespace chamber {

FlowParams fines_only(FlowParams p) {
  p.prefill = false;
  p.choke_feed = false;
  p.material.lump_std = 0;  // the pressings' scatter is the DEM's own: its particles are the lumps
  return p;
}

long FlowModel::cell_of(const Eigen::Vector3d& xc) const {
  constexpr double kTwoPi = 6.28318530717958647692;
  const double u = (xc.z() - cells_.z_lo) / cells_.dz;
  if (!(u >= 0)) return -1;
  const int b = std::min(p_.bands - 1, static_cast<int>(u));
  double a = std::atan2(xc.y(), xc.x());
  if (a < 0) a += kTwoPi;
  const int s = std::min(p_.sectors - 1, static_cast<int>(a / kTwoPi * p_.sectors));  // sector s: [s, s + 1] 2 pi / S
  return static_cast<long>(b) * p_.sectors + s;
}

void FlowModel::deposit(const Eigen::Vector3d& xc, const std::vector<double>& class_kg) {
  const long k = cell_of(xc);
  if (k >= 0) return deposit(static_cast<std::size_t>(k), class_kg);
  if (class_kg.size() != classes()) throw std::invalid_argument("FlowModel::deposit: wrong number of size classes");
  for (std::size_t j = 0; j < classes(); ++j) {
    if (!(class_kg[j] >= 0) || !std::isfinite(class_kg[j]))
      throw std::invalid_argument("FlowModel::deposit: masses must be finite and >= 0");
    out_[j] += class_kg[j];  // below the chamber: discharged with no compression
    fed_ += class_kg[j];
  }
}

std::vector<double> FlowModel::take_discharged() {
  if (taken_.empty()) taken_.assign(classes(), 0.0);
  std::vector<double> d(classes());
  for (std::size_t j = 0; j < classes(); ++j) d[j] = out_[j] - taken_[j];
  taken_ = out_;
  return d;
}

double FlowModel::untaken_kg() const {
  return taken_.empty() ? discharged_kg() : discharged_kg() - std::accumulate(taken_.begin(), taken_.end(), 0.0);
}

}  // namespace chamber
