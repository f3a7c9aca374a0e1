// Patches of a sizing field's table (field/patches.h). A bilinear cell across a kink is off by
// about the slope's jump times the cell's side, so it converges only linearly: refining the whole
// table to the target there would take far more nodes than samples. A patch refines one cell to
// the depth its own error asks; the worst cells are deepened first, within a budget of nodes.
#include "patches.h"

#include <algorithm>
#include <mutex>
#include <string>

namespace vrpd::detail {
namespace {

constexpr std::uint32_t kMaxDepth = 8;

// The nodes of a patch of depth k (none at depth 0: the table cell's own four).
std::uint64_t nodes_at(std::uint32_t k) {
    return k == 0 ? 0 : ((std::uint64_t(1) << k) + 1) * ((std::uint64_t(1) << k) + 1);
}

// The interpolant of a patch's nodes (the even entries of `grid`, m + 1 a side) at (u, v), in
// the table cell's units.
double interpolate(const PatchDraft::Grid& grid, std::uint32_t m, double u, double v) {
    const std::uint32_t n = m / 2;
    const double fx = u * n, fy = v * n;
    const std::uint32_t p = std::min(std::uint32_t(fx), n - 1), q = std::min(std::uint32_t(fy), n - 1);
    const double tx = fx - p, ty = fy - q;
    auto at = [&](std::uint32_t a, std::uint32_t b) { return grid[std::size_t(2 * b) * (m + 1) + 2 * a]; };
    return (at(p, q) * (1 - tx) + at(p + 1, q) * tx) * (1 - ty) + (at(p, q + 1) * (1 - tx) + at(p + 1, q + 1) * tx) * ty;
}

// The largest relative distance between a patch's interpolant and the source at the points of
// its grid between its nodes. There the interpolant is the mean of the two nodes beside the
// point (an edge's midpoint) or of the four around it (a cell's centre): interpolate's value at
// those points, whose weights are all halves.
double patch_error(const PatchDraft& p) {
    const std::uint32_t m = 2u << p.depth;
    const std::size_t row = m + 1;
    const double* g = p.grid.data();
    double e = 0;
    std::size_t k = 0;  // the next entry of p.outside
    for (std::uint32_t b = 0; b <= m; ++b) {
        const bool node_row = b % 2 == 0;
        for (std::uint32_t a = node_row ? 1 : 0; a <= m; a += node_row ? 2 : 1) {
            const std::size_t at = b * row + a;
            if (k < p.outside.size() && p.outside[k].at == at) {
                const PatchDraft::Outside& o = p.outside[k++];
                if (o.source > 0) e = std::max(e, std::abs(interpolate(p.grid, m, o.u, o.v) - o.source) / o.source);
                continue;
            }
            const double mean =
                node_row     ? (g[at - 1] + g[at + 1]) * 0.5
                : a % 2 == 0 ? (g[at - row] + g[at + row]) * 0.5
                             : ((g[at - row - 1] + g[at - row + 1]) + (g[at + row - 1] + g[at + row + 1])) * 0.25;
            e = std::max(e, std::abs(mean - g[at]) / g[at]);
        }
    }
    return e;
}

struct Source {
    const FieldSource& f;
    const Box& box;
    const TableDraft& d;
    bool periodic;

