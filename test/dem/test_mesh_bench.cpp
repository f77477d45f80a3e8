// Throughput of particle-mesh contact (not a timed test: DISABLED_, run by hand with
//   test_dem --gtest_also_run_disabled_tests --gtest_filter='*MeshBench*'
// ). A concave liner of 10^4 triangles, 10^5 particles filling the chamber next to it.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <random>

#include "dem/mesh_contact.hpp"
#include "dem/revolution.hpp"

namespace {

TEST(MeshBench, DISABLED_ConcaveTenThousandTrianglesHundredThousandParticles) {
  std::vector<dem::ProfilePoint> prof;
  for (int i = 0; i <= 50; ++i) {
    const double z = 0.65 * i / 50;
    prof.push_back({z, 0.45 + 0.4 * z});
  }
  const auto concave = dem::revolve_profile(prof, 100, dem::NormalSide::Inward, 0.0, "concave");
  const auto mats = dem::default_table4();
  dem::MeshContact mc(concave, mats, 1);
  mc.set_regions(dem::RegionMap::rings_sectors(concave, 13, 9));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Particles in a 10 cm thick shell inside the concave (the chamber), r = 4..8 mm.
  struct P { double z, phi, rr, rad, vx, vy; };
  std::vector<P> pts;
  while (pts.size() < 100000) {
    const double z = 0.01 + 0.63 * u(rng), phi = 2 * M_PI * u(rng);
    const double rs = 0.45 + 0.4 * z, rad = 0.004 + 0.004 * u(rng);
    const double depth = rad * 0.98 + 0.10 * u(rng) * u(rng) * u(rng);  // crowded near the wall
    pts.push_back({z, phi, rs * std::cos(M_PI / 100) - depth, rad, u(rng) - 0.5, u(rng) - 0.5});
  }
  const int maxt = omp_get_max_threads();
  for (int sorted : {0, 1}) {
  if (sorted)  // storage order following space (2 cm bands in z, then azimuth), as a sorted DEM keeps it
    std::sort(pts.begin(), pts.end(), [](const P& a, const P& b) {
      const int za = static_cast<int>(a.z / 0.02), zb = static_cast<int>(b.z / 0.02);
      return za != zb ? za < zb : a.phi < b.phi;
    });
  dem::Particles p;
  for (const auto& q : pts)
    p.add(q.rr * std::cos(q.phi), q.rr * std::sin(q.phi), q.z, q.rad, 2600.0, 0, q.vx, q.vy, 0);
  for (int threads : {1, maxt}) {
    mc.set_threads(threads);
    mc.add_forces(p, 0.0, 1e-6);  // grid build, warm-up
    const int reps = 20;
    const auto t0 = std::chrono::steady_clock::now();
    const std::clock_t c0 = std::clock();
    for (int k = 0; k < reps; ++k) mc.add_forces(p, 0.0, 1e-6);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / reps;
    const double cpu = double(std::clock() - c0) / CLOCKS_PER_SEC / reps;
    std::printf("cpu_ms_per_step %.3f ", 1e3 * cpu);
    std::printf("%s ", sorted ? "space_ordered" : "random_order");
    std::printf("mesh_contact cell_m %.4f triangles %zu particles %zu contacts %zu threads %d grid_cells %ld "
                "entries %zu ms_per_step %.3f particle_steps_per_s %.3g\n",
                mc.grid().cell_size(), concave.num_triangles(), p.size(), mc.contacts().size(), threads, mc.grid().num_cells(),
                mc.grid().num_entries(), 1e3 * s, p.size() / s);
    EXPECT_GT(mc.contacts().size(), 1000u);
  }
  }
}

}  // namespace
