// Point-set analysis (vrpd/analysis.h) on sets with known spectra and spacings: white noise, a
// square lattice, a hexagonal lattice, and maximal Poisson-disk sets from the sampler; the
// device's periodogram against the host's.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "support.h"
#include "vrpd/analysis.h"

using namespace vrpd;

namespace {

std::vector<glm::dvec2> uniform_random(std::size_t n, std::uint32_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<glm::dvec2> p(n);
    for (auto& q : p) q = {u(rng), u(rng)};
    return p;
}

SpectrumOptions host(int half_width) {
    SpectrumOptions o;
    o.half_width = half_width;
    o.backend = Backend::Cpu;
    return o;
}

std::vector<std::vector<glm::dvec2>> mps_sets(double r, int count) {
    std::vector<std::vector<glm::dvec2>> sets;
    for (int s = 1; s <= count; ++s) {
        const Sampling m = sample(test::options(r, std::uint32_t(s), Backend::Cpu));
        std::vector<glm::dvec2> pts(m.size());
        for (std::size_t i = 0; i < m.size(); ++i) pts[i] = m.point(i);
        sets.push_back(pts);
    }
    return sets;
}

}  // namespace

// White noise: every P(k) is exponential with mean 1. Bands of 8 annuli hold at least 1 600
// values over 4 sets (standard error at most 0.025), so [0.9, 1.1] is 4 standard errors wide.
TEST_CASE("uniform random points: radial power is 1 within 0.1 in every band of 8 frequencies", "[analysis]") {
    std::vector<std::vector<glm::dvec2>> sets;
    for (std::uint32_t s = 0; s < 4; ++s) sets.push_back(uniform_random(1000, s));
    const RadialPower r = radial_power(periodogram(sets, Box{}, host(64)));
    REQUIRE(r.power.size() == 64);
    for (std::size_t band = 8; band + 8 <= r.power.size(); band += 8) {
        double mean = 0;
        for (std::size_t f = band; f < band + 8; ++f) mean += r.power[f] / 8;
        INFO("frequencies " << band + 1 << ".." << band + 8);
        CHECK(mean == Approx(1.0).margin(0.1));
    }
    // One set of white noise has anisotropy near 10 log10(1) = 0 dB (an exponential's variance is
    // its squared mean); 4 sets average it down by 10 log10(4) = 6 dB.
    CHECK(r.anisotropy_db[40] == Approx(-6.0).margin(1.5));
}

// A 16 x 16 lattice: the sum over it vanishes except at multiples of 16, where every phase is a
// whole turn and P = n. The fixed-point phases are exact here, so "zero" is rounding only.
TEST_CASE("square lattice: power n at the lattice frequencies and zero elsewhere", "[analysis]") {
    std::vector<glm::dvec2> grid;
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 16; ++x) grid.push_back({(x + 0.25) / 16, (y + 0.5) / 16});
    const Spectrum s = periodogram({grid}, Box{}, host(40));
    for (int ky = -40; ky <= 40; ++ky)
        for (int kx = -40; kx <= 40; ++kx) {
            INFO("k = (" << kx << ", " << ky << ")");
            if (kx == 0 && ky == 0)
                CHECK(s.at(kx, ky) == 0);
            else if (kx % 16 == 0 && ky % 16 == 0)
                CHECK(s.at(kx, ky) == Approx(256).epsilon(1e-12));
            else
                CHECK(s.at(kx, ky) < 1e-20);
        }
}

