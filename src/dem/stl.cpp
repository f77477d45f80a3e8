#include "dem/stl.hpp"

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace dem {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& what) {
  throw std::invalid_argument("STL '" + path + "': " + what);
}

using Soup = std::vector<std::array<Eigen::Vector3d, 3>>;

Soup parse_ascii(const std::string& text, const std::string& path, double scale) {
  std::istringstream in(text);
  std::string word;
  in >> word;
  if (word != "solid") fail(path, "ASCII STL must start with 'solid'");
  std::getline(in, word);  // rest of the name line
  Soup soup;
  std::array<Eigen::Vector3d, 3> tri;
  int corner = 0;
  while (in >> word) {
    if (word == "vertex") {
      double x, y, z;
      if (!(in >> x >> y >> z)) fail(path, "malformed 'vertex' line after facet " + std::to_string(soup.size()));
      if (corner >= 3) fail(path, "facet " + std::to_string(soup.size()) + " has more than 3 vertices; accepted: triangles");
      tri[corner++] = Eigen::Vector3d(x, y, z) * scale;
    } else if (word == "endfacet") {
      if (corner != 3) fail(path, "facet " + std::to_string(soup.size()) + " has " + std::to_string(corner) + " vertices; accepted: 3");
      soup.push_back(tri);
      corner = 0;
    } else if (word == "endsolid") {
      break;
    }
  }
  return soup;
}

Soup parse_binary(const std::string& data, const std::string& path, double scale) {
  if (data.size() < 84) fail(path, "binary STL shorter than its 84-byte header");
  std::uint32_t n;
  std::memcpy(&n, data.data() + 80, 4);
  const size_t need = 84 + static_cast<size_t>(n) * 50;
  if (data.size() < need)
    fail(path, "binary STL truncated: header announces " + std::to_string(n) + " triangles (" +
                   std::to_string(need) + " bytes), file has " + std::to_string(data.size()) + " bytes");
  Soup soup(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    const char* p = data.data() + 84 + static_cast<size_t>(t) * 50 + 12;  // skip the normal
    for (int k = 0; k < 3; ++k) {
      float c[3];
      std::memcpy(c, p + 12 * k, 12);
      soup[t][k] = Eigen::Vector3d(c[0], c[1], c[2]) * scale;
    }
  }
  return soup;
}

}  // namespace

TriMesh load_stl(const std::string& path, double scale, double weld_tol) {
  if (!(scale > 0.0)) fail(path, "scale = " + std::to_string(scale) + "; accepted: > 0");
  std::ifstream f(path, std::ios::binary);
  if (!f) fail(path, "cannot open file");
  std::string data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  // Binary files may also start with "solid": trust the size announced in the header first.
  bool binary = data.compare(0, 5, "solid") != 0;
  if (data.size() >= 84) {
    std::uint32_t n;
    std::memcpy(&n, data.data() + 80, 4);
    if (84 + static_cast<size_t>(n) * 50 == data.size()) binary = true;
  }
  Soup soup = binary ? parse_binary(data, path, scale) : parse_ascii(data, path, scale);
  if (soup.empty()) fail(path, "no triangles");
  std::string name = path.substr(path.find_last_of('/') + 1);
  return TriMesh::from_soup(soup, weld_tol, name);
}

void save_stl(const TriMesh& mesh, const std::string& path, StlFormat format, double scale) {
  if (!(scale > 0.0)) fail(path, "scale = " + std::to_string(scale) + "; accepted: > 0");
  const double inv = 1.0 / scale;
  std::ofstream f(path, std::ios::binary);
  if (!f) fail(path, "cannot open for writing");
  const auto& V = mesh.vertices();
  if (format == StlFormat::Ascii) {
    f << "solid " << mesh.name() << "\n" << std::setprecision(17);
    for (size_t t = 0; t < mesh.num_triangles(); ++t) {
      const auto& n = mesh.normal(static_cast<int>(t));
      f << "facet normal " << n.x() << " " << n.y() << " " << n.z() << "\n outer loop\n";
      for (int v : mesh.triangle(static_cast<int>(t))) {
        const Eigen::Vector3d p = V[v] * inv;
        f << "  vertex " << p.x() << " " << p.y() << " " << p.z() << "\n";
      }
      f << " endloop\nendfacet\n";
    }
    f << "endsolid " << mesh.name() << "\n";
  } else {
    char header[80] = {0};
    std::snprintf(header, sizeof header, "inertia_crusher binary STL %s", mesh.name().c_str());
    f.write(header, 80);
    std::uint32_t n = static_cast<std::uint32_t>(mesh.num_triangles());
    f.write(reinterpret_cast<const char*>(&n), 4);
    for (size_t t = 0; t < mesh.num_triangles(); ++t) {
      float buf[12];
      const auto& nn = mesh.normal(static_cast<int>(t));
      for (int i = 0; i < 3; ++i) buf[i] = static_cast<float>(nn[i]);
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector3d p = V[mesh.triangle(static_cast<int>(t))[k]] * inv;
        for (int i = 0; i < 3; ++i) buf[3 + 3 * k + i] = static_cast<float>(p[i]);
      }
      f.write(reinterpret_cast<const char*>(buf), 48);
      const std::uint16_t attr = 0;
      f.write(reinterpret_cast<const char*>(&attr), 2);
    }
  }
  if (!f) fail(path, "write failed");
}

}  // namespace dem
