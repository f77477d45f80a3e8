#pragma once
// Region maps: each triangle of a mesh belongs to one region (or none, -1), for per-region sums of
// contact forces. The crusher's concave is split into 13 rings (by height, ring 1 at the top) x 9
// sectors (by azimuth), the areas P_{ring,sector} of the paper's section 4.2.3 (Figure 21a);
// region index = (ring - 1) * sectors + (sector - 1), the row-major order of ConcaveForceMap.msg.
#include <string>
#include <vector>
#include <utility>

#include "dem/mesh.hpp"

namespace dem {

class RegionMap {
 public:
  RegionMap() = default;
  // triangle_region[t] in [-1, names.size()); throws std::invalid_argument otherwise.
  RegionMap(std::vector<int> triangle_region, std::vector<std::string> names);

  // Rings by the height of each triangle's centroid (equal bands between z_lo and z_hi in the body
  // frame; z_lo >= z_hi takes the mesh's own extent), ring 1 at the top; sectors by the centroid's
  // azimuth atan2(y, x) - phi0 in [0, 2 pi), sector 1 first counter-clockwise from phi0. Triangles
  // outside [z_lo, z_hi] get -1. Names are "P_{ring,sector}".
  static RegionMap rings_sectors(const TriMesh& mesh, int rings, int sectors, double phi0 = 0.0,
                                 double z_lo = 0.0, double z_hi = 0.0);

  int num_regions() const { return static_cast<int>(names_.size()); }
  size_t num_triangles() const { return tri_region_.size(); }
  int region_of(int triangle) const { return tri_region_[triangle]; }
  const std::vector<int>& triangle_regions() const { return tri_region_; }
  const std::string& name(int region) const { return names_.at(region); }
  int rings() const { return rings_; }      // 0 unless built by rings_sectors
  int sectors() const { return sectors_; }
  // Region of area P_{ring,sector} (1-based, as in the paper). Throws std::out_of_range.
  int ring_sector(int ring, int sector) const;
  // Summed area of each region's triangles (m^2).
  std::vector<double> region_areas(const TriMesh& mesh) const;

 private:
  std::vector<int> tri_region_;
  std::vector<std::string> names_;
  int rings_ = 0, sectors_ = 0;
};

// Time average of per-region values (e.g. normal force, N) over a window: add(values, dt) after
// each step, mean() = sum(values * dt) / sum(dt). reset() starts a new window.
class RegionAverager {
 public:
  explicit RegionAverager(int regions = 0) : sum_(regions, 0.0) {}
  void add(const std::vector<double>& values, double dt);
  void add_integral(const std::vector<double>& integrals, double dt);  // values already integrated over dt
  std::vector<double> mean() const;  // zeros for an empty window
  double window() const { return time_; }
  void reset();
  // Running sums and window length, for checkpoints.
  const std::vector<double>& sums() const { return sum_; }
  void restore(std::vector<double> sums, double window) { sum_ = std::move(sums), time_ = window; }

 private:
  std::vector<double> sum_;
  double time_ = 0.0;
};

}  // namespace dem
