#include "rocks/rock_file.hpp"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rocks {

void save_rock(const RockPacking& rock, const std::string& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("save_rock: cannot write '" + file + "'");
  out.precision(17);
  out << "# rock packing written by inertia_crusher (src/rocks/rock_file.hpp describes the format)\n";
  out << "inertia_crusher_rock 1\n";
  out << "name " << (rock.name.empty() ? "rock" : rock.name) << "\n";
  out << "seed " << rock.seed << "\n";
  out << "target_density " << rock.target_density << "\n";
  out << "container_volume_m3 " << rock.container_volume << "\n";
  out << "bond_gap_ratio " << rock.bond_gap_ratio << "\n";
  out << "distribution " << rock.distribution << "\n";
  out << "particles " << rock.size() << "\n";
  for (std::size_t i = 0; i < rock.size(); ++i)
    out << rock.positions[i].x() << " " << rock.positions[i].y() << " " << rock.positions[i].z() << " "
        << rock.radii[i] << "\n";
  out << "bonds " << rock.bonds.size() << "\n";
  for (const auto& b : rock.bonds) out << b.first << " " << b.second << "\n";
  out << "end\n";
  if (!out) throw std::runtime_error("save_rock: error writing '" + file + "'");
}

RockPacking load_rock(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("load_rock: cannot open '" + file + "'");
  RockPacking rock;
  std::string line;
  int lineno = 0;
  auto fail = [&](const std::string& what) {
    throw std::runtime_error("load_rock: " + file + ":" + std::to_string(lineno) + ": " + what);
  };
  auto next = [&]() -> bool {
    while (std::getline(in, line)) {
      ++lineno;
      if (!line.empty() && line[0] != '#') return true;
    }
    return false;
  };
  auto field = [&](const std::string& key) -> std::string {
    if (!next()) fail("unexpected end of file, expected '" + key + "'");
    if (line.compare(0, key.size() + 1, key + " ") != 0) fail("expected '" + key + " ...', got '" + line + "'");
    return line.substr(key.size() + 1);
  };
  if (field("inertia_crusher_rock") != "1") fail("unsupported version (accepted: 1)");
  rock.name = field("name");
  try {
    rock.seed = std::stoull(field("seed"));
    rock.target_density = std::stod(field("target_density"));
    rock.container_volume = std::stod(field("container_volume_m3"));
    rock.bond_gap_ratio = std::stod(field("bond_gap_ratio"));
  } catch (const std::logic_error&) {
    fail("not a number");
  }
  rock.distribution = field("distribution");
  const long n = std::atol(field("particles").c_str());
  if (n <= 0) fail("particle count must be > 0");
  rock.positions.resize(n);
  rock.radii.resize(n);
  for (long i = 0; i < n; ++i) {
    if (!next()) fail("file ends inside the particle list");
    std::istringstream s(line);
    double x, y, z, r;
    if (!(s >> x >> y >> z >> r) || !(r > 0.0)) fail("expected 'x y z radius' with radius > 0");
    rock.positions[i] = Vec3(x, y, z);
    rock.radii[i] = r;
  }
  const long m = std::atol(field("bonds").c_str());
  if (m < 0) fail("bond count must be >= 0");
  rock.bonds.resize(m);
  for (long k = 0; k < m; ++k) {
    if (!next()) fail("file ends inside the bond list");
    std::istringstream s(line);
    long i, j;
    if (!(s >> i >> j) || i < 0 || j <= i || j >= n) fail("expected 'i j' with 0 <= i < j < particles");
    rock.bonds[k] = {static_cast<int>(i), static_cast<int>(j)};
  }
  if (!next() || line != "end") fail("expected 'end'");
  return rock;
}

}  // namespace rocks