    // Patch p one level deeper: its grid's entries become the even ones of a grid twice as fine,
    // the source at the others; then its error. Point (a, b) of the fine grid, of `fine` cells a
    // side over the table cell, lies at (cell's column * fine + a) * (h / fine) in x (likewise in
    // y): the same double as any coarser grid's for the same point; on a torus the last row and
    // column are the first.
    void deepen(PatchDraft& p) const {
        const std::uint32_t m = 2u << p.depth, fine = 2 * m;
        const std::size_t side = std::size_t(fine) + 1;
        const std::uint64_t column = std::uint64_t(p.cell % d.cells_x) * fine,
                            row = std::uint64_t(p.cell / d.cells_x) * fine;
        const std::uint64_t wrap_x = std::uint64_t(d.cells_x) * fine, wrap_y = std::uint64_t(d.cells_y) * fine;
        const double step = d.h / fine;
        auto coordinate = [&](std::uint64_t at, std::uint64_t wrap) {
            return double(periodic && at == wrap ? 0 : at) * step;
        };
        const std::size_t fresh = side * side - std::size_t(m + 1) * (m + 1);
        PatchDraft::Grid xs(fresh), ys(fresh), vs(fresh);
        std::size_t k = 0;
        for (std::uint32_t b = 0; b <= fine; ++b) {
            const double y = coordinate(row + b, wrap_y);
            for (std::uint32_t a = b % 2 == 0 ? 1 : 0; a <= fine; a += b % 2 == 0 ? 2 : 1, ++k) {
                xs[k] = coordinate(column + a, wrap_x);
                ys[k] = y;
            }
        }
        f(xs.data(), ys.data(), vs.data(), fresh);
        PatchDraft::Grid grid(side * side);
        p.outside.clear();
        const double x0 = double(p.cell % d.cells_x) * d.h, y0 = double(p.cell / d.cells_x) * d.h;
        k = 0;  // the next fresh point, in the order they were listed
        for (std::uint32_t b = 0; b <= fine; ++b)
            for (std::uint32_t a = 0; a <= fine; ++a) {
                const std::size_t at = b * side + a;
                if (a % 2 == 0 && b % 2 == 0) {
                    grid[at] = p.grid[std::size_t(b / 2) * (m + 1) + a / 2];
                    continue;
                }
                const double x = xs[k], y = ys[k], v = vs[k++];
                grid[at] = node_value(f, box, x, y, v);
                if (x <= box.width && y <= box.height) continue;
                // A cell wholly past the edge has nothing to judge there.
                const double ex = std::min(x, box.width), ey = std::min(y, box.height);
                const bool judged = ex >= x0 && ey >= y0;
                p.outside.push_back(
                    {std::uint32_t(at), (ex - x0) / d.h, (ey - y0) / d.h, judged ? source_at(f, ex, ey) : 0.0});
            }
        p.grid = std::move(grid);
        ++p.depth;
        p.error = patch_error(p);
    }

