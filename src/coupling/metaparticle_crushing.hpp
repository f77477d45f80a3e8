#pragma once
// Crushing of single metaparticles (an extension beyond the paper, off unless dem.crushing.enabled).
// A bonded-particle rock breaks into its metaparticles; a metaparticle itself is a rigid sphere that cannot
// break (the paper, section 4.1.3: "the minimum size limit of the metaparticles makes it impossible to acquire
// the product size below that level"). At the closed side of a running crusher the liners come closer than a
// coarse metaparticle is wide, and the inertia crusher's mantle presses with ~200 kN: an unbreakable sphere is
// then squeezed deep into the liner and its neighbours (forces and power inflated, and eventually a blow-up).
// Here a metaparticle whose contact with a liner carries more than its crushing strength breaks into fines:
//   F_c = pi d^2 sigma_t / 2.8   (point-load strength of an irregular lump, Hiramatsu & Oka 1966,
//                                 with the rock's tensile strength sigma_t, e.g. the Brazilian 3.77 MPa, Eq. 26)
// The fines are far smaller than the setting and pass straight through: the sphere leaves the DEM and its
// mass joins the product with a Gaudin-Schuhmann progeny distribution below its size d:
//   passing(x) = (x / d)^n  for x < d.
// criterion `stress` (instead of `contact`, the liner contact above): a sphere breaks on its whole load, from the
// liners, its neighbours and its bonds alike. Its mean stress (Love-Weber: S = sum over contacts of sym(a (x) f))
// gives an equivalent diametral load F_eq = max(von Mises(S), -tr(S) / 3) / (2 r): the force F of a diametral test
// (S = -2 r F n n), (1 - K) F under a load F with lateral loads K F (K <= 0.4), and under equal loads F from six
// sides F, so a sphere pressed from all sides breaks when each contact carries F_c (the pressure term; without it
// a confined sphere would never break). It breaks when F_eq > F_c. A sphere in a bed is then up to 1.67x stronger
// than one pinched between two points, and force chains through the bed are bounded.
// With `fragments` on, a crushed sphere is replaced instead (particle replacement, as in DEM crusher models
// after Cleary & Sinnott 2015): four spheres of radius 0.4495 r packed in a tetrahedron inside the parent, each
// with a quarter of its mass (density x 2.75: the lumps are irregular and nest, spheres would not fit). The
// fragments stay in the bed and are crushed again; a fragment finer than min_fragment_m (by its mass-equivalent
// size) leaves as fines as above. With fragment_growth_s > 0 the fragments then grow, at constant mass, to the
// rock's density (radius r / 4^(1/3) = 0.63 r) within that time: the crushed rock keeps its volume in the bed, as
// the lumps it stands for would (Cleary & Sinnott grow the progeny of their particle replacement in the same way).
// With 0 they stay 2.75x denser and take 36 % of the parent's volume. Experimental (README). Sizes (strength,
// progeny, screening) are mass-equivalent (a sphere denser than rock takes F_c over its own area:
// CrushingStrength::force_of_sphere):
//   d_eq = (6 m / (pi rho_rock))^(1/3),
// with rho_rock the rock spheres' density (the material's, or heavier with feed.rock_density: chamber_params.hpp).
// Size effect (size_exponent k > 0): small lumps hold fewer and smaller flaws and are stronger (Weibull),
//   sigma(d) = sigma_t (d_ref / d)^k,
// with sigma_t measured at d_ref (the 50 mm Brazilian disk, Eq. 26). Single-particle crushing of limestone,
// 20-120 mm, gives k = 0.54; Weibull's volume scaling gives k = 3 / m (m ~ 5-10 for rock). k = 0: one strength
// for every size, as before.
#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Dense>

#include "dem/mesh_contact.hpp"
#include "dem/particles.hpp"

