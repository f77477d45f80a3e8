// Metaparticle crushing (coupling/metaparticle_crushing.hpp): strength, progeny, and in a chamber.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numeric>

#include "coupling/chamber_dem.hpp"
#include "coupling/metaparticle_crushing.hpp"
#include "dem/world.hpp"
#include "small_chamber.hpp"

namespace {

std::shared_ptr<dem::MeshContact> plate(const dem::World& w, double z, const std::string& name) {
  auto m = std::make_shared<dem::MeshContact>(
      dem::TriMesh({{-0.1, -0.1, 0}, {0.1, -0.1, 0}, {0.1, 0.1, 0}, {-0.1, 0.1, 0}}, {{0, 1, 2}, {0, 2, 3}}, name),
      w.materials(), 1);
  dem::Pose p;
  p.position = Eigen::Vector3d(0, 0, z);
  m->set_pose(p);
  m->set_threads(1);  // one sphere: a thread team would only add its barriers to each of many steps
  return m;
}

// The small chamber pre-filled with 0.5 kg of rock weaker than marble: F_c(8 mm) = 36 N, so the 3 deg
// gyration crushes many metaparticles.
coupling::ChamberParams crushing_chamber() {
  auto p = test_chamber::prefilled_small_chamber(0.5, 0.5);
  p.crushing.enabled = true;
  p.crushing.tensile_strength = 0.5e6;
  return p;
}

}  // namespace

TEST(MetaparticleCrushing, PointLoadStrengthOfHiramatsuOka) {
  // F_c = pi d^2 sigma_t / 2.8: a 12 mm lump of the paper's marble (sigma_t 3.77 MPa) holds 609 N.
  EXPECT_NEAR(coupling::crushing_force(12e-3, 3.77e6), 609.1, 0.1);
  EXPECT_NEAR(coupling::crushing_force(24e-3, 3.77e6) / coupling::crushing_force(12e-3, 3.77e6), 4.0, 1e-12);
}

TEST(MetaparticleCrushing, ProgenyFollowsGaudinSchuhmannBelowTheParentSize) {
  const std::vector<double> sieves{1e-3, 2e-3, 4e-3, 8e-3, 12e-3, 16e-3};
  const auto c = coupling::progeny_by_class(3.0, 10e-3, sieves, 1.0);
  ASSERT_EQ(c.size(), sieves.size() + 1);
  EXPECT_NEAR(std::accumulate(c.begin(), c.end(), 0.0), 3.0, 1e-12);
  EXPECT_NEAR(c[0], 3.0 * 0.1, 1e-12);          // passing 1 mm: (1/10)^1
  EXPECT_NEAR(c[3], 3.0 * (0.8 - 0.4), 1e-12);  // 4-8 mm
  EXPECT_NEAR(c[4], 3.0 * (1.0 - 0.8), 1e-12);  // 8-12 mm holds the rest up to the parent's 10 mm
  EXPECT_EQ(c[5], 0.0);
  EXPECT_EQ(c[6], 0.0);
  const auto sq = coupling::progeny_by_class(1.0, 10e-3, sieves, 2.0);
  EXPECT_NEAR(sq[0], 0.01, 1e-12);  // exponent 2: finer end thinner
}

namespace {

// Lowers `ceiling` at speed v from height z0, one DEM step of w at a time, until crushed() holds after a step:
// the ceiling's height then and the largest ceiling force over the steps before (gtest failure if never).
struct Press {
  double z = 0, force_before = 0;
};
template <class Crushed>
Press press_until(dem::World& w, dem::MeshContact& ceiling, double z0, double v, Crushed crushed) {
  dem::Twist down;
  down.linear = Eigen::Vector3d(0, 0, -v);
  ceiling.set_twist(down);
  Press out{z0, 0};
  long steps = 0;
  for (; steps < 400000; ++steps) {
    out.z -= v * w.dt();
    dem::Pose p;
    p.position = Eigen::Vector3d(0, 0, out.z);
    ceiling.set_pose(p);
    w.step(1);
    if (crushed()) break;
    for (const auto& c : ceiling.contacts()) out.force_before = std::max(out.force_before, c.normal_force);
  }
  EXPECT_LT(steps, 400000) << "never crushed";
  return out;
}

// A sphere of radius r pressed between two steel plates until the contact criterion crushes it: the closure of
// the plates (both contacts' overlaps) and the largest ceiling force before the break.
struct PlateCrush {
  double closure = 0, force_before = 0, E_star = 0;
};
// density_factor: the sphere's density over the rock's (a fragment still growing is denser).
PlateCrush crush_between_plates(double r, const coupling::CrushingStrength& strength, double density_factor = 1) {
  dem::WorldParams wp;
  wp.dt = 1e-6;
  wp.threads = 1;
  dem::World w(wp);
  auto floor = plate(w, 0.0, "floor"), ceiling = plate(w, 2 * r + 1e-5, "ceiling");
  w.add_interaction(floor);
  w.add_interaction(ceiling);
  const double x[3] = {0, 0, r};
  const double rho = w.materials().material(0).density;
  w.add_particle(x, r, 0, density_factor * rho, nullptr, nullptr);
  auto crushed = [&] {
    return !coupling::crushed_particles(w.particles(), {floor.get(), ceiling.get()}, strength, rho).empty();
  };
  const auto press = press_until(w, *ceiling, 2 * r + 1e-5, 0.02, crushed);
  return {2 * r - press.z, press.force_before, w.materials().pair(0, 1).E_star};
}

}  // namespace