    // Table cell c as a patch of depth 0: its 3 x 3 points of the draft's finer grid.
    PatchDraft first(std::uint32_t c) const {
        PatchDraft p;
        p.cell = c;
        p.grid.reserve(9);
        const std::size_t row = 2 * std::size_t(d.cells_x) + 1, i = c % d.cells_x, j = c / d.cells_x;
        for (std::size_t b = 0; b < 3; ++b)
            for (std::size_t a = 0; a < 3; ++a) p.grid.push_back(d.fine[(2 * j + b) * row + 2 * i + a]);
        return p;
    }
};

// Calls visit(n, edge) for each table cell n sharing an edge with cell c (on a torus, around):
// edge 0 below c, 1 above, 2 left, 3 right.
template <typename Visit>
void each_neighbour(std::uint32_t c, const TableDraft& d, bool periodic, Visit&& visit) {
    const std::int64_t i = c % d.cells_x, j = c / d.cells_x;
    constexpr int kStep[4][2] = {{0, -1}, {0, 1}, {-1, 0}, {1, 0}};
    for (int edge = 0; edge < 4; ++edge) {
        std::int64_t x = i + kStep[edge][0], y = j + kStep[edge][1];
        if (periodic) {
            x = (x + d.cells_x) % d.cells_x;
            y = (y + d.cells_y) % d.cells_y;
        } else if (x < 0 || y < 0 || x >= d.cells_x || y >= d.cells_y) {
            continue;
        }
        visit(std::uint32_t(y * d.cells_x + x), edge);
    }
}

// Puts patch p's nodes on an edge shared with a cell of lesser depth (a table cell without a
// patch: depth 0) on that cell's edge, linear between its nodes there, and moves the nodes behind
// each by the same amount fading linearly to nothing at the opposite edge: a step at the edge
// would be as steep as the coarser cell's distance from the source over one patch cell. The
// other edges do not move (the amount is 0 at the edge's ends), so the patch stays continuous
// with every neighbour. The neighbours' nodes are read from `patches` (slot[c]: cell c's patch,
// or -1), as drafted: the coarser side of an edge never moves, so each patch conforms alone.
void conform(PatchDraft& p, const std::vector<PatchDraft>& patches, const std::vector<std::int32_t>& slot,
             const TableDraft& d, bool periodic) {
    // Node k along edge e (each_neighbour's numbering) of a patch of `side` cells a side, at row t
    // from that edge (t = 0: the edge).
    auto along = [](auto& grid, std::uint32_t side, int e, std::uint32_t k, std::uint32_t t) -> auto& {
        const std::uint32_t s = e == 2 ? t : e == 3 ? side - t : k, r = e == 0 ? t : e == 1 ? side - t : k;
        return grid[std::size_t(2 * r) * (2 * side + 1) + 2 * s];
    };
    const std::uint32_t n = 1u << p.depth;
    each_neighbour(p.cell, d, periodic, [&](std::uint32_t c, int edge) {
        const PatchDraft* q = slot[c] < 0 ? nullptr : &patches[std::size_t(slot[c])];
        const std::uint32_t depth = q ? q->depth : 0;
        if (depth >= p.depth) return;
        // The neighbour's nodes along the shared edge (its opposite edge, edge ^ 1): without a
        // patch, the edge's ends, which are this patch's too.
        const std::uint32_t nn = 1u << depth;
        std::vector<double> theirs(nn + 1);
        for (std::uint32_t k = 0; k <= nn; ++k)
            theirs[k] = q ? along(q->grid, nn, edge ^ 1, k, 0) : along(p.grid, n, edge, k == 0 ? 0 : n, 0);
        auto inward = [&](std::uint32_t k, std::uint32_t t) -> double& { return along(p.grid, n, edge, k, t); };
        for (std::uint32_t k = 1; k < n; ++k) {
            const double at = double(k) * nn / n;
            const std::uint32_t seg = std::min(std::uint32_t(at), nn - 1);
            const double w = at - seg;
            const double moved = theirs[seg] * (1 - w) + theirs[seg + 1] * w - inward(k, 0);
            for (std::uint32_t t = 0; t < n; ++t) inward(k, t) += moved * double(n - t) / n;
        }
    });
}

// Deepens each patch while more(p), on the pool's threads. A point between the nodes that is not
// a radius stops the run; the lowest cell's reason is given, so the message does not depend on
// timing.
template <typename More>
void deepen(ThreadPool& pool, const Source& source, std::vector<PatchDraft>& patches, More&& more) {
    std::mutex mutex;
    std::uint32_t failed = UINT32_MAX;
    std::string message;
    pool.parallel_for(
        patches.size(),
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = begin; k < end; ++k) {
                PatchDraft& p = patches[k];
                try {
                    while (more(p)) source.deepen(p);
                } catch (const Error& e) {
                    const std::lock_guard lock(mutex);
                    if (p.cell < failed) failed = p.cell, message = e.what();
                }
            }
        },
        4);
    if (failed != UINT32_MAX) throw Error(message);
}

// Raises depths until no cell is more than one level deeper than a cell sharing an edge with it
// (on a torus, around), so that a patch's edge conforms to a neighbour's at most one level
// coarser: one that is itself within the target there.
void grade(std::vector<std::uint8_t>& depth, const TableDraft& d, bool periodic) {
    for (bool changed = true; changed;) {
        changed = false;
        for (std::uint32_t c = 0; c < depth.size(); ++c) {
            const std::uint8_t k = depth[c];
            if (k <= 1) continue;
            each_neighbour(c, d, periodic, [&](std::uint32_t n, int) {
                if (depth[n] + 1 < k) depth[n] = std::uint8_t(k - 1), changed = true;
            });
        }
    }
}

}  // namespace

