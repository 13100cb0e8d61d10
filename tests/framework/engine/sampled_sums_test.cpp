// The parts of the sampled moments that SDK 6.6 added, measured by the host (CellGrid, engine/
// sampled_sums.cpp): the sums in every sampling bin are the sums of the particles in it, however
// the bins cut the layers (each layer sums its particles in its few bins, the layers' sums are
// added in layer order), and each cell's fresh moments are its particles' (000 Eqs. 4.4-4.6). That
// a decomposed run gets the same bits is tests/framework/study/mpi_slab_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <gdsmc/physics/bins.hpp>

#include "engine/cells.hpp"
#include "engine/streams.hpp"

namespace {

using namespace gdsmc;

struct State {
  std::vector<double> y, vx, vy, vz;
  std::vector<std::uint32_t> cell;
  ParticleSpan span;
  SystemInfo sys;
  host::CellGrid grid;
  State(std::size_t n, std::size_t layers, std::size_t bins) : y(n), vx(n), vy(n), vz(n), cell(n) {
    Rng rng = host::StreamFactory::standalone(3, 0);
    sys.geometry = Geometry::slab;
    sys.box[0] = 2.0, sys.box[1] = 1.0, sys.box[2] = 3.0;
    sys.cells = layers;
    sys.bins = bins;
    for (std::size_t i = 0; i < n; ++i) {
      y[i] = sys.box[1] * (rng.uniform() - 0.5);
      vx[i] = 0.4 * y[i] + rng.normal();  // a shear flow: the layers' means differ
      vy[i] = 1.3 * rng.normal();
      vz[i] = rng.normal();
    }
    y[0] = -0.5 * sys.box[1], y[1] = 0.5 * sys.box[1];  // on the walls
    y[2] = sys.layer_lower(layers / 2);                 // on a layer's edge
    span.count = n;
    span.y = y.data();
    span.vx = vx.data(), span.vy = vy.data(), span.vz = vz.data();
    span.cell = cell.data();
    grid.slab(n, layers, sys.box[1], sys.cross_section());
    grid.set_sampling_system(&sys);
    grid.assign_and_sort(y.data(), cell.data(), n);
  }
};

// 7 bins over 10 layers: most bins straddle two layers; with 1 and 3 bins most layers lie inside one
// bin (summed without reading positions); 10 and 33 bins put a bin edge on every layer edge or
// several bins in a layer. Each bin's count is exact and each sum is the particles' sum to
// round-off (another order of the same additions), third moments included.
TEST(SampledSums, TheBinSumsAreTheSumsOfTheParticlesInEachBinHoweverTheBinsCutTheLayers) {
  for (const std::size_t bins : {1u, 3u, 7u, 10u, 33u}) {
    State s(20000, 10, bins);
    SampledMoments m;
    s.grid.sampled_moments(s.span, 1e-3, m, nullptr, nullptr, moments_bin_heat);
    ASSERT_NE(m.bin_sums, nullptr);
    ASSERT_EQ(m.bin_count, bins);
    ASSERT_EQ(m.bin_sum_stride, static_cast<std::size_t>(BinSums::kSums));
    BinSums direct, hosts;
    direct.begin(bins, true);
    hosts.begin(bins, true);
    direct.add_sample(s.sys, s.span);
    hosts.append_sample(m);
    EXPECT_EQ(hosts.samples(), 1.0);
    double total = 0;
    for (std::size_t b = 0; b < bins; ++b) {
      const double *d = direct.sums(b), *h = hosts.sums(b);
      EXPECT_EQ(h[BinSums::kCount], d[BinSums::kCount]) << "bin " << b;
      total += h[BinSums::kCount];
      // Two orders of the same N additions differ by at most ~N eps max|term| (|v|^3 < 10^3 here):
      // 1e-10 N; one particle in the wrong bin would move a sum by its own term, ~1.
      for (std::size_t j = 1; j < BinSums::kSums; ++j)
        EXPECT_NEAR(h[j], d[j], 1e-10 * d[BinSums::kCount]) << "bin " << b << " sum " << j;
    }
    EXPECT_EQ(total, 20000.0);
  }
}

// Asked for second moments only, the host's sums have no third; a diagnostic sized for third
// moments is refused naming the part to declare, and one sized for other bins too.
TEST(SampledSums, AnAccumulatorThatDoesNotFitTheHostsBinSumsIsRefusedNamingWhatToDeclare) {
  State s(1000, 4, 5);
  SampledMoments second, none;
  s.grid.sampled_moments(s.span, 1e-3, second, nullptr, nullptr, moments_bins);
  s.grid.sampled_moments(s.span, 1e-3, none, nullptr, nullptr, moments_energy);
  EXPECT_EQ(second.bin_sum_stride, static_cast<std::size_t>(BinSums::kSecond));
  EXPECT_EQ(none.bin_sums, nullptr);
  BinSums third, fits, other;
  third.begin(5, true);
  fits.begin(5, false);
  other.begin(4, false);
  EXPECT_NO_THROW(fits.append_sample(second));
  try {
    third.append_sample(second);
    ADD_FAILURE() << "third moments from second-moment sums";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("moments_bin_heat"), std::string::npos) << e.what();
  }
  try {
    fits.append_sample(none);
    ADD_FAILURE() << "no bin sums measured";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("declare moments_bins"), std::string::npos) << e.what();
  }
  EXPECT_THROW(other.append_sample(second), std::invalid_argument);
}