// A sphere pressed between two steel plates breaks when the contact force reaches F_c, i.e. at the Hertz
// overlap delta_c = (F_c / (4/3 E* sqrt(r)))^(2/3) on each side (Eq. 16 integrated), not earlier or later.
TEST(MetaparticleCrushing, SphereBetweenPlatesBreaksAtItsStrength) {
  const double r = 6e-3, sigma = 3.77e6;
  const auto c = crush_between_plates(r, sigma);
  const double Fc = coupling::crushing_force(2 * r, sigma);
  const double delta_c = std::pow(Fc / (4.0 / 3.0 * c.E_star * std::sqrt(r)), 2.0 / 3.0);
  std::printf("crushed at closure %.4g m (2 delta_c = %.4g m), F before %.1f N, F_c %.1f N\n", c.closure,
              2 * delta_c, c.force_before, Fc);
  EXPECT_NEAR(c.closure, 2 * delta_c, 0.03 * 2 * delta_c);
  EXPECT_LE(c.force_before, Fc);
  EXPECT_GT(c.force_before, 0.98 * Fc);
}

// A sphere denser than rock stands for a larger lump (d_eq = 2 r (rho / rho_rock)^(1/3)) but breaks at the contact
// stress of a rock sphere of its own size: F_c = pi (2 r)^2 sigma(d_eq) / 2.8. Six times denser without the size
// effect: the same closure as the rock sphere, where F_c(d_eq) would take 6^(2/3) = 3.3x the force and 2.2x the
// closure (0.44 of the radius at a 1 mm fragment's strength, the blow-up bound being 0.5). A lighter sphere keeps
// F_c(d_eq).
TEST(MetaparticleCrushing, DenseSphereBreaksAtTheStressOfItsOwnSize) {
  const double r = 6e-3, sigma = 3.77e6, rho = dem::rock_table4().density;
  const coupling::CrushingStrength plain(sigma), sized(sigma, 0.05, 0.54);
  const double m_dense = 6 * rho * 4.0 / 3.0 * M_PI * r * r * r, d_dense = 2 * r * std::cbrt(6.0);
  EXPECT_NEAR(plain.force_of_sphere(m_dense, r, rho), coupling::crushing_force(2 * r, sigma), 1e-9);
  EXPECT_NEAR(sized.force_of_sphere(m_dense, r, rho), coupling::crushing_force(2 * r, sized.sigma(d_dense)), 1e-9);
  EXPECT_NEAR(sized.force_of_sphere(m_dense / 6, r, rho), sized.force(2 * r), 1e-9 * sized.force(2 * r));
  EXPECT_NEAR(sized.force_of_sphere(m_dense / 48, r, rho), sized.force(r), 1e-9 * sized.force(r));  // light: d_eq = r
  const auto rock = crush_between_plates(r, plain), dense = crush_between_plates(r, plain, 6.0);
  std::printf("closure at breakage: rock sphere %.4g m, 6x denser %.4g m\n", rock.closure, dense.closure);
  EXPECT_NEAR(dense.closure, rock.closure, 0.03 * rock.closure);
  EXPECT_NEAR(dense.force_before, rock.force_before, 0.03 * rock.force_before);
}

