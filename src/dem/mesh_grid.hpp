#pragma once
// Broad phase for particle-mesh contact: a uniform grid over the mesh's triangles in the BODY frame
// (the mesh is rigid, so the grid is built once and each particle centre is moved to the body frame
// for the query). A triangle is listed in every cell that its bounding box, grown by `margin`,
// overlaps; so one cell lookup returns every triangle a sphere of radius <= margin centred in that
// cell can touch.
#include <Eigen/Core>
#include <vector>

#include "dem/mesh.hpp"

namespace dem {

class TriangleGrid {
 public:
  TriangleGrid() = default;
  // margin: largest particle radius (plus any skin), m. cell: cell edge, m (<= 0: the larger of half the
  // mean longest triangle edge and two margins). The cell count is capped (max_cells) by enlarging cells.
  TriangleGrid(const TriMesh& mesh, double margin, double cell = 0.0, long max_cells = 1L << 22);

  double margin() const { return margin_; }
  double cell_size() const { return h_; }
  bool empty() const { return off_.empty(); }
  // Candidate triangles near body-frame point p (empty range when outside the grown bounds).
  std::pair<const int*, const int*> query(const Eigen::Vector3d& p_body) const {
    const Eigen::Vector3d q = (p_body - lo_) * inv_h_;
    if (!(q.x() >= 0 && q.y() >= 0 && q.z() >= 0)) return {nullptr, nullptr};
    const long ix = static_cast<long>(q.x()), iy = static_cast<long>(q.y()), iz = static_cast<long>(q.z());
    if (ix >= n_[0] || iy >= n_[1] || iz >= n_[2]) return {nullptr, nullptr};
    const long c = (iz * n_[1] + iy) * n_[0] + ix;
    return {idx_.data() + off_[c], idx_.data() + off_[c + 1]};
  }
  size_t num_entries() const { return idx_.size(); }
  long num_cells() const { return n_[0] * n_[1] * n_[2]; }

 private:
  double margin_ = 0.0, h_ = 1.0, inv_h_ = 1.0;
  Eigen::Vector3d lo_ = Eigen::Vector3d::Zero();
  long n_[3] = {0, 0, 0};
  std::vector<long> off_;
  std::vector<int> idx_;
};

}  // namespace dem
