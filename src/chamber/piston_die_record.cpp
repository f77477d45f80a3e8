// The piston-die pourings' text record and the jackknife fits (piston_die_record.hpp).
#include "chamber/piston_die_record.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace chamber {
namespace {

constexpr const char* kHeader = "piston_die_pourings 1";

std::string g17(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

std::string list(const char* key, const std::vector<double>& v) {
  std::string out = key;
  for (double x : v) out += " " + g17(x);
  return out;
}

class Reader {
 public:
  explicit Reader(const std::string& file) : file_(file), in_(file) {
    if (!in_) throw std::invalid_argument("piston-die record '" + file + "': cannot be read");
  }
  // The next non-comment line's words; false at the end.
  bool next(std::vector<std::string>& words) {
    for (std::string line; std::getline(in_, line);) {
      ++line_;
      if (line.empty() || line[0] == '#') continue;
      std::istringstream s(line);
      words.clear();
      for (std::string w; s >> w;) words.push_back(w);
      if (words.empty()) continue;
      if (words.front() == "blowup") {  // free text: the rest of the line
        const std::string rest = line.substr(line.find("blowup") + 6);
        const auto from = rest.find_first_not_of(' ');
        words = {"blowup", from == std::string::npos ? "" : rest.substr(from)};
      }
      return true;
    }
    return false;
  }
  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("piston-die record '" + file_ + "' line " + std::to_string(line_) + ": " + what);
  }
  double number(const std::string& w) const {
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(w.c_str(), &end);
    if (w.empty() || *end || errno == ERANGE) fail("'" + w + "' is not a number");
    return x;
  }
  std::vector<double> numbers(const std::vector<std::string>& words) const {
    std::vector<double> v;
    for (std::size_t i = 1; i < words.size(); ++i) v.push_back(number(words[i]));
    return v;
  }
  // key=value fields after the first word; every key in `keys` required, no other.
  std::map<std::string, double> fields(const std::vector<std::string>& words, const std::vector<std::string>& keys) const {
    std::map<std::string, double> f;
    for (std::size_t i = 1; i < words.size(); ++i) {
      const auto eq = words[i].find('=');
      if (eq == std::string::npos) fail("expected key=value, got '" + words[i] + "'");
      f[words[i].substr(0, eq)] = number(words[i].substr(eq + 1));
    }
    for (const auto& k : keys)
      if (!f.count(k)) fail("'" + words.front() + "' lacks " + k);
    if (f.size() != keys.size()) fail("'" + words.front() + "' has a key not among its " + std::to_string(keys.size()));
    return f;
  }

 private:
  std::string file_;
  std::ifstream in_;
  int line_ = 0;
};

const std::vector<std::string> kPouringKeys = {
    "seed", "rocks", "particles", "bonds", "die_diameter_m", "die_area_m2", "rock_min_m", "rock_max_m", "piston_speed_m_s", "bed_height_m", "rock_mass_kg",
    "solid_density_kg_m3", "loose_solid_fraction", "dt_s", "settle_s", "metaparticle_diameter_m", "min_resolved_m",
    "wall_s"};
const std::vector<std::string> kLoopKeys = {
    "s_max", "s_reached", "loading_work_Pa", "loop_energy_Pa", "energy_per_kg", "loading_energy_per_kg",
    "bonds_broken", "mass_error", "fragments", "wall_s"};

}  // namespace