// Size effect: sigma(d) = sigma_t (d_ref / d)^k. At d_ref the strength is sigma_t; a 4x smaller lump is 4^k
// stronger; F_c then grows as d^(2 - k); k = 0 (or a bare number) is the size-independent strength.
TEST(MetaparticleCrushing, SizeEffectMakesSmallLumpsStronger) {
  const coupling::CrushingStrength s(3.77e6, 0.05, 0.54);
  EXPECT_DOUBLE_EQ(s.sigma(0.05), 3.77e6);
  EXPECT_NEAR(s.sigma(0.0125), 3.77e6 * std::pow(4.0, 0.54), 1.0);  // 7.97 MPa
  EXPECT_NEAR(s.sigma(0.0125), 7.97e6, 0.01e6);
  EXPECT_NEAR(s.force(24e-3) / s.force(12e-3), std::pow(2.0, 2.0 - 0.54), 1e-12);
  EXPECT_DOUBLE_EQ(coupling::CrushingStrength(3.77e6).force(12e-3), coupling::crushing_force(12e-3, 3.77e6));
  coupling::CrushingParams p;
  p.tensile_strength = 2e6;
  p.reference_size = 0.04;
  p.size_exponent = 0.3;
  EXPECT_DOUBLE_EQ(coupling::CrushingStrength(p).sigma(0.01), 2e6 * std::pow(4.0, 0.3));
}

// With the size effect a 12 mm sphere between plates holds (50 / 12)^0.54 = 2.16x the force of the
// size-independent law, and breaks at that force.
TEST(MetaparticleCrushing, SphereBetweenPlatesBreaksAtItsSizeDependentStrength) {
  const double r = 6e-3;
  const coupling::CrushingStrength s(3.77e6, 0.05, 0.54);
  const auto c = crush_between_plates(r, s);
  const double Fc = s.force(2 * r);
  std::printf("size effect: F before %.1f N, F_c %.1f N (size-independent %.1f N)\n", c.force_before, Fc,
              coupling::crushing_force(2 * r, 3.77e6));
  EXPECT_NEAR(Fc / coupling::crushing_force(2 * r, 3.77e6), 2.16, 0.01);
  EXPECT_LE(c.force_before, Fc);
  EXPECT_GT(c.force_before, 0.98 * Fc);
}

// The crushing keys of dem.crushing are read with their units, and a value out of range is refused by name.
TEST(MetaparticleCrushing, ConfigReadsTheSizeEffect) {
  auto load = [](const std::string& extra) {
    return test_chamber::quick_demo_with(extra, "    progeny_exponent: 1.0");
  };
  const auto p = load("    size_exponent: 0.54\n    reference_size_mm: 40\n");
  EXPECT_DOUBLE_EQ(p.crushing.size_exponent, 0.54);
  EXPECT_DOUBLE_EQ(p.crushing.reference_size, 0.04);
  const auto none = load("");
  EXPECT_EQ(none.crushing.size_exponent, 0.0);
  EXPECT_DOUBLE_EQ(none.crushing.reference_size, 0.05);
  try {
    load("    size_exponent: 2\n");
    FAIL() << "expected a ConfigError";
  } catch (const core::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("dem.crushing.size_exponent"), std::string::npos) << e.what();
  }
}

