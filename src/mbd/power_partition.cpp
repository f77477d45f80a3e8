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
  p.bearing_friction = (b.bushing_friction_dissipation - a.bushing_friction_dissipation +
                        b.sphere_friction_dissipation - a.sphere_friction_dissipation) *
                       s;
  p.motor_input = (b.motor_input_work - a.motor_input_work) * s;
  return p;
}

std::string describe(const PowerPartition& p) {
  char buf[400];
  // The effects' terms only when they are on (the line stays as it was without them).
  char bearing[64] = "";
  if (p.bearing_friction != 0) std::snprintf(bearing, sizeof bearing, " + bearing friction %.2f", p.bearing_friction / 1e3);
  std::snprintf(buf, sizeof buf,
                "drive %.2f kW = load %.2f + absorbers %.2f + cone contact %.2f + bed %.2f + joint friction %.2f%s + "
                "residual %.2f (over %.3f s)",
                p.drive / 1e3, p.load / 1e3, p.absorbers / 1e3, p.cone_contact / 1e3, p.bed / 1e3,
                p.joint_friction / 1e3, bearing, p.residual() / 1e3, p.span_s);
  std::string out = buf;
  if (p.motor_input != p.drive) {
    std::snprintf(buf, sizeof buf, "; motor input %.2f kW (drive + drive losses %.2f)", p.motor_input / 1e3,
                  (p.motor_input - p.drive) / 1e3);
    out += buf;
  }
  return out;
}

}  // namespace mbd
