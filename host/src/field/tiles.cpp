// The quadtree's roots (tiles) of a sizing field's table (field/table.h): the side whose leaves
// and table take the fewest bytes.
#include <algorithm>
#include <cmath>

#include "table.h"
#include "../plan.h"

namespace vrpd::detail {

LeafDensity::LeafDensity(const std::vector<double>& survey, std::uint32_t n, const Box& box)
    : points_(double(survey.size())) {
    const bool periodic = box.boundary == Boundary::Periodic;
    auto at = [&](std::int64_t i, std::int64_t j) {
        if (periodic) return survey[std::size_t((j + n) % n) * n + std::size_t((i + n) % n)];
        return survey[std::size_t(std::clamp<std::int64_t>(j, 0, n - 1)) * n +
                      std::size_t(std::clamp<std::int64_t>(i, 0, n - 1))];
    };
    for (std::uint32_t j = 0; j < n; ++j)
        for (std::uint32_t i = 0; i < n; ++i) {
            // The slope between the neighbouring points (half of it at a free box's edge).
            const std::int64_t x = i, y = j;
            const double gx = (at(x + 1, y) - at(x - 1, y)) / (2 * box.width / n),
                         gy = (at(x, y + 1) - at(x, y - 1)) / (2 * box.height / n);
            const double l = std::log2((std::sqrt(2.0) + kSlope * std::hypot(gx, gy)) / at(x, y));
            const double whole = std::floor(l);
            above_[std::min(std::size_t((l - whole) * kBins), kBins - 1)] += std::ldexp(1.0, 2 * int(whole));
        }
    for (std::size_t b = kBins - 1; b > 0; --b) above_[b - 1] += above_[b];  // from bin b up
}

double LeafDensity::operator()(double tile) const {
    const double t = std::log2(tile), whole = std::floor(t);
    // The points whose fraction of l is at least 1 - frac(t) take one level more.
    const std::size_t from = std::min(std::size_t(std::ceil((1 - (t - whole)) * kBins)), kBins);
    const double more = from < kBins ? above_[from] : 0;
    return std::ldexp(above_[0] + 3 * more, 2 * (int(whole) + 1)) / (tile * tile * points_);
}

double tile_bytes(const LeafDensity& leaves, double side, double least) {
    // At a run's peak a leaf holds about 29 bytes (its tree share, stamp and cell twice), a table
    // node about 6.7 (the node and its pyramids' shares).
    constexpr double kLeafBytes = 29, kNodeBytes = 6.7;
    double h = side;  // the table's cells, at most 8 r_min wide (table.cpp)
    while (h > 8 * least) h /= 2;
    return kLeafBytes * leaves(side) + kNodeBytes / (h * h);
}

double lightest_tiles(const Box& box, double largest, double least, std::uint64_t& tx, std::uint64_t& ty,
                      const std::vector<double>& survey, std::uint32_t n) {
    constexpr int kTileCandidates = 64;
    const bool periodic = box.boundary == Boundary::Periodic;
    const LeafDensity density(survey, n, box);
    const std::uint64_t first = tx;
    // A constant field keeps the largest tiles (the first candidate): its r is then the tile's
    // side where that tiles the box, a whole number of lattice units, as for one radius.
    const bool constant =
        std::all_of(survey.begin(), survey.end(), [&](double v) { return v == survey.front(); });
    std::uint64_t next = first;  // on a torus, the fewest tiles a side still to try
    double best = INFINITY, best_side = largest;
    for (int j = 0; j < (constant ? 1 : kTileCandidates); ++j) {
        const double step = std::exp2(double(j) / kTileCandidates);
        double side = largest / step;
        std::uint64_t nx = 0, ny = 0;
        if (periodic) {
            const double want = std::max(double(next), std::ceil(double(first) * step));
            if (!periodic_tiling(box.width, box.height, box.width / (want - 0.5), 1, nx, ny) || nx >= 2 * first) break;
            next = nx + 1;
            side = box.width / double(nx);
        }
        if (const double bytes = tile_bytes(density, side, least); bytes < best) {
            best = bytes, best_side = side;
            if (periodic) tx = nx, ty = ny;
        }
    }
    if (!periodic) {
        tx = std::uint64_t(std::ceil(box.width / best_side));
        ty = std::uint64_t(std::ceil(box.height / best_side));
    }
    return best_side;
}

}  // namespace vrpd::detail