// In a chamber, crushed metaparticles leave as product fines: the mass balance still closes, the product's
// fine end is the progeny's, and no metaparticle stays pressed into a liner beyond its strength.
TEST(MetaparticleCrushing, ChamberKeepsItsMassBalanceAndScreensTheFines) {
  auto p = crushing_chamber();
  auto run = [&](coupling::ChamberDem& dem) {
    coupling::BodyMotion m, c;
    c.com = Eigen::Vector3d(0, 0, p.concave_com_z_m);
    for (int k = 0; k < 120; ++k) {
      test_chamber::gyrate(p, k * 1e-3, 3.0 * M_PI / 180, &m);
      dem.advance(m, c, 1e-3);
    }
  };
  coupling::ChamberDem dem(p);
  run(dem);
  auto q = p;
  q.crushing.enabled = false;
  coupling::ChamberDem uncrushed(q);
  run(uncrushed);
  // No sphere is pressed into a liner deeper than its strength allows: F_c = 4/3 E* sqrt(r) delta^1.5 gives
  // delta_c / r = (3 pi sigma_t / (2.8 E*))^(2/3), the same for every size (rock on steel).
  const double E_star = dem.world().materials().pair(0, 1).E_star;
  const double delta_c = std::pow(3 * M_PI * p.crushing.tensile_strength / (2.8 * E_star), 2.0 / 3.0);
  std::printf("deepest liner overlap %.5f r with crushing (delta_c %.5f r), %.5f r without\n",
              dem.deepest_liner_overlap(), delta_c, uncrushed.deepest_liner_overlap());
  EXPECT_LE(dem.deepest_liner_overlap(), 1.5 * delta_c);  // plus at most one DEM step of approach
  EXPECT_GT(uncrushed.deepest_liner_overlap(), 3 * delta_c);
  // Crushed spheres removed in batches of 0.2 ms: fewer neighbour rebuilds, overlaps still bounded by delta_c
  // plus what the liner closes in one batch (< 1 m/s x 0.2 ms on the smallest, 3.6 mm sphere).
  auto b = p;
  b.crushing.batch_s = 2e-4;
  coupling::ChamberDem batched(b);
  run(batched);
  const auto sb = batched.product();
  std::printf("batched: %ld crushed, %ld neighbour rebuilds (%ld one by one), deepest overlap %.4f r\n",
              sb.metaparticles_crushed, batched.world().n_rebuilds(), dem.world().n_rebuilds(),
              batched.deepest_liner_overlap());
  EXPECT_GT(sb.metaparticles_crushed, 0);
  EXPECT_LT(batched.world().n_rebuilds(), dem.world().n_rebuilds());
  EXPECT_LE(batched.deepest_liner_overlap(), 1.5 * delta_c + 1.0 * 2e-4 / 3.6e-3);
  EXPECT_NEAR(sb.fed_kg, sb.in_chamber_kg + sb.discharged_kg + sb.lost_kg, 1e-9 * sb.fed_kg);
  // With the size effect (k = 1 from 50 mm) the 7-9 mm spheres are ~6x stronger: the chamber crushes fewer
  // (248 against 342; the gyrating liners press hard enough to break many at either strength).
  auto k = p;
  k.crushing.size_exponent = 1.0;
  coupling::ChamberDem stronger(k);
  run(stronger);
  std::printf("size effect k = 1: %ld crushed (%ld without)\n", stronger.product().metaparticles_crushed,
              dem.product().metaparticles_crushed);
  EXPECT_LT(stronger.product().metaparticles_crushed, 0.8 * dem.product().metaparticles_crushed);
  const auto s = dem.product();
  std::printf("crushed %ld metaparticles, %.4f kg; discharged %.4f kg; passing 1 mm %.1f %%\n",
              s.metaparticles_crushed, s.crushed_kg, s.discharged_kg, s.passing_pct[0]);
  ASSERT_GT(s.metaparticles_crushed, 0);
  EXPECT_LE(s.crushed_kg, s.discharged_kg + 1e-15);
  EXPECT_NEAR(s.fed_kg, s.in_chamber_kg + s.discharged_kg + s.lost_kg, 1e-9 * s.fed_kg);
  // Nothing but the fines can pass 4 mm here (the smallest sphere is 7.2 mm wide): passing 1 mm is the
  // crushed mass times the progeny's 1 mm share, (1 mm / d)^1, over the discharge.
  EXPECT_GT(s.passing_pct[0], 0.0);
  EXPECT_LE(s.passing_pct[0], 100.0 * s.crushed_kg / s.discharged_kg * (1e-3 / 7.2e-3) + 1e-9);
  EXPECT_GE(s.passing_pct[0], 100.0 * s.crushed_kg / s.discharged_kg * (1e-3 / 8.8e-3) - 1e-9);
}

// Four fragments in a tetrahedron fill the parent as closely as four equal spheres can: each touches the
// parent's surface from inside and the other three, with no overlap, whatever the rotation.
TEST(MetaparticleCrushing, TetrahedralFragmentsTouchEachOtherAndTheParentFromInside) {
  const double r = 6e-3;
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, -0.5).normalized()).toRotationMatrix();
  const auto f = coupling::tetrahedral_fragments(r, rot);
  EXPECT_NEAR(f.radius, 0.4495 * r, 1e-4 * r);  // r / (1 + sqrt(3/2))
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int a = 0; a < 4; ++a) {
    sum += f.offset[a];
    EXPECT_NEAR(f.offset[a].norm() + f.radius, r, 1e-12 * r);
    for (int b = a + 1; b < 4; ++b) EXPECT_NEAR((f.offset[a] - f.offset[b]).norm(), 2 * f.radius, 1e-12 * r);
  }
  EXPECT_LT(sum.norm(), 1e-15);  // centred: the fragments' mass centre is the parent's
  // Mass-equivalent size of a quarter of the parent: d / 4^(1/3).
  const double rho = 2600, m = rho * 4.0 / 3.0 * M_PI * r * r * r;
  EXPECT_NEAR(coupling::equivalent_diameter(m, rho), 2 * r, 1e-12);
  EXPECT_NEAR(coupling::equivalent_diameter(m / 4, rho), 2 * r / std::cbrt(4.0), 1e-12);
}

