#pragma once
// Azimuthal domain decomposition of a charge about the z axis (issue 25: the chamber's ranks). ROS-free, no MPI:
// which rank owns each particle, which particles a rank must see as ghosts, and equal-count sectors (rebalancing as
// the charge moves). The exchange of ghosts over MPI builds on it.
//
// Rank r owns the wedge of azimuths [bounds[r], bounds[r + 1]) (all z, all radii); bounds ascend over one turn,
// bounds[P] = bounds[0] + 2 pi. A particle outside a wedge lies at distance
//   d = min over the wedge's two boundary half-planes (azimuth a) of  rho |sin(phi - a)|  if cos(phi - a) >= 0,
//                                                                      rho (to the axis)    otherwise
// from it (its nearest point of the wedge is on a boundary, for any wedge angle). A rank's ghosts are the particles
// it does not own within `reach` of its wedge: every particle closer than `reach` to one it owns is among them,
// because an owned particle lies in the wedge (test: every pair and bond within reach is complete on its owner's
// rank). For a charge uniform in azimuth, a boundary has N w / (2 pi r_m) ghosts on each side (the cost model's N_g,
// cost_model.hpp).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace dem {

class SectorDecomposition {
 public:
  // bounds: P + 1 azimuths (rad), strictly ascending, bounds[P] = bounds[0] + 2 pi (to 1e-12). P = 1: one wedge.
  explicit SectorDecomposition(std::vector<double> bounds);
  int ranks() const { return static_cast<int>(bounds_.size()) - 1; }
  const std::vector<double>& bounds() const { return bounds_; }
  int owner(double x, double y) const;  // rank whose wedge holds (x, y); the axis (0, 0) belongs to rank 0
  double distance(int rank, double x, double y) const;  // m from (x, y, any z) to the rank's wedge (0 inside)
  // m from (x, y, any z) to the nearer of the rank's two boundary half-planes: its distance to the wedge when it lies
  // outside (a caller that knows the owner skips the owner's azimuth).
  double boundary_distance(int rank, double x, double y) const;

 private:
  std::vector<double> bounds_, cos_, sin_;  // cos_, sin_: of each bound
};

// Equal-count wedges for the particles (x[i], y[i]), i < n: each boundary half-way (in azimuth) between the last
// particle of one rank and the first of the next in azimuth order, so the counts differ by at most 1 (distinct
// azimuths); the first boundary lies in the widest empty gap between consecutive particles (where the wrap costs
// least). n = 0 or ranks = 1: equal wedges from azimuth 0.
SectorDecomposition balanced_sectors(const double* x, const double* y, std::size_t n, int ranks);

struct RankLayout {
  std::vector<int> owner;                       // per particle
  std::vector<std::vector<uint32_t>> owned;     // per rank, ascending particle index
  std::vector<std::vector<uint32_t>> ghosts;    // per rank: owned elsewhere, within reach of the wedge, ascending
};

// Owners and ghost lists of n particles for a reach (m; the interaction range across a boundary: the largest
// contact or bond length plus the neighbour list's skin).
RankLayout rank_layout(const SectorDecomposition& d, const double* x, const double* y, std::size_t n, double reach);

}  // namespace dem