std::vector<PatchDraft> draft_patches(ThreadPool& pool, const FieldSource& f, const Box& box, const TableDraft& d,
                                      const std::vector<double>& cell_error, double target, std::uint64_t budget,
                                      double& error) {
    const bool periodic = box.boundary == Boundary::Periodic;
    const std::size_t cells = cell_error.size();
    // Each cell past the target at the depth that halving its error per level would take (a
    // kink's rate; a smooth field's error falls four times faster), the depths graded so that
    // neighbours differ by at most one level. Patches are made only if all of them fit the budget.
    std::vector<std::uint8_t> depth(cells, 0);
    std::vector<std::uint32_t> over;
    for (std::uint32_t c = 0; c < cells; ++c) {
        if (cell_error[c] <= target) continue;
        const double levels = std::ceil(std::log2(cell_error[c] / target));
        if (levels > kMaxDepth) return {};  // a jump, or a kink too sharp for the deepest patch
        depth[c] = std::uint8_t(std::max(1.0, levels));
        over.push_back(c);
    }
    if (over.empty()) return {};
    std::uint64_t least = 0;  // before grading
    for (std::uint32_t c : over) least += nodes_at(depth[c]);
    if (least > budget) return {};
    auto graded_nodes = [&] {
        grade(depth, d, periodic);
        std::uint64_t n = 0;
        for (std::uint8_t k : depth) n += nodes_at(k);
        return n;
    };
    if (graded_nodes() > budget) return {};
    // Then each such cell deepened while its measured error exceeds the target, the depths graded
    // again, and the cells below their graded depth deepened to it.
    const Source source{f, box, d, periodic};
    std::vector<PatchDraft> patches;
    std::vector<std::int32_t> slot(cells, -1);  // each cell's patch, or -1
    // `depth` becomes the depth each cell is wanted at: each patch goes at least that deep, and on
    // while its error exceeds the target, and the depths are graded again, until they hold.
    std::fill(depth.begin(), depth.end(), 0);
    for (std::uint32_t c : over) depth[c] = 1;
    auto open = [&](std::uint32_t c) {
        if (slot[c] >= 0) return;
        slot[c] = std::int32_t(patches.size());
        patches.push_back(source.first(c));
    };
    auto wanted = [&](const PatchDraft& p) {
        return p.depth < depth[p.cell] || (p.error > target && p.depth < kMaxDepth);
    };
    for (;;) {
        // Each cell wanted deeper that has no patch gets one, in cell order; their points are
        // copied on the threads.
        const std::size_t opened = patches.size();
        std::size_t wanted_now = 0;
        for (std::uint32_t c = 0; c < cells; ++c) wanted_now += depth[c] > 0 && slot[c] < 0;
        patches.reserve(opened + wanted_now);
        for (std::uint32_t c = 0; c < cells; ++c)
            if (depth[c] > 0 && slot[c] < 0) slot[c] = std::int32_t(patches.size()), patches.emplace_back().cell = c;
        pool.parallel_for(patches.size() - opened, [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = opened + begin; k < opened + end; ++k) patches[k] = source.first(patches[k].cell);
        });
        deepen(pool, source, patches, wanted);
        for (const PatchDraft& p : patches) {
            if (p.error > target) return {};  // past the deepest patch
            depth[p.cell] = std::max(depth[p.cell], std::uint8_t(p.depth));
        }
        if (graded_nodes() > 2 * budget) return {};
        if (std::none_of(patches.begin(), patches.end(), [&](const PatchDraft& p) { return p.depth < depth[p.cell]; }))
            break;
    }
    // Whether conforming takes patch c past the target. It reads only c's patch and its
    // neighbours' depths and patches, so each patch's answer is found on the threads first, and
    // found again only where a raise has changed the patch or a neighbour since.
    auto past_when_conformed = [&](std::uint32_t c) {
        const std::uint32_t k = patches[std::size_t(slot[c])].depth;
        bool coarser = false;
        each_neighbour(c, d, periodic, [&](std::uint32_t n, int) { coarser |= depth[n] < k; });
        if (!coarser) return false;
        PatchDraft q = patches[std::size_t(slot[c])];
        conform(q, patches, slot, d, periodic);
        return patch_error(q) > target;
    };
    constexpr std::int8_t kUnknown = -1;
    std::vector<std::int8_t> past(cells, kUnknown);
    pool.parallel_for(
        patches.size(),
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = begin; k < end; ++k)
                past[patches[k].cell] = std::int8_t(past_when_conformed(patches[k].cell));
        },
        64);
    // Where conforming to a coarser neighbour takes a patch past the target (the neighbour's edge,
    // within the target at its own points, is not at the finer ones, as where a kink crosses it),
    // the neighbour goes as deep, its own neighbours graded after it; each cell changed is checked
    // again. Depths only grow, so this ends.
    std::vector<std::uint32_t> work;
    std::vector<bool> queued(cells, false);
    auto queue = [&](std::uint32_t c) {
        if (slot[c] >= 0 && !queued[c]) queued[c] = true, work.push_back(c);
    };
    for (const PatchDraft& p : patches) queue(p.cell);
    bool deepest = false;  // a patch past the target at the deepest level
    auto raise = [&](auto&& self, std::uint32_t c, std::uint32_t k) -> void {
        if (k == 0 || depth[c] >= k) return;
        depth[c] = std::uint8_t(k);
        open(c);
        PatchDraft& p = patches[std::size_t(slot[c])];
        while (wanted(p)) source.deepen(p);
        deepest |= p.error > target;
        past[c] = kUnknown;
        queue(c);
        each_neighbour(c, d, periodic, [&](std::uint32_t n, int) {
            past[n] = kUnknown;
            queue(n);
            self(self, n, k - 1);
        });
    };
    while (!work.empty() && !deepest) {
        const std::uint32_t c = work.back();
        work.pop_back();
        queued[c] = false;
        if (past[c] == kUnknown) past[c] = std::int8_t(past_when_conformed(c));
        if (!past[c]) continue;
        const std::uint32_t k = patches[std::size_t(slot[c])].depth;
        each_neighbour(c, d, periodic, [&](std::uint32_t n, int) { raise(raise, n, k); });
    }
    std::uint64_t nodes = 0;
    for (const PatchDraft& p : patches) nodes += nodes_at(p.depth);
    if (deepest || nodes > 2 * budget) return {};
    // Conforming in place, on the threads: a patch reads only its coarser neighbours' edges, which
    // no patch moves (a patch moves only its nodes off the edges it shares with coarser ones).
    pool.parallel_for(
        patches.size(),
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = begin; k < end; ++k) {
                conform(patches[k], patches, slot, d, periodic);
                patches[k].error = patch_error(patches[k]);
            }
        },
        4);
    // In cell order: each cell's patch moved out through its slot.
    std::vector<PatchDraft> ordered;
    ordered.reserve(patches.size());
    error = 0;
    for (std::uint32_t c = 0; c < cells; ++c) {
        if (slot[c] < 0) {
            error = std::max(error, cell_error[c]);
            continue;
        }
        ordered.push_back(std::move(patches[std::size_t(slot[c])]));
        error = std::max(error, ordered.back().error);
    }
    return ordered;
}