// With crushing.fragments, crushed spheres stay in the chamber as fragments (each a quarter of its parent's mass,
// heavier than its sphere) until they are finer than min_fragment_m, where without fragments they leave at once.
// The mass balance closes either way.
TEST(MetaparticleCrushing, FragmentsStayInTheBedUntilFinerThanTheLimit) {
  auto p = crushing_chamber();
  p.crushing.batch_s = 2e-4;
  p.crushing.min_fragment_m = 4e-3;  // 8 mm spheres -> 5.0 mm fragments -> 3.2 mm: fines
  auto run = [&](coupling::ChamberDem& dem, double* mantle_force) {
    coupling::BodyMotion m, c;
    c.com = Eigen::Vector3d(0, 0, p.concave_com_z_m);
    double f = 0;
    int n = 0;
    for (int k = 0; k < 120; ++k) {
      test_chamber::gyrate(p, k * 1e-3, 3.0 * M_PI / 180, &m);
      const auto w = dem.advance(m, c, 1e-3);
      if (k >= 60) f += w.first.force.norm(), ++n;
    }
    *mantle_force = f / n;
  };
  auto q = p;
  q.crushing.fragments = true;
  coupling::ChamberDem fines(p), frag(q);
  double f_fines = 0, f_frag = 0;
  run(fines, &f_fines);
  run(frag, &f_frag);
  const auto a = fines.product(), b = frag.product();
  std::printf("fines only: %ld crushed, %.4f kg in the chamber, mantle force %.1f N\n", a.metaparticles_crushed,
              a.in_chamber_kg, f_fines);
  std::printf("fragments: %ld fragmented, %ld to fines, %.4f kg in the chamber, mantle force %.1f N\n",
              b.metaparticles_fragmented, b.metaparticles_crushed, b.in_chamber_kg, f_frag);
  EXPECT_EQ(a.metaparticles_fragmented, 0);
  ASSERT_GT(b.metaparticles_fragmented, 0);
  EXPECT_NEAR(b.fed_kg, b.in_chamber_kg + b.discharged_kg + b.lost_kg, 1e-9 * b.fed_kg);
  EXPECT_GT(b.in_chamber_kg, a.in_chamber_kg);
  EXPECT_LT(b.crushed_kg, a.crushed_kg);
  // Every sphere is a whole metaparticle or a fragment: a quarter, or a quarter of a quarter, of its parent's mass
  // at 2.75 or 7.56 times the rock's density (fragments finer than 4 mm leave as fines).
  const auto& P = frag.world().particles();
  const double rho = frag.world().materials().material(0).density;
  long heavy = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double ratio = test_chamber::sphere_density(P, i) / rho;
    const bool known = std::abs(ratio - 1) < 1e-9 || std::abs(ratio - std::pow(1 + std::sqrt(1.5), 3) / 4) < 1e-9;
    EXPECT_TRUE(known) << "particle " << i << " at " << ratio << " x the rock density";
    if (ratio > 1.5) {
      ++heavy;
      EXPECT_GE(coupling::equivalent_diameter(P.m[i], rho), p.crushing.min_fragment_m);
    }
  }
  EXPECT_GT(heavy, 0);
  // Not asserted: the mean mantle force. Here it is about the same (13.6 N fines only, 12.9 N with fragments):
  // every liner contact is still capped by its sphere's F_c, and fragments are weaker (F_c ~ d^2).
}

