#include "dem/mesh_liners.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "dem/revolution.hpp"

namespace dem {

LinerMeshes make_liner_meshes(const core::ChamberGeometry& g, int sectors, double max_edge,
                              int force_rings, int force_sectors) {
  if (!(max_edge > 0.0))
    throw std::invalid_argument("make_liner_meshes: max_edge = " + std::to_string(max_edge) +
                                "; accepted: > 0 (m)");
  if (force_rings < 1 || force_sectors < 1)
    throw std::invalid_argument("make_liner_meshes: force map " + std::to_string(force_rings) + " x " +
                                std::to_string(force_sectors) + "; accepted: >= 1 x >= 1");
  core::validate_chamber_geometry(g);
  auto mantle_pts = refine_profile(profile_points(g.mantle), max_edge);
  const auto& cz = g.concave.z;
  const double z_lo = *std::min_element(cz.begin(), cz.end());
  const double z_hi = *std::max_element(cz.begin(), cz.end());
  std::vector<double> cuts;
  for (int k = 0; k <= force_rings; ++k) cuts.push_back(z_lo + (z_hi - z_lo) * k / force_rings);
  auto concave_pts = refine_profile(profile_points(g.concave), max_edge, cuts);
  LinerMeshes out{revolve_profile(mantle_pts, sectors, NormalSide::Outward, 0.0, "mantle"),
                  revolve_profile(concave_pts, sectors, NormalSide::Inward, 0.0, "concave"),
                  RegionMap()};
  out.concave_regions = RegionMap::rings_sectors(out.concave, force_rings, force_sectors, 0.0, z_lo, z_hi);
  return out;
}

}  // namespace dem