void install_patches(FieldTable& t, const std::vector<PatchDraft>& patches, ThreadPool& pool) {
    if (patches.empty()) return;
    const std::size_t cells = std::size_t(t.cells_x) * t.cells_y;
    t.patched.assign((cells + 63) / 64, 0);
    t.patch_rank.assign(t.patched.size(), 0);
    // Each patch's nodes at its own offset, written on the threads; a radius too large for the
    // lattice is reported for the first such patch in cell order, as one pass would.
    t.patches.resize(patches.size());
    std::uint64_t nodes = t.patch_nodes.size();
    for (std::size_t k = 0; k < patches.size(); ++k) {
        const std::uint32_t n = 1u << patches[k].depth;
        t.patches[k] = {std::uint32_t(nodes), patches[k].depth, UINT32_MAX, 0};
        nodes += std::uint64_t(n + 1) * (n + 1);
    }
    t.patch_nodes.resize(nodes);
    std::vector<double> too_large(patches.size(), 0.0);
    pool.parallel_for(patches.size(), [&](std::size_t begin, std::size_t end, unsigned) {
        for (std::size_t k = begin; k < end; ++k) {
            const PatchDraft& p = patches[k];
            FieldTable::Patch& q = t.patches[k];
            const std::uint32_t n = 1u << p.depth, m = 2 * n;
            std::uint32_t* out = t.patch_nodes.data() + q.first;
            for (std::uint32_t r = 0; r <= n && too_large[k] == 0; ++r)
                for (std::uint32_t s = 0; s <= n; ++s) {
                    const double v = p.grid[std::size_t(2 * r) * (m + 1) + 2 * s];
                    const double units = std::round(v / t.quantum);
                    if (units >= 4294967295.0) {
                        too_large[k] = v;
                        break;
                    }
                    const std::uint32_t node = std::max<std::uint32_t>(1, std::uint32_t(units));
                    *out++ = node;
                    q.lo = std::min(q.lo, node);
                    q.hi = std::max(q.hi, node);
                }
        }
    });
    for (const double v : too_large)
        if (v != 0) throw Error(fmt::format("the field's radius {:.6g} is too large for the lattice of this box", v));
    for (const PatchDraft& p : patches) t.patched[p.cell >> 6] |= std::uint64_t(1) << (p.cell & 63);
    std::uint32_t before = 0;
    for (std::size_t w = 0; w < t.patched.size(); ++w) {
        t.patch_rank[w] = before;
        before += std::uint32_t(std::popcount(t.patched[w]));
    }
}