void write_pourings(const std::vector<PistonDieResult>& pourings, const std::string& file) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("piston-die record '" + file + "': cannot be written");
  out << kHeader << "\n# every pouring of a virtual piston-die test (src/chamber/piston_die_record.hpp), SI units\n";
  for (const auto& r : pourings) {
    out << "pouring seed=" << r.seed << " rocks=" << r.rocks << " particles=" << r.particles << " bonds=" << r.bonds
        << " die_diameter_m=" << g17(r.die_diameter) << " die_area_m2=" << g17(r.die_area)
        << " rock_min_m=" << g17(r.rock_min) << " rock_max_m=" << g17(r.rock_max)
        << " piston_speed_m_s=" << g17(r.piston_speed)
        << " bed_height_m=" << g17(r.bed_height) << " rock_mass_kg=" << g17(r.rock_mass)
        << " solid_density_kg_m3=" << g17(r.solid_density) << " loose_solid_fraction=" << g17(r.loose_solid_fraction)
        << " dt_s=" << g17(r.dt) << " settle_s=" << g17(r.settle_time)
        << " metaparticle_diameter_m=" << g17(r.metaparticle_diameter) << " min_resolved_m=" << g17(r.min_resolved)
        << " wall_s=" << g17(r.wall_s) << "\n";
    if (!r.blowup.empty()) {
      std::string b = r.blowup;
      for (char& c : b)
        if (c == '\n') c = ' ';
      out << "blowup " << b << "\n";
    }
    out << list("feed_passing", r.feed_passing) << "\n";
    for (const auto& L : r.loops) {
      out << "loop s_max=" << g17(L.s_max) << " s_reached=" << g17(L.s_reached) << " loading_work_Pa="
          << g17(L.loading_work) << " loop_energy_Pa=" << g17(L.loop_energy) << " energy_per_kg=" << g17(L.energy_per_kg)
          << " loading_energy_per_kg=" << g17(L.loading_energy_per_kg) << " bonds_broken=" << L.bonds_broken
          << " mass_error=" << g17(L.mass_error) << " fragments=" << L.fragments << " wall_s=" << g17(L.wall_s) << "\n";
      out << list("passing", L.passing) << "\n" << list("s", L.s) << "\n" << list("p_Pa", L.p) << "\nphase";
      for (int ph : L.phase) out << " " << ph;
      out << "\n";
    }
  }
  if (!out) throw std::runtime_error("piston-die record '" + file + "': write failed");
}

std::vector<PistonDieResult> read_pourings(const std::string& file) {
  Reader in(file);
  std::vector<std::string> w;
  if (!in.next(w) || w.size() != 2 || w[0] + " " + w[1] != kHeader)
    in.fail(std::string("expected the header '") + kHeader + "'");
  std::vector<PistonDieResult> out;
  const std::size_t sieves = flow_sieves_mm().size();
  while (in.next(w)) {
    const std::string& k = w.front();
    if (k == "pouring") {
      const auto f = in.fields(w, kPouringKeys);
      PistonDieResult r;
      r.seed = static_cast<unsigned long long>(f.at("seed"));
      r.rocks = static_cast<int>(f.at("rocks"));
      r.particles = static_cast<std::size_t>(f.at("particles"));
      r.bonds = static_cast<std::size_t>(f.at("bonds"));
      r.die_diameter = f.at("die_diameter_m"), r.die_area = f.at("die_area_m2"), r.bed_height = f.at("bed_height_m");
      r.rock_min = f.at("rock_min_m"), r.rock_max = f.at("rock_max_m"), r.piston_speed = f.at("piston_speed_m_s");
      r.rock_mass = f.at("rock_mass_kg"), r.solid_density = f.at("solid_density_kg_m3");
      r.loose_solid_fraction = f.at("loose_solid_fraction");
      r.dt = f.at("dt_s"), r.settle_time = f.at("settle_s");
      r.metaparticle_diameter = f.at("metaparticle_diameter_m"), r.min_resolved = f.at("min_resolved_m");
      r.wall_s = f.at("wall_s");
      if (!(r.rock_mass > 0 && r.solid_density > 0 && r.loose_solid_fraction > 0 && r.loose_solid_fraction < 1))
        in.fail("a pouring needs rock_mass_kg > 0, solid_density_kg_m3 > 0 and loose_solid_fraction in (0, 1)");
      out.push_back(std::move(r));
      continue;
    }
    if (out.empty()) in.fail("'" + k + "' before the first 'pouring' line");
    PistonDieResult& r = out.back();
    if (k == "blowup") {
      r.blowup = w[1];
    } else if (k == "feed_passing" || k == "passing") {
      auto v = in.numbers(w);
      if (v.size() != sieves) in.fail(k + " needs " + std::to_string(sieves) + " values (the flow sieves), got " + std::to_string(v.size()));
      if (k == "feed_passing") r.feed_passing = std::move(v);
      else if (r.loops.empty()) in.fail("'passing' before the first 'loop' line");
      else r.loops.back().passing = std::move(v);
    } else if (k == "loop") {
      const auto f = in.fields(w, kLoopKeys);
      PressLoop L;
      L.s_max = f.at("s_max"), L.s_reached = f.at("s_reached"), L.loading_work = f.at("loading_work_Pa");
      L.loop_energy = f.at("loop_energy_Pa"), L.energy_per_kg = f.at("energy_per_kg");
      L.loading_energy_per_kg = f.at("loading_energy_per_kg");
      L.bonds_broken = static_cast<std::size_t>(f.at("bonds_broken"));
      L.mass_error = f.at("mass_error"), L.fragments = static_cast<int>(f.at("fragments")), L.wall_s = f.at("wall_s");
      r.loops.push_back(std::move(L));
    } else if (k == "s" || k == "p_Pa" || k == "phase") {
      if (r.loops.empty()) in.fail("'" + k + "' before the first 'loop' line");
      PressLoop& L = r.loops.back();
      const auto v = in.numbers(w);
      if (k == "s") L.s = v;
      else if (k == "p_Pa") L.p = v;
      else
        for (double x : v) {
          if (x != 0 && x != 1) in.fail("phase values are 0 (loading) or 1 (unloading)");
          L.phase.push_back(static_cast<int>(x));
        }
    } else {
      in.fail("unknown item '" + k + "' (accepted: pouring, blowup, feed_passing, loop, passing, s, p_Pa, phase)");
    }
  }
  if (out.empty()) in.fail("no pouring in the record");
  for (const auto& r : out) {
    if (r.feed_passing.size() != sieves) in.fail("pouring seed " + std::to_string(r.seed) + " has no feed_passing");
    if (r.loops.empty()) in.fail("pouring seed " + std::to_string(r.seed) + " has no loop");
    for (const auto& L : r.loops)
      if (L.s.size() != L.p.size() || L.s.size() != L.phase.size() || L.passing.size() != sieves || L.s.empty())
        in.fail("pouring seed " + std::to_string(r.seed) + ": a loop's s, p_Pa and phase differ in length or its passing is missing");
  }
  return out;
}

