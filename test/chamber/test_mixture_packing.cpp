// The loose packing of a size mixture (chamber/mixture_packing.hpp, de Larrard's compressible packing model) and the
// flow model's cells packed by their own mixture: against the model's closed forms (one size; two sizes, where the
// packing equation is a quadratic; Furnas' densest binary at sizes far apart), the reference bed's round trip, and a
// resume bit for bit.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../common/coaxial_liners.hpp"
#include "../common/flow_params.hpp"
#include "chamber/flow_model.hpp"
#include "chamber/mixture_packing.hpp"

namespace {

using chamber::MixturePacking;

// The root x = 1 / Phi > max(c1, c2) of K = w1 / (x - c1) + w2 / (x - c2): the larger root of a quadratic.
double binary_packing(double c1, double c2, double w1, double w2, double K) {
  const double b = K * (c1 + c2) + w1 + w2, c = K * c1 * c2 + w1 * c2 + w2 * c1;
  return 2 * K / (b + std::sqrt(b * b - 4 * K * c));
}

}  // namespace

// One size packs to beta K / (1 + K), whatever the size, for any beta and K.
TEST(MixturePacking, OneSizePacksToBetaKOverOnePlusK) {
  for (double beta : {0.5, 0.64, 0.74})
    for (double K : {4.1, 9.0}) {
      const MixturePacking mp({0.002, 0.010, 0.030}, beta, K);
      for (int i = 0; i < 3; ++i) {
        double kg[3] = {0, 0, 0};
        kg[i] = 2.5;
        EXPECT_NEAR(mp.fraction(kg), beta * K / (1 + K), 1e-12) << beta << " " << K << " " << i;
      }
    }
}

// Two sizes d2 = r d1: the virtual packings gamma_1 = beta / (1 - (1 - a) y2) (the coarse dominant, loosened by the
// fine, a = sqrt(1 - (1 - r)^1.02)) and gamma_2 = beta / (1 - (1 - beta)(1 - b) y1) (the fine dominant, the coarse
// grains' wall effect, b = 1 - (1 - r)^1.5), and the packing the quadratic's root; from any guess.
TEST(MixturePacking, TwoSizesPackAsTheQuadraticOfTheModelSays) {
  const double beta = 0.58, K = 4.1;
  for (double r : {0.9, 0.5, 0.2, 0.05}) {
    const MixturePacking mp({0.02, 0.02 * r}, beta, K);
    const double a = std::sqrt(1 - std::pow(1 - r, 1.02)), b = 1 - std::pow(1 - r, 1.5);
    for (double y1 : {0.1, 0.5, 0.7, 0.95}) {
      const double y2 = 1 - y1;
      const double g1 = beta / (1 - (1 - a) * y2), g2 = beta / (1 - (1 - beta) * (1 - b) * y1);
      const double want = binary_packing(1 / g1, 1 / g2, y1 / beta, y2 / beta, K);
      const double kg[2] = {3 * y1, 3 * y2};
      for (double guess : {0.0, 0.3, want, 0.99})
        EXPECT_NEAR(mp.fraction(kg, guess), want, 1e-12) << r << " " << y1 << " " << guess;
    }
  }
  // the finer the fine grains, the denser the mixture (70 % coarse)
  const double kg[2] = {0.7, 0.3};
  double last = 0;
  for (double r : {0.9, 0.5, 0.2, 0.05}) {
    const double phi = MixturePacking({0.02, 0.02 * r}, beta, K).fraction(kg);
    EXPECT_GT(phi, last + 0.005) << r;
    last = phi;
  }
}

