#pragma once
// Surfaces of revolution: the crusher's liners (mantle, concave) as a profile of (z, r) points in
// the body frame revolved about the body z axis into N sectors.
#include <vector>

#include "dem/mesh.hpp"

namespace dem {

struct ProfilePoint {
  double z;  // m, along the body axis
  double r;  // m, distance from the axis (>= 0; 0 only at the first or last point: an apex)
};

// Outward: normal (dz, -dr) in the (r, z) half plane, i.e. pointing away from the axis for a
// profile listed bottom to top (the mantle's surface). Inward: the opposite (the concave's).
enum class NormalSide { Outward, Inward };

// Vertex (i, j) = (r_i cos(phi0 + 2 pi j / N), r_i sin(...), z_i); each profile segment and sector
// gives two triangles (one when an end is an apex). Sector j spans azimuth
// [phi0 + 2 pi j / N, phi0 + 2 pi (j+1) / N). Throws std::invalid_argument on fewer than 2
// profile points, N < 3, negative/non-finite radius, interior points on the axis, or repeated points.
TriMesh revolve_profile(const std::vector<ProfilePoint>& profile, int sectors, NormalSide side,
                        double phi0 = 0.0, const std::string& name = "revolution");

}  // namespace dem
