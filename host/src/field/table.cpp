// Tabulating a sizing field (field/table.h). The lattice: quadtree roots (tiles) from r_max / 2
// to r_max wide, of the side whose leaves and table are lightest (field/tiles.cpp), and table
// cells of 2^15 lattice units at most 8 r_min wide, so r_min spans at least 4096 lattice units
// and the interpolant's rounding costs under 0.025 %. The table is refined (table cells and
// lattice halved together) while its interpolant is further than 0.075 % from the source at some
// table cell's centre or edge midpoint, within the 31-bit lattice and a budget of 8 nodes per
// expected sample. A kink, such as abs()'s, converges only linearly: where the source's one kink
// crosses a cell, the cell interpolates the kink's two branches (each smooth) and takes their
// least or greatest, as the source does (a kinked cell). The cells still past 0.075 % then get
// patches (field/patches.cpp), quadtrees of their own; kinked cells and patches share a budget
// of table words per expected sample (Sizing::table_budget, 32 by default; at least 2^18; a split
// takes 8, a kinked cell 9). Where the patches cannot reach 0.075 % within it, they reach the
// least target they can, up by factors of 2^(1/4).
#include "table.h"

#include "drafts.h"
#include "patches.h"

#include "field.h"
#include "../cpu/thread_pool.h"
#include "../cpu/uninitialised.h"
#include "../plan.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <optional>

#include <fmt/format.h>

