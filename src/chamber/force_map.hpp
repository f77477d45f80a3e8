#pragma once
// The concave force map of the flow model: its cells' normal forces summed over the concave's areas P_{ring,sector}
// of the paper's section 4.2.3 (13 rings by height over the concave, ring 1 at the top, x 9 sectors by azimuth from
// the x axis counter-clockwise; the DEM's dem::RegionMap::rings_sectors splits the concave mesh the same way).
// A cell's force is split over the areas it overlaps, in proportion to the overlap of its band (in z) and its sector
// (in azimuth), so the map's total is the cells' total.
#include <utility>
#include <vector>

#include "chamber/flow_model.hpp"
#include "core/chamber_geometry.hpp"

namespace chamber {

class ConcaveForceMap {
 public:
  // concave: the profile whose z extent the rings divide. Throws std::invalid_argument for rings or sectors < 1.
  ConcaveForceMap(const FlowModel& f, const core::Profile& concave, int rings = 13, int sectors = 9);
  int rings() const { return rings_; }
  int sectors() const { return sectors_; }
  // per_cell: a value per flow cell (N); returns their sums per area, row-major (ring - 1) * sectors + sector - 1.
  std::vector<double> map(const std::vector<double>& per_cell) const;
  // The middle of area a on the concave (concave liner frame, m): mid-height of its ring, mid-azimuth of its sector.
  Eigen::Vector3d area_centre(int a) const;

 private:
  int rings_, sectors_;
  core::Profile concave_;
  std::vector<std::vector<std::pair<int, double>>> share_;  // per cell: (area, share of the cell)
};

}  // namespace chamber
