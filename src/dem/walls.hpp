#pragma once
// Infinite planar walls moving with a prescribed velocity; the contact force on each wall is recorded.
#include <cmath>
#include <stdexcept>

namespace dem {

struct PlanarWall {
  double p[3] = {0, 0, 0};  // a point on the plane (m), advanced by v each step
  double n[3] = {0, 0, 1};  // unit normal pointing into the particle side
  double v[3] = {0, 0, 0};  // prescribed velocity (m/s)
  int material = 1;         // MaterialTable index (default steel)
  double force[3] = {0, 0, 0};  // total contact force of the particles on the wall in the last step (N)

  static PlanarWall make(const double point[3], const double normal[3], int material) {
    PlanarWall w;
    const double l = std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
    if (!(l > 0) || !std::isfinite(l)) throw std::invalid_argument("planar wall: normal must be a non-zero finite vector");
    for (int k = 0; k < 3; ++k) {
      w.p[k] = point[k];
      w.n[k] = normal[k] / l;
    }
    w.material = material;
    return w;
  }
};

}  // namespace dem