void patch_bounds(const FieldTable& t, BoundsPart& bounds, ThreadPool& pool) {
    const std::uint32_t last_x = t.lattice.extent_x - 1, last_y = t.lattice.extent_y - 1;
    // Each patch's table cell, in patch order.
    std::vector<std::uint32_t> cells;
    cells.reserve(t.patches.size());
    for (std::size_t w = 0; w < t.patched.size(); ++w)
        for (std::uint64_t word = t.patched[w]; word != 0; word &= word - 1)
            cells.push_back(std::uint32_t(w * 64 + std::size_t(std::countr_zero(word))));
    std::vector<BoundsPart> parts(pool.chunks(cells.size(), 4));
    pool.parallel_for(
        cells.size(),
        [&](std::size_t begin, std::size_t end, unsigned chunk) {
            BoundsPart part;
            for (std::size_t k = begin; k < end; ++k) {
                const std::size_t c = cells[k];
                const FieldTable::Patch& q = t.patches[k];
                const std::uint32_t n = 1u << q.depth, bits = t.cell_bits - q.depth;
                const std::uint64_t x0 = std::uint64_t(c % t.cells_x) << t.cell_bits, y0 = std::uint64_t(c / t.cells_x)
                                                                                           << t.cell_bits;
                auto at = [&](std::uint32_t s, std::uint32_t r) {
                    return double(t.patch_nodes[q.first + r * (n + 1) + s]);
                };
                for (std::uint32_t r = 0; r <= n; ++r)
                    for (std::uint32_t s = 0; s <= n; ++s) {
                        const std::uint64_t x = x0 + (std::uint64_t(s) << bits), y = y0 + (std::uint64_t(r) << bits);
                        if ((x > last_x && s > 0 && x - (std::uint64_t(1) << bits) > last_x) ||
                            (y > last_y && r > 0 && y - (std::uint64_t(1) << bits) > last_y))
                            continue;
                        if ((x > last_x && s == 0) || (y > last_y && r == 0)) continue;
                        // r at a node of the patch's own cells (not its far edges, its
                        // neighbours') is the node.
                        const std::uint32_t v = s < n && r < n && x <= last_x && y <= last_y
                                                    ? t.patch_nodes[q.first + r * (n + 1) + s]
                                                    : t.radius({std::uint32_t(std::min<std::uint64_t>(x, last_x)),
                                                                std::uint32_t(std::min<std::uint64_t>(y, last_y))});
                        part.lo = std::min(part.lo, v);
                        part.hi = std::max(part.hi, v);
                    }
                // A patch cell of side 2^-depth table cells: its gradient scaled up by 2^depth.
                // Those wholly past a free box's lattice, where r is never read, are passed over.
                for (std::uint32_t r = 0; r < n; ++r)
                    for (std::uint32_t s = 0; s < n; ++s)
                        if (x0 + (std::uint64_t(s) << bits) <= last_x && y0 + (std::uint64_t(r) << bits) <= last_y)
                            raise_steepest(part.steepest, at(s, r), at(s + 1, r), at(s, r + 1), at(s + 1, r + 1), n);
            }
            parts[chunk] = part;
        },
        4);
    for (const BoundsPart& part : parts) bounds.join(part);
}

}  // namespace vrpd::detail
