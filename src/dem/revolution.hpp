#pragma once
// Surfaces of revolution: the crusher's liners (mantle, concave) as a profile of (z, r) points in
// the body frame revolved about the body z axis into N sectors.
#include <string>
#include <vector>

#include "core/chamber_geometry.hpp"

#include "dem/mesh.hpp"

namespace dem {

struct ProfilePoint {
  double z;  // m, along the body axis
  double r;  // m, distance from the axis (>= 0; 0 only at the first or last point: an apex)
};

// Outward: normals pointing away from the axis (the mantle's surface); Inward: towards it (the
// concave's). Precisely, Outward is the normal (dz, -dr) in the (r, z) half plane for a profile
// whose z rises overall (last z >= first z) and (-dz, dr) for one listed top to bottom, so both
// orders give the same surface. For a closed profile (axis to axis) listed bottom to top, Outward
// is the enclosed body's outer side.
enum class NormalSide { Outward, Inward };

// Vertex (i, j) = (r_i cos(phi0 + 2 pi j / N), r_i sin(...), z_i); each profile segment and sector
// gives two triangles (one when an end is an apex). Sector j spans azimuth
// [phi0 + 2 pi j / N, phi0 + 2 pi (j+1) / N). Throws std::invalid_argument on fewer than 2
// profile points, N < 3, negative/non-finite radius, interior points on the axis, or repeated points.
TriMesh revolve_profile(const std::vector<ProfilePoint>& profile, int sectors, NormalSide side,
                        double phi0 = 0.0, const std::string& name = "revolution");

// (z, r) points of a core::Profile (the chamber geometry shared with the MBD).
std::vector<ProfilePoint> profile_points(const core::Profile& profile);

// Same polyline with extra points: where a segment crosses one of z_cuts (e.g. the 14 ring
// boundaries of the concave force map, so each triangle lies in one ring), and evenly inside
// segments longer than max_len (m; <= 0: no limit). Throws std::invalid_argument on < 2 points.
std::vector<ProfilePoint> refine_profile(const std::vector<ProfilePoint>& profile, double max_len,
                                         const std::vector<double>& z_cuts = {});

}  // namespace dem
