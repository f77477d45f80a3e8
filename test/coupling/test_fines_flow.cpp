// The coupled run's crushed fines carried by the chamber flow model (dem.fines: flow; chamber/flow_model.hpp): in the
// gyrating small chamber they stay in the chamber and load the liners, mass balances with them counted in the
// chamber, what leaves the flow model's bottom is screened as product; the config names the flow model's material
// and refuses the retired dem.fines_bed. The flow model's own laws are tested in test/chamber.
#include <gtest/gtest.h>

#include <cmath>
#include <chrono>
#include <cstdio>

#include "small_chamber.hpp"

namespace {

// The small chamber crushing its metaparticles, the fines in the flow model (or not): 150 coupling steps of 1 ms.
struct FinesRun {
  coupling::ProductState product;
  double mean_fines_force = 0, wall_s = 0;  // N over the run; s
  long dem_steps = 0;
};

FinesRun run_small_chamber(bool fines_flow) {
  auto p = test_chamber::prefilled_small_chamber(0.5, 0.5);
  p.crushing.enabled = true;
  p.crushing.tensile_strength = 0.5e6;
  p.fines_flow = fines_flow;
  p.fines = chamber::fines_only(chamber::FlowParams());
  p.fines.bands = 8;
  p.fines.sectors = 12;
  p.fines.material.loose_fraction = 0.1;  // loose enough that the few crushed grams fill the bottom's gap in 0.15 s
  coupling::ChamberDem dem(p);
  coupling::BodyMotion m, c;
  c.com = Eigen::Vector3d(0, 0, p.concave_com_z_m);
  FinesRun r;
  double sum = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int k = 0; k < 150; ++k) {
    test_chamber::gyrate(p, k * 1e-3, 3.0 * M_PI / 180, &m);
    dem.advance(m, c, 1e-3);
    sum += dem.fines_normal_force();
  }
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.dem_steps = std::lround(dem.time() / dem.dt());
  r.mean_fines_force = sum / 150;
  r.product = dem.product();
  if (fines_flow) {  // the flow model's own balance: what was deposited is held or left its bottom
    const auto* f = dem.fines();
    EXPECT_NEAR(f->fed_kg(), f->mass_kg() + f->discharged_kg(), 1e-12 * f->fed_kg());
    EXPECT_NEAR(f->fed_kg(), r.product.crushed_kg, 1e-12 * r.product.crushed_kg);
  }
  return r;
}

}  // namespace

TEST(FinesFlow, ChamberKeepsCrushedFinesInTheFlowModelAndBalancesItsMass) {
  const auto a = run_small_chamber(true), b = run_small_chamber(false);
  const auto &s = a.product, &s0 = b.product;
  std::printf("crushed %.4f kg (%ld); fines held %.4f kg, discharged %.4f kg (without them %.4f kg crushed, %.4f "
              "discharged); mean fines force %.1f N; wall %.3f s / %ld DEM steps = %.1f us per step (without %.1f)\n",
              s.crushed_kg, s.metaparticles_crushed, s.fines_bed_kg, s.discharged_kg, s0.crushed_kg, s0.discharged_kg,
              a.mean_fines_force, a.wall_s, a.dem_steps, 1e6 * a.wall_s / a.dem_steps, 1e6 * b.wall_s / b.dem_steps);
  ASSERT_GT(s.metaparticles_crushed, 0);
  EXPECT_NEAR(s.fed_kg, s.in_chamber_kg + s.discharged_kg + s.lost_kg, 1e-9 * s.fed_kg);
  EXPECT_NEAR(s0.fed_kg, s0.in_chamber_kg + s0.discharged_kg + s0.lost_kg, 1e-9 * s0.fed_kg);
  EXPECT_GT(s.fines_bed_kg, 0.0);
  EXPECT_LE(s.fines_bed_kg, s.crushed_kg + 1e-15);
  EXPECT_EQ(s0.fines_bed_kg, 0.0);
  EXPECT_GE(s0.discharged_kg, s0.crushed_kg - 1e-15);  // without them the fines are discharged at once
  EXPECT_GT(a.mean_fines_force, 0.0);
  EXPECT_EQ(b.mean_fines_force, 0.0);
  EXPECT_NEAR(s.passing_pct.back(), s.discharged_kg > 0 ? 100.0 : 0.0, 1e-9);  // screening sums to the discharge
}

// The quick demo ships dem.fines: flow with the flow: section's material (as the fast mode reads it), as fines only;
// a bad flow material is named by its key; flow without crushing, and the retired dem.fines_bed, are refused naming
// what to do.
TEST(FinesFlow, ConfigReadsTheFlowModelAndNamesWhatIsWrong) {
  const std::string demo = test_chamber::quick_demo_text();
  const auto p = test_chamber::chamber_params_of(demo);
  ASSERT_TRUE(p.fines_flow);  // as shipped
  EXPECT_FALSE(p.fines.prefill);
  EXPECT_FALSE(p.fines.choke_feed);
  EXPECT_DOUBLE_EQ(p.fines.material.modulus_Pa, 5.12556e6);  // quick_demo.yaml's flow.material
  EXPECT_DOUBLE_EQ(p.fines.material.loose_fraction, 0.4564);
  EXPECT_EQ(p.fines.bands, 30);
  EXPECT_EQ(p.fines.sectors, 16);
  auto replaced = [&](const std::string& what, const std::string& with) {
    std::string text = demo;
    const auto at = text.find(what);
    if (at == std::string::npos) throw std::logic_error("quick_demo.yaml has no '" + what + "'");
    return text.replace(at, what.size(), with);
  };
  EXPECT_FALSE(test_chamber::chamber_params_of(replaced("  fines: flow ", "  fines: discharge ")).fines_flow);
  auto error_of = [](const std::string& text) {
    try {
      test_chamber::chamber_params_of(text);
    } catch (const core::ConfigError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const std::string e1 = error_of(replaced("loose_solid_fraction: 0.4564", "loose_solid_fraction: 1.5"));
  EXPECT_NE(e1.find("flow.material.loose_solid_fraction"), std::string::npos) << e1;
  const std::string e2 = error_of(replaced("  fines: flow ", "  fines: bed "));
  EXPECT_NE(e2.find("dem.fines"), std::string::npos) << e2;
  EXPECT_NE(e2.find("discharge"), std::string::npos) << e2;
  std::string no_crushing = demo;
  no_crushing.replace(no_crushing.find("enabled: true", no_crushing.find("  crushing:")), 13, "enabled: false");
  const std::string e3 = error_of(no_crushing);
  EXPECT_NE(e3.find("dem.fines"), std::string::npos) << e3;
  EXPECT_NE(e3.find("crushing"), std::string::npos) << e3;
  // No flow material to take the fines' from.
  std::string no_flow = demo;
  no_flow.replace(no_flow.find("flow:    "), 4, "flox");
  const std::string e5 = error_of(no_flow);
  EXPECT_NE(e5.find("flow.material"), std::string::npos) << e5;
  // A config of the retired fines bed: what replaced it.
  const std::string e4 = error_of(replaced("  fines: flow ", "  fines_bed: {enabled: true, max_strain: 0.35}  #"));
  EXPECT_NE(e4.find("dem.fines_bed"), std::string::npos) << e4;
  EXPECT_NE(e4.find("replaced by dem.fines: flow"), std::string::npos) << e4;
}