namespace coupling {

struct CrushingParams {
  bool enabled = false;
  double tensile_strength = 3.77e6;  // Pa, sigma_t of the rock (Brazilian test, Eq. 26)
  double progeny_exponent = 1.0;     // n of the Gaudin-Schuhmann progeny distribution
  // Spheres found crushed within this time leave together (each removal compacts the particle arrays and the
  // neighbour list; before removals stopped forcing a list rebuild, one by one took 40 % of a full chamber's
  // run). Meanwhile a crushed sphere still carries load: its overlap grows by at most the closing speed x
  // batch_s. 0: at once.
  double batch_s = 0.0;
  bool stress_criterion = false;  // crush on the sphere's whole load (above); off: on its liner contacts only
  bool fragments = false;        // replace a crushed sphere by four (above); off: it leaves as fines at once
  double min_fragment_m = 4e-3;  // m, mass-equivalent size below which a fragment leaves as fines
  double fragment_growth_s = 0;  // s, time a fragment takes to grow to the rock's density (0: it stays heavy)
  double reference_size = 0.05;  // m, d_ref: the size at which tensile_strength was measured
  double size_exponent = 0;      // k of the size effect (above); 0: none
};

// The crushing strength of a lump of size d: F_c = pi d^2 sigma(d) / 2.8 with sigma(d) = sigma_t (d_ref / d)^k.
// From a number alone: one strength for every size.
struct CrushingStrength {
  CrushingStrength(double tensile_strength, double reference_size = 0.05, double size_exponent = 0)  // NOLINT
      : sigma_t(tensile_strength), d_ref(reference_size), k(size_exponent) {}
  explicit CrushingStrength(const CrushingParams& p)
      : CrushingStrength(p.tensile_strength, p.reference_size, p.size_exponent) {}
  double sigma(double d) const;  // Pa
  double force(double d) const;  // N
  // F_c of a sphere of radius r and mass m, a lump of rock density rho: the strength sigma(d_eq) of its
  // mass-equivalent size, over the area of the smaller of d_eq and 2 r. A sphere denser than rock (a fragment
  // still growing, or kept heavy) then breaks at the contact stress of a rock sphere of its own size, so its
  // overlap at breakage stays that of a rock sphere (not (rho / rho_rock)^(1/3) deeper, 1.8x at 6x the density).
  double force_of_sphere(double m, double r, double rho) const;  // N
  double sigma_t, d_ref, k;
};

// Mass-equivalent diameter of a sphere of mass m of rock of density rho (m).
double equivalent_diameter(double m, double rho);

// Radius of each of a crushed sphere's four fragments: r / (1 + sqrt(3/2)) = 0.4495 r.
double fragment_radius(double parent_radius);

// A crushed sphere's four fragments: radius (m) and centre offsets from the parent's centre (m), a regular
// tetrahedron turned by `rotation` (a rotation matrix).
struct FragmentSet {
  double radius = 0;
  std::array<Eigen::Vector3d, 4> offset;
};
FragmentSet tetrahedral_fragments(double parent_radius, const Eigen::Matrix3d& rotation);

// Placing a crushed sphere's fragments. A sphere is crushed while pressed into its neighbours, by up to ~0.25 of
// its radius for a small rock sphere at its strength. A fragment inside it keeps at most that overlap, but measured
// against its own 0.45x radius it is up to 2.2x deeper: beyond the blow-up bound (0.5) and a kick of stored energy
// at birth. So the tetrahedron is turned, of `orientations` tries, to the one whose deepest fragment overlap (a
// fraction of the smaller radius) is least, and, where fragments grow, a fragment still deeper than
// kFragmentBirthOverlap is born that much smaller (at the same mass) and grows into place with the others.
constexpr double kFragmentBirthOverlap = 0.25;

// What a fragment may touch at birth: a sphere (centre c, radius r > 0) or a liner's tangent plane (point c on it,
// unit normal n towards the crushed sphere, r = 0).
struct Obstacle {
  Eigen::Vector3d c = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::Zero();
  double r = 0;
};
// Overlap of a sphere (x, r) with an obstacle as a fraction of the smaller radius (of r for a plane); <= 0 clear.
double overlap_ratio(const Eigen::Vector3d& x, double r, const Obstacle& o);
// The fragments of a sphere (centre x, radius r) turned by the best of `orientations` (above), and per fragment its
// birth radius: the set's radius, or (with `shrink`) less, so that no overlap ratio exceeds kFragmentBirthOverlap,
// but not below half the set's radius.
struct PlacedFragments {
  FragmentSet set;
  std::array<double, 4> birth_radius{};
  double deepest = 0;  // deepest overlap ratio of the chosen orientation at the set's radius
};
PlacedFragments place_fragments(const Eigen::Vector3d& x, double r, const std::vector<Eigen::Matrix3d>& orientations,
                                const std::vector<Obstacle>& obstacles, bool shrink);

// One sphere of a batch crushed together (ChamberDem::crush_squeezed): `turns` are the orientations to try (none: it
// leaves as fines), `obstacles` what it touches outside the batch, `crushed_neighbours` the batch indices of the
// spheres crushed with it that it overlaps.
struct CrushedSphere {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();
  double r = 0;
  std::vector<Eigen::Matrix3d> turns;
  std::vector<Obstacle> obstacles;
  std::vector<std::size_t> crushed_neighbours;
};
// Places the batch's fragments in batch order (place_fragments). Two overlapping spheres crushed together leave
// fragments that may overlap each other as deeply as those of one sphere and its neighbour, so each sphere's
// obstacles gain the fragments, at their birth radii, already placed for its crushed neighbours. Entry n of the
// result is left default (birth radii 0) where batch[n] has no turns.
std::vector<PlacedFragments> place_crushed_batch(std::vector<CrushedSphere>& batch, bool shrink);

// A mesh contact record of the last step whose particle is still at its index (removals make records stale).
bool contact_is_current(const dem::Particles& P, const dem::MeshContactRecord& c);

// F_c of a sphere of diameter d (N), size-independent strength.
double crushing_force(double d, double tensile_strength);

// Indices (ascending, unique) of the particles pressed against one of the meshes harder than their F_c
// (of their mass-equivalent size for rock density rho) in the meshes' last step (normal forces summed over
// the facets of a mesh the particle touches).
std::vector<std::size_t> crushed_particles(const dem::Particles& P, const std::vector<const dem::MeshContact*>& meshes,
                                           const CrushingStrength& strength, double rho);

// F_eq = max(von Mises(S), -tr(S) / 3) / (2 r) of S = (xx yy zz xy yz zx), the stress criterion's equivalent
// diametral load (N).
double equivalent_diametral_load(const double* s6, double r);

// The stress criterion: indices (ascending) of the particles with F_eq > F_c (of their mass-equivalent size), from
// World::contact_stress's sums `s` (6 per particle), to which the meshes' contacts of the last step are added.
std::vector<std::size_t> crushed_by_stress(const dem::Particles& P, std::vector<double>& s,
                                           const std::vector<const dem::MeshContact*>& meshes,
                                           const CrushingStrength& strength, double rho);

// A crushed sphere's mass split over the sieve classes of ascending `sieves` (m): entry k holds the mass between
// sieves[k-1] and sieves[k] (entry 0: below sieves[0]); the last entry (index sieves.size()) holds what is above
// the largest sieve. Sums to `mass`.
std::vector<double> progeny_by_class(double mass, double d, const std::vector<double>& sieves, double exponent);

}  // namespace coupling