// With fragment_growth_s, the fragments grow at constant mass to the rock's density: the crushed rock keeps its
// volume in the bed. Heavy fragments (no growth) keep 36 % of it.
TEST(MetaparticleCrushing, GrowingFragmentsKeepTheRocksVolume) {
  auto p = crushing_chamber();
  p.crushing.batch_s = 2e-4;
  p.crushing.min_fragment_m = 4e-3;
  p.crushing.fragments = true;
  auto q = p;
  q.crushing.fragment_growth_s = 5e-3;
  coupling::ChamberDem heavy(p), grown(q);
  coupling::BodyMotion m, c;
  c.com = Eigen::Vector3d(0, 0, p.concave_com_z_m);
  for (int k = 0; k < 140; ++k) {  // 120 ms of gyration, then 20 ms held at the last pose
    if (k < 120) test_chamber::gyrate(p, k * 1e-3, 3.0 * M_PI / 180, &m);
    heavy.advance(m, c, 1e-3);
    grown.advance(m, c, 1e-3);
  }
  const double rho = grown.world().materials().material(0).density;
  // solid volume of the spheres / volume of their mass at the rock's density
  auto volume_ratio = [&](const coupling::ChamberDem& d) {
    const auto& P = d.world().particles();
    double v = 0, vm = 0;
    for (std::size_t i = 0; i < P.size(); ++i) v += 4.0 / 3.0 * M_PI * std::pow(P.r[i], 3), vm += P.m[i] / rho;
    return v / vm;
  };
  const auto a = heavy.product(), b = grown.product();
  std::printf("heavy fragments: %ld fragmented, %.4f kg in the chamber, sphere volume %.3f of the mass's\n",
              a.metaparticles_fragmented, a.in_chamber_kg, volume_ratio(heavy));
  std::printf("growing fragments: %ld fragmented, %.4f kg in the chamber, sphere volume %.3f of the mass's, %zu "
              "still growing\n", b.metaparticles_fragmented, b.in_chamber_kg, volume_ratio(grown),
              grown.growing_fragments());
  ASSERT_GT(b.metaparticles_fragmented, 20);
  EXPECT_NEAR(b.fed_kg, b.in_chamber_kg + b.discharged_kg + b.lost_kg, 1e-9 * b.fed_kg);
  EXPECT_LT(volume_ratio(heavy), 0.95);
  // Every fragment older than the growth time is at the rock's density: only those still growing (crushed during
  // the last 5 ms, a few as the bed settled after the gyration) are denser.
  const auto& P = grown.world().particles();
  std::size_t denser = 0;
  for (std::size_t i = 0; i < P.size(); ++i) {
    const double ratio = test_chamber::sphere_density(P, i) / rho;
    EXPECT_GT(ratio, 1 - 1e-9);
    if (ratio > 1 + 1e-9) ++denser;
  }
  EXPECT_EQ(denser, grown.growing_fragments());
  EXPECT_LT(grown.growing_fragments(), 40u);
  EXPECT_GT(volume_ratio(grown), 0.99);
  // Placement at birth: only growing fragments are born smaller (place_fragments).
  std::printf("birth: deepest overlap %.2f (heavy) and %.2f (growing) of the smaller radius; born smaller: %ld, %ld\n",
              heavy.deepest_birth_overlap(), grown.deepest_birth_overlap(), heavy.fragments_shrunk_at_birth(),
              grown.fragments_shrunk_at_birth());
  EXPECT_EQ(heavy.fragments_shrunk_at_birth(), 0);
}