namespace vrpd::detail {
namespace {

constexpr std::uint64_t kLatticeLimit = 0x7FFFFFFFu;
constexpr std::uint64_t kMaxTableNodes = std::uint64_t(16) << 20;
constexpr double kNodesPerSample = 8;
constexpr std::uint64_t kMinTableNodes = std::uint64_t(1) << 16;
constexpr std::uint32_t kMinLatticeRadius = 4096;
constexpr std::uint32_t kSurvey = 256;
constexpr double kMinPatchWords = 1 << 18;

}  // namespace

FieldStats FieldTable::stats() const {
    return {box_lo * quantum, box_hi * quantum, lipschitz, tabulation_error,
            std::uint64_t(nodes.size() + 5 * splits.size() + 8 * std::uint64_t(kink_count))};
}

void require_memory(const char* what, double expected, double bytes_per_sample) {
    const MemoryLimit limit = host_memory_limit();
    if (!(expected * bytes_per_sample <= double(limit.bytes)))
        throw Error(fmt::format("{} needs about {:.3g} samples and {:.0f} MiB, more than the {} ({:.0f} MiB)", what,
                                expected, expected * bytes_per_sample / (1 << 20), limit.what,
                                double(limit.bytes) / (1 << 20)));
}

namespace {

// The table of `s` over `box`, its kinked cells from the source's branches g (none if g is
// empty). Empty where the branches fail it: a cell kinks cross is no join of them, a branch
// passes the lattice's radii, or the kinked cells take more words than the patches' budget; the
// table without branches is then made instead.
std::optional<FieldTable> tabulate_with(const Sizing& s, const Box& box, unsigned threads, const FieldBranches& g) {
    const BlocksReleased released;  // the drafts' blocks, once the drafts are gone
    if (s.lipschitz != -1 && !(std::isfinite(s.lipschitz) && s.lipschitz >= 0))
        throw Error(fmt::format("the Lipschitz bound must be a finite number >= 0 (got {})", s.lipschitz));
    if (!(s.table_budget >= 1 && s.table_budget <= 1024))
        throw Error(fmt::format("the table budget must be 1 to 1024 words a sample (got {})", s.table_budget));
    const FieldSource f = field_source(s, box);
    const bool periodic = box.boundary == Boundary::Periodic;
    double lo = INFINITY, hi = 0;
    std::vector<double> xs(kSurvey + 1), ys(kSurvey + 1), vs(kSurvey + 1);
    for (std::uint32_t j = 0; j <= kSurvey; ++j) {
        for (std::uint32_t i = 0; i <= kSurvey; ++i) {
            xs[i] = box.width * i / kSurvey * (1 - 1e-12);
            ys[i] = box.height * j / kSurvey * (1 - 1e-12);
        }
        f(xs.data(), ys.data(), vs.data(), kSurvey + 1);
        for (std::uint32_t i = 0; i <= kSurvey; ++i) {
            const double v = checked_radius(vs[i], xs[i], ys[i]);
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    }
    // The samples to expect, 0.70 per r^2 of area (as for one radius), refused past memory.
    double expected = 0;
    std::vector<double> centres(std::size_t(kSurvey) * kSurvey);  // r at the survey cells' centres
    for (std::uint32_t j = 0; j < kSurvey; ++j) {
        for (std::uint32_t i = 0; i < kSurvey; ++i) {
            xs[i] = box.width * (i + 0.5) / kSurvey;
            ys[i] = box.height * (j + 0.5) / kSurvey;
        }
        f(xs.data(), ys.data(), &centres[std::size_t(j) * kSurvey], kSurvey);
        for (std::uint32_t i = 0; i < kSurvey; ++i) {
            const double v = checked_radius(centres[std::size_t(j) * kSurvey + i], xs[i], ys[i]);
            expected += 0.70 * box.width * box.height / (kSurvey * kSurvey) / (v * v);
        }
    }
    // A budget past the default adds its words to each sample's bytes.
    require_memory("the field", expected, kFieldBytesPerSample + 4 * std::max(0.0, s.table_budget - 32));
    const double short_side = std::min(box.width, box.height);
    if (periodic && hi >= short_side / 2)
        throw Error(
            fmt::format("the field's largest radius {:.6g} is too large for a periodic box of {} x {}: it must "
                        "be < {} (half the shorter side)",
                        hi, box.width, box.height, short_side / 2));

    FieldTable t;
    std::uint64_t tx = 0, ty = 0;
    double tile = std::min(hi, std::max(box.width, box.height));
    if (periodic && !periodic_tiling(box.width, box.height, tile, 1, tx, ty))
        throw Error(
            fmt::format("periodic box {} x {}: width/height must be a ratio of small integers so that "
                        "square tiles fit it",
                        box.width, box.height));
    tile = lightest_tiles(box, tile, lo, tx, ty, centres, kSurvey);
    auto fits = [&](std::uint32_t a) {
        return (std::max(tx, ty) << (a + shared::MAX_FIELD_CELL_BITS)) <= kLatticeLimit &&
               ((tx * ty) << (2 * a)) <= kMaxTableNodes;
    };
    std::uint32_t a = 0;
    while (tile / double(1u << a) > 8 * lo && a < 30) ++a;
    if (!fits(a))
        throw Error(
            fmt::format("the field's radii ({:.6g} to {:.6g}) span more of the box than the 31-bit lattice and "
                        "the table's {} nodes hold",
                        lo, hi, kMaxTableNodes));
    Draft d;
    double samples = 0;
    ThreadPool pool(threads);
    for (;;) {
        d = draft(pool, f, g, box, std::uint32_t(tx << a), std::uint32_t(ty << a), tile / double(1u << a),
                  std::move(d));
        if (d.broken) return std::nullopt;
        const double quantum = d.h / double(1u << shared::MAX_FIELD_CELL_BITS);
        const double least = *std::min_element(d.values.begin(), d.values.end());
        const bool fine = d.error <= kTargetError && least / quantum >= kMinLatticeRadius;
        // The table stays within a few nodes per expected sample (0.70 per r^2 of area).
        samples = 0;
        for (double v : d.values) samples += 0.70 * d.h * d.h / (v * v);
        const double next_nodes = double(tx << (a + 1)) * double(ty << (a + 1));
        const bool affordable = next_nodes <= std::max(kNodesPerSample * samples, double(kMinTableNodes));
        if (fine || !fits(a + 1) || (least / quantum >= kMinLatticeRadius && !affordable)) break;
        ++a;
    }
    // The kinked cells, in cell order, with their joins; their words come from the patches' budget.
    std::vector<std::uint32_t> kinked;
    if (g)
        for (std::uint32_t j = 0; j < d.cells_y; ++j)
            for (std::uint32_t i = 0; i < d.cells_x; ++i)
                if (cell_model(d, i, j).join != kPlain) kinked.push_back(j * d.cells_x + i);
    double budget = std::max(s.table_budget * samples, double(kMinPatchWords));
    if (budget < double(kinked.size()) * shared::FIELD_KINK_WORDS) return std::nullopt;
    // Patches where the table strays from the source past the target (a kink the cells do not
    // take as kinked, or a bend), within their own budget of table words; none under --lipschitz,
    // whose field is the table's nodes themselves, nor on a kinked cell. Where they cannot reach
    // the target within it, the least target they reach, from the target up by factors of 2^(1/4).
    // `unpatched`: the table's error without them, or negative to measure it.
    struct Patched {
        std::vector<PatchDraft> patches;
        double error = 0;
        double kinked_error = 0;  // the kinked cells' own
        bool met_kinked = false;
    };
    auto patch = [&](const std::vector<std::uint32_t>& fixed, double unpatched) {
        Patched out;
        const TableDraft view{d.values.data(), d.fine.data(), d.cells_x, d.cells_y, d.h};
        std::vector<double> cell_error = cell_errors(pool, f, box, d);
        out.error = unpatched >= 0 ? unpatched : *std::max_element(cell_error.begin(), cell_error.end());
        for (std::uint32_t c : fixed) out.kinked_error = std::max(out.kinked_error, cell_error[c]), cell_error[c] = 0;
        const double rest = *std::max_element(cell_error.begin(), cell_error.end());
        const auto words = std::uint64_t(budget - double(fixed.size()) * shared::FIELD_KINK_WORDS);
        for (double target = kTargetError; out.patches.empty() && !out.met_kinked && target < rest;
             target *= std::sqrt(std::sqrt(2.0)))
            out.patches =
                draft_patches(pool, f, box, view, cell_error, target, words, fixed, out.error, out.met_kinked);
        if (!out.patches.empty()) out.error = std::max(out.error, out.kinked_error);
        return out;
    };
    double error = d.error;
    std::vector<PatchDraft> patches;
    if (s.lipschitz < 0 && d.error > kTargetError) {
        Patched best = patch(kinked, d.error);
        // The same draft with every cell plain, where a patch would fall on a kinked cell (the
        // grading of patches beside it: patches and kinked cells meet only where the patches'
        // leaves beside a kinked cell are at most one level below it), or where the kinked cells
        // stay past the target themselves (branches that bend within a cell, which they cannot
        // refine); the closer table is kept.
        if (!kinked.empty() && (best.met_kinked || (best.error > kTargetError && best.kinked_error > kTargetError))) {
            Bytes mask = std::move(d.mask);
            d.mask.clear();
            Patched plain = patch({}, -1);
            if (best.met_kinked || plain.error < best.error) {
                best = std::move(plain);
                kinked.clear();
            } else {
                d.mask = std::move(mask);
            }
        }
        patches = std::move(best.patches);
        error = best.error;
    }
    Doubles().swap(d.fine);
    if (lo == hi && std::all_of(d.values.begin(), d.values.end(), [&](double v) { return v == lo; })) t.constant = lo;
    if (s.lipschitz >= 0) limit_lipschitz(d.values, d.cells_x, d.cells_y, d.h, s.lipschitz, periodic, threads);

    t.cell_bits = shared::MAX_FIELD_CELL_BITS;
    t.quantum = d.h / double(1u << t.cell_bits);
    t.tile_bits = a + t.cell_bits;
    t.tiles_x = std::uint32_t(tx);
    t.tiles_y = std::uint32_t(ty);
    t.cells_x = d.cells_x;
    t.cells_y = d.cells_y;
    t.lattice.periodic = periodic ? 1u : 0u;
    const std::uint64_t ex = tx << t.tile_bits, ey = ty << t.tile_bits;
    t.lattice.extent_x =
        periodic ? std::uint32_t(ex) : std::uint32_t(std::min<double>(std::ceil(box.width / t.quantum), double(ex)));
    t.lattice.extent_y =
        periodic ? std::uint32_t(ey) : std::uint32_t(std::min<double>(std::ceil(box.height / t.quantum), double(ey)));
    t.tabulation_error = error;
    // The largest node decides whether every node fits 32 bits (rounding is monotone).
    const double largest = *std::max_element(d.values.begin(), d.values.end());
    if (std::round(largest / t.quantum) >= 4294967295.0)
        throw Error(fmt::format("the field's radius {:.6g} is too large for the lattice of this box", largest));
    t.nodes.resize(d.values.size());
    pool.parallel_for(d.values.size(), [&](std::size_t begin, std::size_t end, unsigned) {
        for (std::size_t i = begin; i < end; ++i)
            t.nodes[i] = std::max<std::uint32_t>(1, std::uint32_t(std::round(d.values[i] / t.quantum)));
    });
    install_patches(t, patches, pool);
    // The drafts are many small blocks of the heap, freed before the bounds are made: their pages
    // stay with the heap, whose later small arrays reuse them without a page fault.
    std::vector<PatchDraft>().swap(patches);
    if (!kinked.empty()) {
        t.kink_count = std::uint32_t(kinked.size());
        t.kinks.reserve(kinked.size() * shared::FIELD_KINK_WORDS);
        for (std::uint32_t c : kinked) {
            const CellModel m = cell_model(d, c % d.cells_x, c / d.cells_x);
            for (const double* branch : {m.a, m.b})
                for (int k = 0; k < 4; ++k) {
                    // As the nodes are rounded: the branch the source takes at a corner is its node.
                    const double v = std::round(branch[k] / t.quantum);
                    if (v >= 4294967295.0) return std::nullopt;
                    t.kinks.push_back(std::max<std::uint32_t>(1, std::uint32_t(v)));
                }
            t.kinks.push_back(std::uint32_t(m.join));
        }
        rank_cells(std::size_t(t.cells_x) * t.cells_y, kinked, t.kinked, t.kink_rank);
    }
    complete_bounds(t, pool);
    return t;
}

}  // namespace

FieldTable tabulate(const Sizing& s, const Box& box, unsigned threads) {
    if (s.lipschitz < 0)
        if (const FieldBranches g = field_branches(s, box))
            if (std::optional<FieldTable> t = tabulate_with(s, box, threads, g)) return std::move(*t);
    return std::move(*tabulate_with(s, box, threads, {}));
}

FieldTable scaled(const FieldTable& t, double scale, ThreadPool& pool) {
    // The largest node decides whether every scaled node fits 32 bits (rounding is monotone).
    if (std::round(double(t.r_hi) * scale) >= 4294967295.0)
        throw Error(fmt::format("the field's radius {:.6g} at {} times is too large for the lattice of this box",
                                double(t.r_hi) * t.quantum, scale));
    auto times = [&](std::uint32_t v) {
        return std::max<std::uint32_t>(1, std::uint32_t(std::round(double(v) * scale)));
    };
    FieldTable out = t;
    auto scale_nodes = [&](std::vector<std::uint32_t>& nodes) {
        pool.parallel_for(nodes.size(), [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t i = begin; i < end; ++i) nodes[i] = times(nodes[i]);
        });
    };
    scale_nodes(out.nodes);
    // A split's least and greatest node scale with it: `times` is non-decreasing.
    pool.parallel_for(out.splits.size(), [&](std::size_t begin, std::size_t end, unsigned) {
        for (std::size_t i = begin; i < end; ++i) {
            FieldTable::Split& s = out.splits[i];
            for (std::uint32_t& m : s.mid) m = times(m);
            s.lo = times(s.lo);
            s.hi = times(s.hi);
        }
    });
    // The kinked cells' branches scale alike; their joins stay.
    for (std::size_t k = 0; k < out.kinks.size(); ++k)
        if (k % shared::FIELD_KINK_WORDS != 8) out.kinks[k] = times(out.kinks[k]);
    out.constant = t.constant * scale;
    complete_bounds(out, pool);
    return out;
}

void limit_lipschitz(std::span<double> values, std::uint32_t cells_x, std::uint32_t cells_y, double h, double L,
                     bool periodic, unsigned threads) {
    // The distinct nodes (on a torus the last row and column repeat the first), and min pyramids
    // over blocks of 2^k x 2^k of them.
    const std::size_t nx = std::size_t(cells_x) + 1, ny = std::size_t(cells_y) + 1;
    const std::size_t w = periodic ? nx - 1 : nx, hgt = periodic ? ny - 1 : ny;
    std::vector<std::vector<double>> mins(1, std::vector<double>(w * hgt));
    std::vector<std::size_t> widths(1, w), heights(1, hgt);
    for (std::size_t j = 0; j < hgt; ++j)
        for (std::size_t i = 0; i < w; ++i) mins[0][j * w + i] = values[j * nx + i];
    while (widths.back() > 1 || heights.back() > 1) {
        const std::size_t pw = widths.back(), ph = heights.back(), cw = (pw + 1) / 2, ch = (ph + 1) / 2;
        std::vector<double> next(cw * ch, INFINITY);
        const std::vector<double>& prev = mins.back();
        for (std::size_t j = 0; j < ph; ++j)
            for (std::size_t i = 0; i < pw; ++i)
                next[j / 2 * cw + i / 2] = std::min(next[j / 2 * cw + i / 2], prev[j * pw + i]);
        mins.push_back(std::move(next));
        widths.push_back(cw);
        heights.push_back(ch);
    }
    // The nodes' gap to [lo, hi] along an axis of n distinct nodes: on a torus, the shorter way.
    auto gap = [&](std::size_t c, std::size_t lo, std::size_t hi, std::size_t n) -> double {
        if (c >= lo && c <= hi) return 0;
        const std::size_t before = c < lo ? lo - c : lo + n - c, after = c > hi ? c - hi : c + n - hi;
        if (!periodic) return double(c < lo ? before : after);
        return double(std::min(before, after));
    };
    const double slope = L * h;
    std::vector<double> out(w * hgt);
    ThreadPool pool(threads);
    for_rows(pool, hgt, [&](std::size_t j) {
        struct Block {
            std::size_t level, bx, by;
            double bound;  // its least node raised by L times its distance
        };
        auto block = [&](std::size_t i, std::size_t level, std::size_t bx, std::size_t by) {
            const std::size_t lo_x = bx << level, lo_y = by << level;
            const std::size_t hi_x = std::min(w, (bx + 1) << level) - 1, hi_y = std::min(hgt, (by + 1) << level) - 1;
            // Inner blocks' bounds only order and prune the search, with a margin far wider than
            // sqrt's rounding; a node's is its value, as the cone's formula gives it.
            const double gx = gap(i, lo_x, hi_x, w), gy = gap(j, lo_y, hi_y, hgt);
            return Block{level, bx, by,
                         mins[level][by * widths[level] + bx] +
                             slope * (level == 0 ? std::hypot(gx, gy) : std::sqrt(gx * gx + gy * gy))};
        };
        std::vector<Block> stack;
        for (std::size_t i = 0; i < w; ++i) {
            // Branch and bound, nearest bound first: a block whose bound is not below the best
            // so far holds no better node. Blocks within 1e-12 of it are not entered either:
            // along a cone's rays every node ties with the best, and the nodes' values are
            // rounded to lattice units far coarser than that.
            double best = mins[0][j * w + i];
            if (mins.size() > 1) stack.push_back(block(i, mins.size() - 1, 0, 0));  // else one node
            while (!stack.empty()) {
                const Block b = stack.back();
                stack.pop_back();
                if (b.bound >= best * (1 - 1e-12)) continue;
                Block kids[4];
                int n = 0;
                for (std::size_t c = 0; c < 4; ++c) {
                    const std::size_t cx = 2 * b.bx + (c & 1), cy = 2 * b.by + (c >> 1);
                    if (cx < widths[b.level - 1] && cy < heights[b.level - 1])
                        kids[n++] = block(i, b.level - 1, cx, cy);
                }
                if (b.level == 1) {  // the kids are nodes
                    for (int k = 0; k < n; ++k) best = std::min(best, kids[k].bound);
                    continue;
                }
                for (int k = 1; k < n; ++k)  // largest bound first, so the smallest is popped first
                    for (int m = k; m > 0 && kids[m - 1].bound < kids[m].bound; --m) std::swap(kids[m - 1], kids[m]);
                for (int k = 0; k < n; ++k)
                    if (kids[k].bound < best * (1 - 1e-12)) stack.push_back(kids[k]);
            }
            out[j * w + i] = best;
        }
    });
    for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t i = 0; i < nx; ++i) values[j * nx + i] = out[(j % hgt) * w + i % w];
}

}  // namespace vrpd::detail