// Each cell's fresh moments: N_I exact, u_I the cell mean the peculiar moments subtract (the same
// bits), T_I = sum |v - u_I|^2 / 3 N_I to round-off; their count-weighted mean is T-bar (Eq. 4.8).
TEST(SampledSums, EachCellsFreshMomentsAreItsParticles) {
  State s(20000, 10, 10);
  SampledMoments m;
  s.grid.sampled_moments(s.span, 1e-3, m, nullptr, nullptr, moments_cells | moments_means);
  ASSERT_NE(m.cells, nullptr);
  ASSERT_NE(m.cell_mean_velocity, nullptr);
  double weighted = 0;
  for (std::size_t c = 0; c < 10; ++c) {
    const CellMoments& cm = m.cells[c];
    ASSERT_EQ(cm.count, s.grid.members_count(c));
    double u[3] = {0, 0, 0};
    for (std::size_t i = 0; i < s.span.count; ++i)
      if (s.cell[i] == c) u[0] += s.vx[i], u[1] += s.vy[i], u[2] += s.vz[i];
    double c2 = 0;
    for (int a = 0; a < 3; ++a) u[a] /= static_cast<double>(cm.count);
    for (std::size_t i = 0; i < s.span.count; ++i)
      if (s.cell[i] == c)
        c2 += (s.vx[i] - u[0]) * (s.vx[i] - u[0]) + (s.vy[i] - u[1]) * (s.vy[i] - u[1]) + (s.vz[i] - u[2]) * (s.vz[i] - u[2]);
    for (int a = 0; a < 3; ++a) {
      EXPECT_EQ(cm.mean_velocity[a], m.cell_mean_velocity[3 * c + a]);
      EXPECT_NEAR(cm.mean_velocity[a], u[a], 1e-13);
    }
    EXPECT_NEAR(cm.temperature, c2 / (3.0 * static_cast<double>(cm.count)), 1e-13);
    EXPECT_DOUBLE_EQ(cm.number_density, static_cast<double>(cm.count) / s.grid.cell_volume(c));
    weighted += static_cast<double>(cm.count) * cm.temperature;
  }
  SampledMoments all;
  s.grid.sampled_moments(s.span, 1e-3, all, nullptr, nullptr, moments_all);
  EXPECT_NEAR(weighted / 20000.0, all.local.temperature, 1e-13);
  EXPECT_EQ(all.cells, nullptr);  // not asked for
}

}  // namespace