// Fragment placement (closed forms): a liner plane pressing a sphere of radius r by 0.2 r. A tetrahedron with a
// vertex towards it leaves that fragment 0.2 r deep, 0.445 of its 0.4495 r; turned with a face towards it, all four
// are clear (the face's vertices sit 0.5505 r / 3 towards it). Kept in the vertex turn, the deep fragment is born
// at h / (1 - 0.25) = 0.333 r, exactly 0.25 deep, and the others keep their radius.
TEST(MetaparticleCrushing, FragmentsAreTurnedAndBornClearOfTheirNeighbours) {
  const double r = 5e-3;
  const Eigen::Vector3d x(0, 0, 0);
  const coupling::Obstacle plane{Eigen::Vector3d(0, 0, -0.8 * r), Eigen::Vector3d(0, 0, 1), 0.0};
  // rotations taking the tetrahedron's vertex (1, 1, 1) (and so the face opposite (-1, -1, -1)) to -z or +z
  const Eigen::Vector3d v = Eigen::Vector3d(1, 1, 1).normalized();
  const Eigen::Matrix3d vertex_down = Eigen::Quaterniond::FromTwoVectors(v, -Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d face_down = Eigen::Quaterniond::FromTwoVectors(v, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const double rf = coupling::fragment_radius(r);
  const auto one = coupling::place_fragments(x, r, {vertex_down}, {plane}, false);
  EXPECT_NEAR(one.deepest, 0.2 * r / rf, 1e-9);
  for (double rb : one.birth_radius) EXPECT_DOUBLE_EQ(rb, rf);
  const auto best = coupling::place_fragments(x, r, {vertex_down, face_down}, {plane}, true);
  EXPECT_DOUBLE_EQ(best.deepest, 0.0);
  for (int k = 0; k < 4; ++k) EXPECT_LT(coupling::overlap_ratio(x + best.set.offset[k], rf, plane), 0);
  for (double rb : best.birth_radius) EXPECT_DOUBLE_EQ(rb, rf);
  const auto shrunk = coupling::place_fragments(x, r, {vertex_down}, {plane}, true);
  int smaller = 0;
  for (int k = 0; k < 4; ++k) {
    const double rb = shrunk.birth_radius[k];
    if (rb < rf) {
      ++smaller;
      EXPECT_NEAR(rb, (0.8 - (1 - 1 / (1 + std::sqrt(1.5)))) * r / 0.75, 1e-12);
      EXPECT_NEAR(coupling::overlap_ratio(x + shrunk.set.offset[k], rb, plane), coupling::kFragmentBirthOverlap, 1e-9);
    } else {
      EXPECT_DOUBLE_EQ(rb, rf);
    }
  }
  EXPECT_EQ(smaller, 1);
  // A sphere obstacle, larger and smaller than the fragment: born just at the bound, measured on the smaller radius.
  for (double R : {2 * r, 0.3 * r}) {
    const Eigen::Vector3d c = shrunk.set.offset[0] + Eigen::Vector3d(0, 0, rf + R - 0.4 * std::min(rf, R));
    const coupling::Obstacle sphere{c, Eigen::Vector3d::Zero(), R};
    const auto s = coupling::place_fragments(x, r, {vertex_down}, {sphere}, true);
    EXPECT_NEAR(coupling::overlap_ratio(x + s.set.offset[0], s.birth_radius[0], sphere), coupling::kFragmentBirthOverlap,
                1e-9) << "R = " << R;
    EXPECT_LT(s.birth_radius[0], rf);
  }
  EXPECT_THROW(coupling::place_fragments(x, r, {}, {plane}, true), std::invalid_argument);
}

// Two spheres of radius r, 0.2 r into each other, crushed in one batch (closed forms). The first can only turn a
// vertex towards the second: that fragment reaches the first's surface, 0.2 r into the second sphere. Turned the
// same way, the second's vertex fragment would be 0.2 r into it, 0.445 of the fragments' radius; with a face towards
// the first, its fragments are clear (centres 1.186 r from it, radii 0.899 r together). The second sees the first's
// fragments only through its crushed neighbour: without it, its first turn is as good as any.
TEST(MetaparticleCrushing, FragmentsOfNeighboursCrushedTogetherAreClearOfEachOther) {
  const double r = 5e-3, rf = coupling::fragment_radius(r);
  const Eigen::Vector3d v = Eigen::Vector3d(1, 1, 1).normalized();
  using Q = Eigen::Quaterniond;
  const Eigen::Matrix3d vertex_up = Q::FromTwoVectors(v, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d vertex_down = Q::FromTwoVectors(v, -Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d face_down = vertex_up;  // the face opposite the vertex (1, 1, 1) then points down
  auto batch_of = [&](std::vector<Eigen::Matrix3d> second_turns, bool neighbours) {
    std::vector<coupling::CrushedSphere> b(2);
    b[0].x = Eigen::Vector3d::Zero();
    b[1].x = Eigen::Vector3d(0, 0, 1.8 * r);
    b[0].r = b[1].r = r;
    b[0].turns = {vertex_up};
    b[1].turns = std::move(second_turns);
    if (neighbours) b[0].crushed_neighbours = {1}, b[1].crushed_neighbours = {0};
    return b;
  };
  // deepest overlap ratio between the two sets of fragments, at their birth radii
  auto deepest_between = [&](const std::vector<coupling::CrushedSphere>& b,
                             const std::vector<coupling::PlacedFragments>& p) {
    double worst = -1e300;
    for (int k = 0; k < 4; ++k)
      for (int l = 0; l < 4; ++l) {
        const coupling::Obstacle o{b[0].x + p[0].set.offset[k], Eigen::Vector3d::Zero(), p[0].birth_radius[k]};
        worst = std::max(worst, coupling::overlap_ratio(b[1].x + p[1].set.offset[l], p[1].birth_radius[l], o));
      }
    return worst;
  };
  auto blind = batch_of({vertex_down, face_down}, false);
  const auto p_blind = coupling::place_crushed_batch(blind, true);
  EXPECT_NEAR(deepest_between(blind, p_blind), 0.2 * r / rf, 1e-9);
  auto seen = batch_of({vertex_down, face_down}, true);
  const auto p_seen = coupling::place_crushed_batch(seen, true);
  EXPECT_EQ(seen[1].obstacles.size(), 4u);  // the first's four fragments
  EXPECT_TRUE(seen[0].obstacles.empty());   // placed first, before the second's
  EXPECT_DOUBLE_EQ(p_seen[1].deepest, 0.0);
  const double a = r - rf;  // a fragment centre's distance from its parent's
  const double gap = std::hypot(1.8 * r - a - a / 3, a * std::sqrt(8.0) / 3);  // first's top to second's lower three
  EXPECT_NEAR(deepest_between(seen, p_seen), (2 * rf - gap) / rf, 1e-9);
  // Only the vertex turn offered: the second's deep fragment is born smaller, exactly at the bound.
  auto forced = batch_of({vertex_down}, true);
  const auto p_forced = coupling::place_crushed_batch(forced, true);
  EXPECT_NEAR(p_forced[1].deepest, 0.2 * r / rf, 1e-9);
  EXPECT_NEAR(deepest_between(forced, p_forced), coupling::kFragmentBirthOverlap, 1e-9);
  // A sphere that leaves as fines (no turns) is not placed and is no obstacle.
  auto fines = batch_of({vertex_down}, true);
  fines[0].turns.clear();
  const auto p_fines = coupling::place_crushed_batch(fines, true);
  EXPECT_TRUE(fines[1].obstacles.empty());
  EXPECT_DOUBLE_EQ(p_fines[0].birth_radius[0], 0.0);
  EXPECT_DOUBLE_EQ(p_fines[1].birth_radius[0], rf);
}

// The stress criterion's equivalent diametral load (closed forms): the diametral test's F; F (1 - K) under
// uniaxial load F with lateral contact loads K F (K <= 0.4), F (1 + 2K) / 3 above; F under equal loads F from all
// six sides (the pressure term).
TEST(MetaparticleCrushing, EquivalentDiametralLoadOfClosedFormLoadings) {
  const double r = 5e-3, F = 800.0;
  // two opposite contacts at +-r n with inward forces -+F n: S = -2 r F n n
  const double diametral[6] = {0, 0, -2 * r * F, 0, 0, 0};
  EXPECT_NEAR(coupling::equivalent_diametral_load(diametral, r), F, 1e-9 * F);
  const double K = 0.4;
  const double confined[6] = {-2 * r * K * F, -2 * r * K * F, -2 * r * F, 0, 0, 0};
  EXPECT_NEAR(coupling::equivalent_diametral_load(confined, r), (1 - K) * F, 1e-9 * F);
  const double K2 = 0.7;
  const double well_confined[6] = {-2 * r * K2 * F, -2 * r * K2 * F, -2 * r * F, 0, 0, 0};
  EXPECT_NEAR(coupling::equivalent_diametral_load(well_confined, r), (1 + 2 * K2) / 3 * F, 1e-9 * F);
  const double hydrostatic[6] = {-2 * r * F, -2 * r * F, -2 * r * F, 0, 0, 0};
  EXPECT_NEAR(coupling::equivalent_diametral_load(hydrostatic, r), F, 1e-9 * F);
  // frame independent: the diametral load along (1, 1, 0) / sqrt(2)
  const double turned[6] = {-r * F, -r * F, 0, -r * F, 0, 0};
  EXPECT_NEAR(coupling::equivalent_diametral_load(turned, r), F, 1e-9 * F);
}

// A column of three spheres pressed between two plates: the middle one, the smallest and weakest, touches no liner.
// The contact criterion never crushes it; the stress criterion crushes it, first, when the column's force reaches
// its F_c (from its contacts with the outer spheres), and crushes a lone sphere between the plates at the same F_c
// as the contact criterion.
TEST(MetaparticleCrushing, StressCriterionCrushesASphereInsideAColumnAtItsStrength) {
  dem::WorldParams wp;
  wp.dt = 5e-7;
  wp.threads = 1;
  wp.gravity = {{0, 0, 0}};
  dem::World w(wp);
  const double R = 6e-3, rm = 4e-3, sigma = 3.77e6, v = 0.02;
  const double h = 2 * R + 2 * rm + 2 * R;  // column height
  auto floor = plate(w, 0.0, "floor"), ceiling = plate(w, h + 1e-5, "ceiling");
  w.add_interaction(floor);
  w.add_interaction(ceiling);
  const double a[3] = {0, 0, R}, b[3] = {0, 0, 2 * R + rm}, c[3] = {0, 0, 2 * R + 2 * rm + R};
  w.add_particle(a, R, 0);
  w.add_particle(b, rm, 0);
  w.add_particle(c, R, 0);
  const double rho = w.materials().material(0).density;
  std::vector<double> s;
  std::vector<std::size_t> by_stress;
  auto crushed = [&] {
    EXPECT_TRUE(coupling::crushed_particles(w.particles(), {floor.get(), ceiling.get()}, 1e3 * sigma, rho).empty());
    w.contact_stress(s);
    by_stress = coupling::crushed_by_stress(w.particles(), s, {floor.get(), ceiling.get()}, sigma, rho);
    return !by_stress.empty();
  };
  const double force = press_until(w, *ceiling, h + 1e-5, v, crushed).force_before;
  const double Fc = coupling::crushing_force(2 * rm, sigma);
  std::printf("column: middle sphere crushed at a column force of %.1f N (its F_c %.1f N)\n", force, Fc);
  ASSERT_EQ(by_stress.size(), 1u);
  EXPECT_EQ(by_stress[0], 1u);  // the middle sphere
  EXPECT_GT(force, 0.97 * Fc);
  EXPECT_LE(force, 1.01 * Fc);
  // the contact criterion at the same strength sees only the outer spheres' liner contacts, below their F_c
  EXPECT_TRUE(coupling::crushed_particles(w.particles(), {floor.get(), ceiling.get()}, sigma, rho).empty());
}