// Maximal Poisson-disk sampling at r = 0.02 (about 1 660 points, sqrt(n) about 41): the dark
// disc below 0.25 sqrt(n), a first peak above 1, and a normalised minimum distance near 0.777.
TEST_CASE("maximal Poisson-disk sets: dark low frequencies, a peak above 1, delta_x >= 0.75", "[analysis]") {
    const auto sets = mps_sets(0.02, 4);
    const Spectrum s = periodogram(sets, Box{}, host(96));
    const RadialPower r = radial_power(s);
    const double root_n = std::sqrt(s.mean_points);
    double peak = 0;
    for (std::size_t i = 0; i < r.power.size(); ++i) {
        if (r.frequency[i] < 0.25 * root_n) {
            INFO("frequency " << r.frequency[i]);
            CHECK(r.power[i] <= 0.15);
        }
        peak = std::max(peak, r.power[i]);
    }
    CHECK(peak > 1.0);
    for (const auto& set : sets) {
        const Spacing sp = spacing(set, Box{});
        CHECK(sp.delta_x >= 0.75);
        CHECK(sp.mean_min_distance > sp.delta_x);
        CHECK(sp.mean_min_distance < 1.0);
    }
}

// On the hexagonal lattice every nearest neighbour is at the packing spacing: delta_x = 1.
TEST_CASE("hexagonal lattice: delta_x and the mean minimum distance are 1", "[analysis]") {
    const int cols = 12, rows = 14;  // rows even, so the torus closes
    const Box box{double(cols), rows * std::sqrt(3.0) / 2, Boundary::Periodic};
    std::vector<glm::dvec2> hex;
    for (int y = 0; y < rows; ++y)
        for (int x = 0; x < cols; ++x) hex.push_back({x + 0.5 * (y % 2) + 0.1, y * std::sqrt(3.0) / 2 + 0.1});
    const Spacing s = spacing(hex, box);
    CHECK(s.d_max == Approx(1.0).epsilon(1e-12));
    CHECK(s.delta_x == Approx(1.0).epsilon(1e-12));
    CHECK(s.mean_min_distance == Approx(1.0).epsilon(1e-12));
    // A free box loses the wrap-around: the corner point's neighbours are still 1 away.
    CHECK(spacing(hex, Box{box.width, box.height, Boundary::Free}).delta_x == Approx(1.0).epsilon(1e-12));
}

TEST_CASE("spacing and spectrum refuse what they cannot measure", "[analysis]") {
    CHECK_THROWS_WITH(spacing({{0.5, 0.5}}, Box{}), Catch::Contains("at least 2 points"));
    CHECK_THROWS_WITH(periodogram({}, Box{}, host(8)), Catch::Contains("no point set"));
    CHECK_THROWS_WITH(periodogram({{}}, Box{}, host(8)), Catch::Contains("set 1 has no points"));
    CHECK_THROWS_WITH(periodogram({{{0.5, 1.5}}}, Box{}, host(8)), Catch::Contains("outside the box"));
    CHECK_THROWS_WITH(periodogram({{{0.5, 0.5}}}, Box{}, host(0)), Catch::Contains("must reach 1 to 1024"));
    CHECK_THROWS_WITH(periodogram({{{0.5, 0.5}}}, Box{}, host(1025)), Catch::Contains("must reach 1 to 1024"));
}

// The kernel sums in float with an exact phase and its own sine and cosine; the host in double.
// Stated tolerance: 1e-4 of max(P, 1), the white-noise level (near-zero powers have no relative
// accuracy to speak of in float).
TEST_CASE("the device's periodogram equals the host's within 1e-4", "[analysis][gpu]") {
    const auto sets = mps_sets(0.02, 2);
    SpectrumOptions gpu = host(96);
    gpu.backend = Backend::Gpu;
    const Spectrum d = periodogram(sets, Box{}, gpu);
    const Spectrum h = periodogram(sets, Box{}, host(96));
    REQUIRE(d.backend == Backend::Gpu);
    REQUIRE(d.power.size() == h.power.size());
    double worst = 0;
    for (std::size_t i = 0; i < h.power.size(); ++i)
        worst = std::max(worst, std::abs(d.power[i] - h.power[i]) / std::max(h.power[i], 1.0));
    INFO("largest difference " << worst);
    CHECK(worst <= 1e-4);
    CHECK(worst > 0);  // the two really are different computations
}
