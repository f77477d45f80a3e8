#pragma once
// Uniform cell grid over a range of particles (counting sort by cell, stable: particles in a cell are in
// index order), used by the Verlet neighbour list and by bond formation.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "dem/particles.hpp"

namespace dem {

class CellGrid {
 public:
  // Bins particles [first, last) into cubic cells of edge >= h. The number of cells is capped at about
  // 4 (last - first) + 64 by enlarging the edge (a far-flying particle must not blow the memory up).
  void build(const Particles& p, std::size_t first, std::size_t last, double h);
  int nx = 1, ny = 1, nz = 1;
  double lo[3] = {0, 0, 0};
  double h = 1;
  std::vector<uint32_t> start;  // cell -> first slot in items (size ncells + 1)
  std::vector<uint32_t> items;  // particle indices sorted by cell
  std::vector<uint32_t> cell_of;  // particle (minus first) -> cell
  int cell_index(int cx, int cy, int cz) const { return (cz * ny + cy) * nx + cx; }
  void coords(uint32_t c, int& cx, int& cy, int& cz) const {
    cx = static_cast<int>(c % nx);
    cy = static_cast<int>((c / nx) % ny);
    cz = static_cast<int>(c / (static_cast<uint32_t>(nx) * ny));
  }

 private:
  std::vector<uint32_t> fill_;
};

}  // namespace dem
