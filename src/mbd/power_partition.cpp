#include "mbd/power_partition.hpp"

#include <cstdio>
#include <stdexcept>

namespace mbd {

PowerPartition power_partition(const EnergyAudit& a, double ta, const EnergyAudit& b, double tb) {
  if (!(tb > ta)) throw std::invalid_argument("power_partition: the span must be positive (tb > ta)");
  const double s = 1.0 / (tb - ta);
  PowerPartition p;
  p.span_s = tb - ta;
  p.drive = (b.drive_work - a.drive_work) * s;
  p.load = -(b.external_work - a.external_work) * s;
  p.absorbers = (b.absorber_dissipation - a.absorber_dissipation) * s;
  p.cone_contact = (b.contact_dissipation - a.contact_dissipation) * s;
  p.bed = (b.bed_dissipation - a.bed_dissipation) * s;
  p.joint_friction = (b.joint_friction_dissipation - a.joint_friction_dissipation) * s;
  return p;
}

std::string describe(const PowerPartition& p) {
  char buf[320];
  std::snprintf(buf, sizeof buf,
                "drive %.2f kW = load %.2f + absorbers %.2f + cone contact %.2f + bed %.2f + joint friction %.2f + "
                "residual %.2f (over %.3f s)",
                p.drive / 1e3, p.load / 1e3, p.absorbers / 1e3, p.cone_contact / 1e3, p.bed / 1e3,
                p.joint_friction / 1e3, p.residual() / 1e3, p.span_s);
  return buf;
}

}  // namespace mbd