// Sizes far apart and a compaction index far beyond a pour's: the densest binary is Furnas', 1 - (1 - beta)^2 at the
// coarse share 1 / (2 - beta) (the fine grains just fill the coarse grains' voids).
TEST(MixturePacking, FarApartSizesPackToFurnasDensestBinary) {
  const double beta = 0.6;
  const MixturePacking mp({0.05, 0.05e-12}, beta, 1e7);  // (a ~ sqrt(1.02 r): 1e-6)
  const double y1 = 1 / (2 - beta), kg[2] = {y1, 1 - y1};
  EXPECT_NEAR(mp.fraction(kg), 1 - (1 - beta) * (1 - beta), 1e-4);
  const double coarse_heavy[2] = {0.9, 0.1}, fine_heavy[2] = {0.4, 0.6};
  EXPECT_LT(mp.fraction(coarse_heavy), 1 - (1 - beta) * (1 - beta) - 0.05);
  EXPECT_LT(mp.fraction(fine_heavy), 1 - (1 - beta) * (1 - beta) - 0.05);
}

// beta_for finds the beta at which a reference bed packs as measured (the piston die's 28-40 mm rocks at 0.468), and
// even_size_mixture spreads the reference sizes over the classes by their share of the interval.
TEST(MixturePacking, TheReferenceBedPacksAsMeasured) {
  const std::vector<double> lower = {0, 0.001, 0.0224, 0.0315}, upper = {0.001, 0.0224, 0.0315, 0.040};
  const std::vector<double> ref = chamber::even_size_mixture(lower, upper, 0.028, 0.040);
  ASSERT_EQ(ref.size(), 4u);
  EXPECT_NEAR(ref[2], 3.5 / 12, 1e-12);
  EXPECT_NEAR(ref[3], 8.5 / 12, 1e-12);
  EXPECT_EQ(ref[0] + ref[1], 0.0);
  const std::vector<double> sizes = {0.0005, 0.0047, 0.0266, 0.0355};
  const double beta = MixturePacking::beta_for(sizes, 4.1, ref, 0.468);
  EXPECT_NEAR(MixturePacking(sizes, beta, 4.1).fraction(ref.data()), 0.468, 1e-12);
  EXPECT_LT(beta, 0.468 * (1 + 1 / 4.1));  // two sizes pack denser than one: the same packing asks a lower beta
  EXPECT_GT(beta, 0.468 * (1 + 1 / 4.1) - 0.05);
  // refused by name
  auto says = [](auto f, const std::string& what) {
    try {
      f();
      ADD_FAILURE() << "accepted: " << what;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  says([&] { MixturePacking({0.01}, 1.2, 4.1); }, "beta");
  says([&] { MixturePacking({0.01}, 0.6, 0); }, "compaction index");
  says([&] { MixturePacking({0.01, -1}, 0.6, 4.1); }, "class sizes");
  says([&] { const double none[1] = {0}; MixturePacking({0.01}, 0.6, 4.1).fraction(none); }, "needs mass");
  says([&] { chamber::even_size_mixture(lower, upper, 0.04, 0.028); }, "reference sizes");
}

// The flow model with the mixture's packing: a chamber wider than the feed fills its top band with the choke feed to the
// feed's own loose packing (denser than the die's rocks: its fine part fills their voids), its compaction limit the
// solid's; the reference bed's sizes alone would pack to the material's loose fraction.
TEST(MixturePacking, TheFlowModelFillsEachCellToItsMixturesLoosePacking) {
  auto p = test_liners::flow_params(12, 4);
  p.choke_feed = true;
  p.material.loose_fraction = 0.468;
  p.material.max_compression = 0.532;
  p.material.packing_index = 4.1;
  chamber::FlowModel m(p, test_liners::cylinder(0.3), test_liners::cylinder(0.38, -0.8, -0.2));
  const auto& br = m.breakage();
  std::vector<double> sizes, lower, upper, feed;
  for (std::size_t j = 0; j < m.classes(); ++j) sizes.push_back(br.size(j)), lower.push_back(br.lower(j)), upper.push_back(br.upper(j));
  const auto ref = chamber::even_size_mixture(lower, upper, 0.028, 0.040);
  const MixturePacking mp(sizes, MixturePacking::beta_for(sizes, 4.1, ref, 0.468), 4.1);
  for (std::size_t j = 0; j < m.classes(); ++j)
    feed.push_back((j < p.feed_passing.size() ? p.feed_passing[j] : 1.0) - (j > 0 ? p.feed_passing[j - 1] : 0.0));
  const double phi_feed = mp.fraction(feed.data());
  EXPECT_GT(phi_feed, 0.468 + 0.02);
  for (int i = 0; i < 3000; ++i) m.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), {0, 0, -0.5},
                                        {0, 0, -0.6}, 2e-4, 9.81);
  ASSERT_GT(m.discharged_kg(), 1.0);
  const std::size_t top = m.cells() - 1;
  EXPECT_NEAR(m.cell_loose_density(top), phi_feed * p.material.solid_density, 1e-9 * m.cell_loose_density(top));
  EXPECT_NEAR(m.cell_compaction_limit(top), 1 - phi_feed, 1e-9);
  EXPECT_NEAR(m.cell_mass(top), m.cell_area(top) * m.cell_gap(top) * phi_feed * p.material.solid_density,
              1e-9 * m.cell_mass(top));
  // without the law the same cell holds the reference bed's loose mass
  p.material.packing_index = 0;
  chamber::FlowModel one(p, test_liners::cylinder(0.3), test_liners::cylinder(0.38, -0.8, -0.2));
  for (int i = 0; i < 3000; ++i) one.step(Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), {0, 0, -0.5},
                                          {0, 0, -0.6}, 2e-4, 9.81);
  EXPECT_NEAR(one.cell_mass(top), one.cell_area(top) * one.cell_gap(top) * 0.468 * p.material.solid_density,
              1e-9 * one.cell_mass(top));
}

