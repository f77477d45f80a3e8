#pragma once
// STL input/output for liner meshes. Binary and ASCII are detected on load; coordinates are
// multiplied by `scale` on load (e.g. 1e-3 for files in mm) and divided by it on save.
#include <string>

#include "dem/mesh.hpp"

namespace dem {

// Loads binary or ASCII STL. Vertices that are bit-identical after scaling (or closer than
// weld_tol, m) are merged so the mesh has edge/vertex topology. Throws std::invalid_argument
// naming the file and the problem (missing, truncated, malformed, empty).
TriMesh load_stl(const std::string& path, double scale = 1.0, double weld_tol = 0.0);

enum class StlFormat { Binary, Ascii };
// Writes the body-frame geometry. Throws std::invalid_argument if the file cannot be written.
void save_stl(const TriMesh& mesh, const std::string& path, StlFormat format = StlFormat::Binary,
              double scale = 1.0);

}  // namespace dem
