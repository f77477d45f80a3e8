#pragma once
// The crusher's liner meshes from the chamber geometry shared with the MBD (core::ChamberGeometry):
// the mantle revolved with outward normals, the concave with inward normals and refined at the 14
// ring boundaries of the 13 x 9 concave force map (section 4.2.3), plus that map. Each mesh is in
// its own liner frame (core/chamber_geometry.hpp): set its pose from the body pose every step.
#include "core/chamber_geometry.hpp"
#include "dem/mesh.hpp"
#include "dem/region_map.hpp"

namespace dem {

struct LinerMeshes {
  TriMesh mantle;
  TriMesh concave;
  RegionMap concave_regions;  // rings x sectors over the concave's height, ring 1 at the top
};

// sectors: triangles around the axis (a multiple of `force_sectors` keeps every triangle inside one
// sector; otherwise the triangle's centroid decides); max_edge: longest profile segment (m).
// Throws std::invalid_argument on bad counts or an invalid geometry.
LinerMeshes make_liner_meshes(const core::ChamberGeometry& g, int sectors, double max_edge,
                              int force_rings = 13, int force_sectors = 9);

}  // namespace dem
