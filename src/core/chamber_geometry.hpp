#pragma once
// Liner profiles of the crushing chamber (mantle on the floating cone B2, concave on the fixed cone B1)
// as meridian polylines (z, r) of surfaces of revolution. Shared by the MBD cone contact / bed model
// and by the DEM (liner meshes).
//
// Frame convention ("liner frame"): origin at the centre of the spherical joint O1 in the assembled,
// untilted crusher; z along the body's own axis (up); r the distance from that axis. The mantle profile
// moves with the floating cone, the concave profile with the fixed cone. Both are given top to bottom
// or bottom to top (z strictly monotonic), in metres after loading (config in mm).
#include <Eigen/Core>
#include <vector>

#include "core/config.hpp"

namespace core {

struct Profile {
  std::vector<double> z;  // m, strictly monotonic
  std::vector<double> r;  // m, > 0

  std::size_t size() const { return z.size(); }
  // Radius at height z by linear interpolation (clamped to the end radii outside the span).
  double radius_at(double zq) const;
  // Length of the polyline in the (z, r) plane.
  double length() const;
  // Point at arc length s from the first vertex (clamped), and the unit tangent there.
  Eigen::Vector2d point_at(double s, Eigen::Vector2d* tangent = nullptr) const;  // (z, r)
};

struct ChamberGeometry {
  Profile mantle;   // outer surface of the mantle, in the floating cone's liner frame
  Profile concave;  // inner surface of the concave, in the fixed cone's liner frame
};

// Signed distance from a meridian point q = (z, r) to a profile, measured in the (z, r) plane:
// positive when q lies on the axis side of the profile (inside the concave / inside the chamber for
// the concave; inside the mantle body for the mantle would be negative). `normal_zr` receives the unit
// direction from q to the closest profile point when the distance is positive (the outward normal
// of the profile seen from the axis side).
double signed_distance_inside(const Profile& p, const Eigen::Vector2d& q, Eigen::Vector2d* normal_zr);

// signed_distance_inside with the segments precomputed, for hot loops: the sign from the side of the closest
// segment's outward normal (the same as signed_distance_inside where the point lies within the profile's z range).
// A foot inside a segment gives the signed distance to its line directly (no square root); only an end point needs
// one. normal_zr: the closest segment's outward unit normal (z, r).
class ProfileDistance {
 public:
  explicit ProfileDistance(const Profile& p);
  double signed_distance(double z, double r, Eigen::Vector2d* normal_zr) const;
  // signed_distance of n points (z[i], r[i]) at once, d[i] the distance, seg[i] the closest segment (its normal:
  // normal_zr(seg[i])). The same arithmetic point by point (results equal to round-off: the compiler may fuse its
  // multiply-adds differently); the loop over the points vectorises (the flow model's cells, every step).
  void signed_distances(std::size_t n, const double* z, const double* r, double* d, int* seg) const;
  Eigen::Vector2d normal_zr(int seg) const { return {segs_[seg].nz, segs_[seg].nr}; }

 private:
  struct Seg {
    double az, ar, dz, dr, inv_len2, nz, nr;
  };
  std::vector<Seg> segs_;
};

// Cells on the concave's surface (liner frame): `bands` equal height bands over [z_lo, z_hi] x `sectors` equal
// sectors. Per band its mid height, the concave's radius there and one cell's area (the band's conical strip divided
// by the sectors); per sector the cosine and sine of its mid azimuth. The continuum beds' cells (chamber flow model,
// retained fines).
struct ConcaveCells {
  double z_lo = 0, dz = 0;
  std::vector<double> z_mid, r_mid, area, cos, sin;
  Eigen::Vector3d point(std::size_t band, std::size_t sector) const {  // the cell's concave point, liner frame
    return {r_mid[band] * cos[sector], r_mid[band] * sin[sector], z_mid[band]};
  }
};
ConcaveCells concave_cells(const Profile& concave, double z_lo, double z_hi, int bands, int sectors);

// Loads of a continuum bed on each liner, about the given centres of mass (world frame).
struct LinerLoads {
  Eigen::Vector3d f_mantle = Eigen::Vector3d::Zero(), t_mantle = Eigen::Vector3d::Zero();
  Eigen::Vector3d f_concave = Eigen::Vector3d::Zero(), t_concave = Eigen::Vector3d::Zero();
  double normal_force = 0;  // N, sum of p A
};

// Reads `mantle_z_mm`, `mantle_r_mm`, `concave_z_mm`, `concave_r_mm` (lists in mm) of `node`.
// Throws ConfigError naming the key when lengths differ, z is not monotonic, r <= 0, or the concave
// does not enclose the mantle over their common height (gap must stay > 0 in the untilted assembly).
ChamberGeometry load_chamber_geometry(const ConfigNode& node);
void validate_chamber_geometry(const ChamberGeometry& g);  // same checks, throws std::invalid_argument

}  // namespace core
