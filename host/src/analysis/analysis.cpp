// Point-set analysis (vrpd/analysis.h): the periodogram on the host or a device, its radial
// mean, and the spacing measures.
#include "vrpd/analysis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include <fmt/format.h>

#include "cpu/thread_pool.h"
#include "shared/spectrum.h"
#include "vulkan/spectrum_kernel.h"

namespace vrpd {
namespace {

constexpr int kMaxHalfWidth = 1024;     // the kernel's dispatch stays within 65 535 workgroups
constexpr std::size_t kPointBlock = 1024;  // points whose phase tables the host holds at once
// A point's phase tables take about 3 half_width turns, a row of S a block of points' sums: both
// go to the threads from a few items (the pool's default grain suits loops of a few instructions).
constexpr std::size_t kPointGrain = 16, kRowGrain = 2;

using shared::uvec2;

// Each coordinate as a 32-bit fraction of its side: the phases are then exact integers.
std::vector<uvec2> fixed_point(const std::vector<glm::dvec2>& points, const Box& box) {
    std::vector<uvec2> out(points.size());
    auto fraction = [](double v, double side) {
        return std::uint32_t(std::min(std::floor(v / side * 4294967296.0), 4294967295.0));
    };
    for (std::size_t i = 0; i < points.size(); ++i)
        out[i] = {fraction(points[i].x, box.width), fraction(points[i].y, box.height)};
    return out;
}

// cos and sin of 2 pi phase / 2^32, in double.
void turn(std::uint32_t phase, double& c, double& s) {
    const double angle = double(phase) * (2.0 * std::numbers::pi / 4294967296.0);
    c = std::cos(angle);
    s = std::sin(angle);
}

// s += x c over n complex values (split into real and imaginary arrays): the periodogram's inner
// loop, built for AVX2 too where the processor has it (the same sums: no fused multiply-adds).
__attribute__((target_clones("avx2", "default"))) void multiply_add(double* __restrict sr, double* __restrict si,
                                                                      const double* __restrict xr,
                                                                      const double* __restrict xi, double cr,
                                                                      double ci, std::size_t n) {
    for (std::size_t k = 0; k < n; ++k) {
        sr[k] += xr[k] * cr - xi[k] * ci;
        si[k] += xr[k] * ci + xi[k] * cr;
    }
}

// One set's P at the half plane's frequencies, added to `sum`: S(kx, ky) = sum_j a_j(kx) b_j(ky)
// with a_j(kx) = exp(2 pi i kx x_j) and b_j(ky) = exp(2 pi i ky y_j), a block of points at a
// time, each thread summing whole rows ky.
void host_periodogram(const std::vector<uvec2>& pts, int half_width, detail::ThreadPool& pool,
                      std::vector<double>& sum) {
    const std::size_t w = std::size_t(2 * half_width + 1), rows = std::size_t(half_width + 1);
    std::vector<double> re(rows * w, 0.0), im(rows * w, 0.0);  // S at ky = 0..half, kx = -half..half
    std::vector<double> ar(kPointBlock * w), ai(kPointBlock * w), br(kPointBlock * rows), bi(kPointBlock * rows);
    for (std::size_t first = 0; first < pts.size(); first += kPointBlock) {
        const std::size_t block = std::min(kPointBlock, pts.size() - first);
        pool.parallel_for(
            block,
            [&](std::size_t begin, std::size_t end, unsigned) {
                for (std::size_t j = begin; j < end; ++j) {
                    const uvec2 u = pts[first + j];
                    for (int k = -half_width; k <= half_width; ++k)
                        turn(std::uint32_t(k) * u.x, ar[j * w + std::size_t(k + half_width)],
                             ai[j * w + std::size_t(k + half_width)]);
                    for (int k = 0; k <= half_width; ++k)
                        turn(std::uint32_t(k) * u.y, br[j * rows + std::size_t(k)], bi[j * rows + std::size_t(k)]);
                }
            },
            kPointGrain);
        pool.parallel_for(
            rows,
            [&](std::size_t begin, std::size_t end, unsigned) {
                for (std::size_t ky = begin; ky < end; ++ky)
                    for (std::size_t j = 0; j < block; ++j)
                        multiply_add(&re[ky * w], &im[ky * w], &ar[j * w], &ai[j * w], br[j * rows + ky],
                                     bi[j * rows + ky], w);
            },
            kRowGrain);
    }
    // The half plane in shared/spectrum.h's order: row ky = 0 from kx = 1, then whole rows.
    const double n = double(pts.size());
    std::size_t f = 0;
    for (std::size_t ky = 0; ky < rows; ++ky)
        for (std::size_t kx = ky == 0 ? std::size_t(half_width) + 1 : 0; kx < w; ++kx, ++f)
            sum[f] += (re[ky * w + kx] * re[ky * w + kx] + im[ky * w + kx] * im[ky * w + kx]) / n;
}

}  // namespace

Spectrum periodogram(const std::vector<std::vector<glm::dvec2>>& sets, const Box& box,
                     const SpectrumOptions& options) {
    if (sets.empty()) throw Error("no point set to analyse");
    if (!(options.half_width >= 1 && options.half_width <= kMaxHalfWidth))
        throw Error(fmt::format("the spectrum's frequencies must reach 1 to {} (got {})", kMaxHalfWidth,
                                options.half_width));
    std::vector<std::vector<uvec2>> fixed;
    double points = 0;
    for (std::size_t s = 0; s < sets.size(); ++s) {
        if (sets[s].empty()) throw Error(fmt::format("set {} has no points", s + 1));
        for (std::size_t i = 0; i < sets[s].size(); ++i) {
            const glm::dvec2 p = sets[s][i];
            if (!(p.x >= 0 && p.y >= 0 && p.x < box.width && p.y < box.height))
                throw Error(fmt::format("set {}, point {} ({}, {}) is outside the box [0,{}) x [0,{})", s + 1, i + 1,
                                        p.x, p.y, box.width, box.height));
        }
        fixed.push_back(fixed_point(sets[s], box));
        points += double(sets[s].size());
    }
    const int h = options.half_width;
    const std::size_t w = std::size_t(2 * h + 1);
    std::vector<double> half_plane((w * w - 1) / 2, 0.0);

    SampleOptions choice_of;
    choice_of.backend = options.backend;
    choice_of.device = options.device;
    Spectrum out;
    out.backend = choose_backend(choice_of).backend;
    if (out.backend == Backend::Gpu) {
        out.device = detail::device_periodogram(fixed, std::uint32_t(h), options.device, half_plane);
    } else {
        out.backend = Backend::Cpu;
        out.device = "host";
        detail::ThreadPool pool(options.threads);
        for (const auto& set : fixed) host_periodogram(set, h, pool, half_plane);
    }
    out.half_width = h;
    out.sets = sets.size();
    out.mean_points = points / double(sets.size());
    out.power.assign(w * w, 0.0);
    const std::size_t centre = (w * w - 1) / 2;
    for (std::size_t f = 0; f < half_plane.size(); ++f) {
        const double p = half_plane[f] / double(sets.size());
        out.power[centre + 1 + f] = p;  // k
        out.power[centre - 1 - f] = p;  // -k, its mirror through the centre
    }
    return out;
}

RadialPower radial_power(const Spectrum& spectrum) {
    const int h = spectrum.half_width;
    std::vector<double> sum(std::size_t(h) + 1, 0.0), sum2(std::size_t(h) + 1, 0.0), count(std::size_t(h) + 1, 0.0);
    for (int ky = -h; ky <= h; ++ky)
        for (int kx = -h; kx <= h; ++kx) {
            const auto f = std::size_t(std::lround(std::hypot(double(kx), double(ky))));
            if (f == 0 || f > std::size_t(h)) continue;
            const double p = spectrum.at(kx, ky);
            sum[f] += p;
            sum2[f] += p * p;
            count[f] += 1;
        }
    RadialPower r;
    for (std::size_t f = 1; f <= std::size_t(h); ++f) {
        const double mean = sum[f] / count[f];
        const double variance = std::max(0.0, sum2[f] / count[f] - mean * mean);
        r.frequency.push_back(double(f));
        r.power.push_back(mean);
        r.anisotropy_db.push_back(mean > 0 && variance > 0 ? 10 * std::log10(variance / (mean * mean))
                                                           : -std::numeric_limits<double>::infinity());
    }
    return r;
}

Spacing spacing(const std::vector<glm::dvec2>& points, const Box& box) {
    const std::size_t n = points.size();
    if (n < 2) throw Error("spacing needs at least 2 points");
    const bool periodic = box.boundary == Boundary::Periodic;
    // Buckets of about one point each; a point's nearest neighbour is searched ring by ring.
    const double side = std::sqrt(box.width * box.height / double(n));
    const auto gx = std::int64_t(std::clamp(std::floor(box.width / side), 1.0, 4096.0));
    const auto gy = std::int64_t(std::clamp(std::floor(box.height / side), 1.0, 4096.0));
    const double sx = box.width / double(gx), sy = box.height / double(gy);
    auto bucket_x = [&](double v) { return std::clamp(std::int64_t(v / sx), std::int64_t(0), gx - 1); };
    auto bucket_y = [&](double v) { return std::clamp(std::int64_t(v / sy), std::int64_t(0), gy - 1); };
    std::vector<std::uint32_t> start(std::size_t(gx * gy) + 1, 0), order(n);
    for (const glm::dvec2& p : points) ++start[std::size_t(bucket_y(p.y) * gx + bucket_x(p.x)) + 1];
    for (std::size_t b = 1; b < start.size(); ++b) start[b] += start[b - 1];
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t i = 0; i < n; ++i)
        order[fill[std::size_t(bucket_y(points[i].y) * gx + bucket_x(points[i].x))]++] = i;
    auto gap = [&](double a, double b, double extent) {
        const double d = std::abs(a - b);
        return periodic ? std::min(d, extent - d) : d;
    };
    double smallest = INFINITY, total = 0;
    const std::int64_t widest = std::max(gx, gy);
    for (std::uint32_t i = 0; i < n; ++i) {
        const glm::dvec2 p = points[i];
        const std::int64_t cx = bucket_x(p.x), cy = bucket_y(p.y);
        double best = INFINITY;
        auto visit = [&](std::int64_t x, std::int64_t y) {
            if (periodic) {
                x = (x % gx + gx) % gx;
                y = (y % gy + gy) % gy;
            } else if (x < 0 || y < 0 || x >= gx || y >= gy) {
                return;
            }
            const std::size_t b = std::size_t(y * gx + x);
            for (std::uint32_t k = start[b]; k < start[b + 1]; ++k)
                if (order[k] != i)
                    best = std::min(best, std::hypot(gap(points[order[k]].x, p.x, box.width),
                                                     gap(points[order[k]].y, p.y, box.height)));
        };
        // Ring r holds the buckets at Chebyshev distance r; every point in it is at least
        // (r - 1) min(sx, sy) away. Past half the grid a periodic ring would wrap onto buckets
        // seen before, so the search ends with a pass over every bucket (seeing one twice is
        // harmless).
        for (std::int64_t r = 0;; ++r) {
            if (double(r - 1) * std::min(sx, sy) >= best) break;
            if (periodic && 2 * r + 1 > widest) {
                for (std::int64_t y = 0; y < gy; ++y)
                    for (std::int64_t x = 0; x < gx; ++x) visit(x, y);
                break;
            }
            if (!periodic && r > widest) break;
            for (std::int64_t d = -r; d <= r; ++d) {
                visit(cx + d, cy - r);
                if (r > 0) visit(cx + d, cy + r);
                if (d != -r && d != r) {
                    visit(cx - r, cy + d);
                    visit(cx + r, cy + d);
                }
            }
        }
        smallest = std::min(smallest, best);
        total += best;
    }
    Spacing s;
    s.d_max = std::sqrt(2.0 * box.width * box.height / (std::sqrt(3.0) * double(n)));
    s.delta_x = smallest / s.d_max;
    s.mean_min_distance = total / double(n) / s.d_max;
    return s;
}

}  // namespace vrpd
