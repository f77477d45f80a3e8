#include "dem/region_map.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dem {

RegionMap::RegionMap(std::vector<int> triangle_region, std::vector<std::string> names)
    : tri_region_(std::move(triangle_region)), names_(std::move(names)) {
  const int n = static_cast<int>(names_.size());
  for (size_t t = 0; t < tri_region_.size(); ++t)
    if (tri_region_[t] < -1 || tri_region_[t] >= n)
      throw std::invalid_argument("RegionMap: triangle " + std::to_string(t) + " has region " +
                                  std::to_string(tri_region_[t]) + "; accepted: -1 (none) or 0.." +
                                  std::to_string(n - 1));
}

RegionMap RegionMap::rings_sectors(const TriMesh& mesh, int rings, int sectors, double phi0,
                                   double z_lo, double z_hi) {
  if (rings < 1 || sectors < 1)
    throw std::invalid_argument("RegionMap::rings_sectors: rings = " + std::to_string(rings) +
                                ", sectors = " + std::to_string(sectors) + "; accepted: >= 1 each");
  if (!(z_lo < z_hi)) {
    z_lo = mesh.bbox_min().z();
    z_hi = mesh.bbox_max().z();
  }
  if (!(z_hi > z_lo))
    throw std::invalid_argument("RegionMap::rings_sectors: mesh '" + mesh.name() +
                                "' has no height extent; accepted: a surface spanning a z range");
  const double two_pi = 2.0 * 3.14159265358979323846;
  const int nt = static_cast<int>(mesh.num_triangles());
  std::vector<int> reg(nt, -1);
  const double band = (z_hi - z_lo) / rings;
  for (int t = 0; t < nt; ++t) {
    const Eigen::Vector3d c = mesh.centroid(t);
    if (c.z() < z_lo || c.z() > z_hi) continue;
    int ring = static_cast<int>(std::floor((z_hi - c.z()) / band));  // 0 = top band
    ring = std::min(std::max(ring, 0), rings - 1);
    double phi = std::atan2(c.y(), c.x()) - phi0;
    phi = std::fmod(phi, two_pi);
    if (phi < 0) phi += two_pi;
    int sector = static_cast<int>(std::floor(phi / (two_pi / sectors)));
    sector = std::min(std::max(sector, 0), sectors - 1);
    reg[t] = ring * sectors + sector;
  }
  std::vector<std::string> names;
  for (int r = 1; r <= rings; ++r)
    for (int s = 1; s <= sectors; ++s)
      names.push_back("P_{" + std::to_string(r) + "," + std::to_string(s) + "}");
  RegionMap m(std::move(reg), std::move(names));
  m.rings_ = rings;
  m.sectors_ = sectors;
  return m;
}

int RegionMap::ring_sector(int ring, int sector) const {
  if (rings_ == 0 || ring < 1 || ring > rings_ || sector < 1 || sector > sectors_)
    throw std::out_of_range("RegionMap::ring_sector(" + std::to_string(ring) + ", " +
                            std::to_string(sector) + "): accepted ring 1.." + std::to_string(rings_) +
                            ", sector 1.." + std::to_string(sectors_));
  return (ring - 1) * sectors_ + (sector - 1);
}

std::vector<double> RegionMap::region_areas(const TriMesh& mesh) const {
  if (mesh.num_triangles() != tri_region_.size())
    throw std::invalid_argument("RegionMap::region_areas: map has " + std::to_string(tri_region_.size()) +
                                " triangles, mesh '" + mesh.name() + "' has " +
                                std::to_string(mesh.num_triangles()));
  std::vector<double> a(names_.size(), 0.0);
  for (size_t t = 0; t < tri_region_.size(); ++t)
    if (tri_region_[t] >= 0) a[tri_region_[t]] += mesh.triangle_area(static_cast<int>(t));
  return a;
}

void RegionAverager::add(const std::vector<double>& values, double dt) {
  if (values.size() != sum_.size())
    throw std::invalid_argument("RegionAverager::add: " + std::to_string(values.size()) +
                                " values; accepted: " + std::to_string(sum_.size()));
  if (!(dt >= 0.0)) throw std::invalid_argument("RegionAverager::add: dt must be >= 0");
  for (size_t i = 0; i < sum_.size(); ++i) sum_[i] += values[i] * dt;
  time_ += dt;
}

void RegionAverager::add_integral(const std::vector<double>& integrals, double dt) {
  if (integrals.size() != sum_.size())
    throw std::invalid_argument("RegionAverager::add_integral: " + std::to_string(integrals.size()) +
                                " values; accepted: " + std::to_string(sum_.size()));
  if (!(dt >= 0.0)) throw std::invalid_argument("RegionAverager::add_integral: dt must be >= 0");
  for (size_t i = 0; i < sum_.size(); ++i) sum_[i] += integrals[i];
  time_ += dt;
}

std::vector<double> RegionAverager::mean() const {
  std::vector<double> m(sum_.size(), 0.0);
  if (time_ > 0)
    for (size_t i = 0; i < sum_.size(); ++i) m[i] = sum_[i] / time_;
  return m;
}

void RegionAverager::reset() {
  std::fill(sum_.begin(), sum_.end(), 0.0);
  time_ = 0.0;
}

}  // namespace dem
