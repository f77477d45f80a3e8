#include "dem/cell_grid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace dem {

void CellGrid::build(const Particles& p, std::size_t first, std::size_t last, double h_in) {
  const std::size_t n = last - first;
  double hi[3] = {0, 0, 0};
  lo[0] = lo[1] = lo[2] = 0;
  if (n > 0) {
    lo[0] = hi[0] = p.x[first];
    lo[1] = hi[1] = p.y[first];
    lo[2] = hi[2] = p.z[first];
  }
  for (std::size_t i = first; i < last; ++i) {
    if (!std::isfinite(p.x[i]) || !std::isfinite(p.y[i]) || !std::isfinite(p.z[i]))
      throw std::runtime_error("DEM: particle id " + std::to_string(p.id[i]) + " (index " + std::to_string(i) +
                               ") has a non-finite position (numerical blow-up; reduce the time step)");
    lo[0] = std::min(lo[0], p.x[i]); hi[0] = std::max(hi[0], p.x[i]);
    lo[1] = std::min(lo[1], p.y[i]); hi[1] = std::max(hi[1], p.y[i]);
    lo[2] = std::min(lo[2], p.z[i]); hi[2] = std::max(hi[2], p.z[i]);
  }
  h = h_in;
  const double cap = 4.0 * static_cast<double>(n) + 64.0;
  for (;;) {
    const double cx = std::floor((hi[0] - lo[0]) / h) + 1, cy = std::floor((hi[1] - lo[1]) / h) + 1,
                 cz = std::floor((hi[2] - lo[2]) / h) + 1;
    if (cx * cy * cz <= cap) {
      nx = static_cast<int>(cx); ny = static_cast<int>(cy); nz = static_cast<int>(cz);
      break;
    }
    h *= 1.25;
  }
  const std::size_t nc = static_cast<std::size_t>(nx) * ny * nz;
  start.assign(nc + 1, 0);
  cell_of.resize(n);
  items.resize(n);
  const double ih = 1.0 / h;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = first + k;
    int cx = std::min(nx - 1, static_cast<int>((p.x[i] - lo[0]) * ih));
    int cy = std::min(ny - 1, static_cast<int>((p.y[i] - lo[1]) * ih));
    int cz = std::min(nz - 1, static_cast<int>((p.z[i] - lo[2]) * ih));
    const uint32_t c = static_cast<uint32_t>(cell_index(cx, cy, cz));
    cell_of[k] = c;
    ++start[c + 1];
  }
  for (std::size_t c = 0; c < nc; ++c) start[c + 1] += start[c];
  fill_.assign(start.begin(), start.end() - 1);
  for (std::size_t k = 0; k < n; ++k) items[fill_[cell_of[k]]++] = static_cast<uint32_t>(first + k);
}

}  // namespace dem