std::vector<MaterialFit> leave_one_out_fits(const std::vector<PistonDieResult>& pourings, PressureLaw law) {
  if (pourings.size() < 3)
    throw std::invalid_argument("leave_one_out_fits: the jackknife needs at least 3 pourings, got " +
                                std::to_string(pourings.size()));
  std::vector<MaterialFit> fits;
  for (std::size_t i = 0; i < pourings.size(); ++i) {
    std::vector<const PistonDieResult*> rest;
    for (std::size_t j = 0; j < pourings.size(); ++j)
      if (j != i) rest.push_back(&pourings[j]);
    fits.push_back(fit_flow_material(rest, law));
  }
  return fits;
}

std::vector<PistonDieResult> merge_repressed_pourings(const std::vector<PistonDieResult>& pourings) {
  std::vector<PistonDieResult> out;
  for (const auto& r : pourings) {
    auto same = std::find_if(out.begin(), out.end(), [&](const PistonDieResult& q) { return q.seed == r.seed; });
    if (same == out.end()) {
      out.push_back(r);
      continue;
    }
    auto& q = *same;
    const std::string who = "seed " + std::to_string(r.seed) + " is recorded twice";
    auto close = [](double a, double b) { return std::fabs(a - b) <= 1e-12 * std::max(std::fabs(a), std::fabs(b)); };
    if (q.rocks != r.rocks || q.particles != r.particles || q.bonds != r.bonds || !close(q.rock_mass, r.rock_mass) ||
        !close(q.bed_height, r.bed_height) || !close(q.dt, r.dt) || !close(q.die_diameter, r.die_diameter))
      throw std::invalid_argument(who + " as different beds (rocks, particles, bonds, rock mass, bed height, die or "
                                        "time step differ): a pouring counted twice would weigh double");
    for (const auto& L : r.loops) {
      for (const auto& K : q.loops)
        if (close(K.s_max, L.s_max))
          throw std::invalid_argument(who + " with the loop to s_max " + std::to_string(L.s_max) +
                                      " in both: a pressing counted twice would weigh double");
      q.loops.push_back(L);
    }
    std::sort(q.loops.begin(), q.loops.end(), [](const PressLoop& a, const PressLoop& b) { return a.s_max < b.s_max; });
    if (!r.blowup.empty()) q.blowup += (q.blowup.empty() ? "" : "; ") + r.blowup;
    q.wall_s += r.wall_s;
  }
  return out;
}

}  // namespace chamber