// A gyrating mantle over the cone chamber with the mixture's packing: mass balance to round-off, a resumed copy bit for
// bit, the law in the fingerprint; refused with the laws it is not written for.
TEST(MixturePacking, TheFlowModelWithItBalancesItsMassAndResumesBitForBit) {
  const core::Profile mantle = test_liners::gyp_mantle(), concave = test_liners::gyp_concave();
  chamber::FlowParams p = test_liners::cone_chamber_params();
  p.material.packing_index = 4.1;
  chamber::FlowModel m(p, mantle, concave);
  test_liners::nutate({&m}, 0, 1500);
  const auto resumed = test_liners::resumed(m, p, mantle, concave);
  test_liners::nutate({&m, resumed.get()}, 1500, 3000);
  EXPECT_GT(m.events(), 100);
  EXPECT_EQ(m.crushing_energy_J(), resumed->crushing_energy_J());
  EXPECT_EQ(m.discharged_by_class(), resumed->discharged_by_class());
  EXPECT_EQ(m.mass_kg(), resumed->mass_kg());
  EXPECT_NEAR(m.fed_kg(), m.mass_kg() + m.discharged_kg(), 1e-9 * m.fed_kg());
  double denser = 0;  // the broken rock's cells pack denser than the die's bed
  for (std::size_t k = 0; k < m.cells(); ++k)
    if (m.cell_mass(k) > 0) denser = std::max(denser, m.cell_loose_density(k) / m.loose_density());
  EXPECT_GT(denser, 1.05);
  EXPECT_EQ(chamber::law_fingerprint(p.material), (std::vector<double>{-7.0, 4.1, 0.028, 0.040}));
  auto refused = [&](chamber::FlowParams bad) {
    try {
      chamber::FlowModel no(bad, mantle, concave);
      ADD_FAILURE() << "accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("packing."), std::string::npos) << e.what();
    }
  };
  auto bad = p;
  bad.compaction_memory = true;
  refused(bad);
  bad = p;
  bad.material.packing_index = -1;
  refused(bad);
  bad = p;
  bad.material.packing_ref_max_m = 0.01;
  refused(bad);
}
