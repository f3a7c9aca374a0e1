// Patches of a sizing field's table (field/table.h, FieldTable::Split): quadtrees over the table
// cells whose bilinear interpolant strays from the source, as at a kink.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "table.h"
#include "../cpu/thread_pool.h"

namespace vrpd::detail {

// Runs body(k) for k in [0, n) on the pool's threads, in chunks of at least `grain`; a k that
// throws Error stops its chunk's work, and the lowest such k's message is rethrown, so that it
// does not depend on timing.
template <typename Body>
void each_reporting(ThreadPool& pool, std::size_t n, std::size_t grain, Body&& body) {
    std::mutex mutex;
    std::size_t failed = SIZE_MAX;
    std::string message;
    pool.parallel_for(
        n,
        [&](std::size_t begin, std::size_t end, unsigned) {
            for (std::size_t k = begin; k < end; ++k) {
                try {
                    body(k);
                } catch (const Error& e) {
                    const std::lock_guard lock(mutex);
                    if (k < failed) failed = k, message = e.what();
                    return;
                }
            }
        },
        grain);
    if (failed != SIZE_MAX) throw Error(message);
}

// v = r(x, y), a point of the box; throws unless v is a radius.
inline double checked_radius(double v, double x, double y) {
    if (!(std::isfinite(v) && v > 0))
        throw Error(
            fmt::format("sizing field: r({:.6g}, {:.6g}) = {}; it must be a finite number > 0 everywhere in "
                        "the box",
                        x, y, v));
    return v;
}

// The source at one point of the box, checked.
inline double source_at(const FieldSource& f, double x, double y) {
    double v;
    f(&x, &y, &v, 1);
    return checked_radius(v, x, y);
}

// A table node's value from the source's value v at (x, y): inside the box v, checked; past a
// free box's edge v if it is a radius, else the source at the edge.
inline double node_value(const FieldSource& f, const Box& box, double x, double y, double v) {
    if (x <= box.width && y <= box.height) return checked_radius(v, x, y);
    return std::isfinite(v) && v > 0 ? v : source_at(f, std::min(x, box.width), std::min(y, box.height));
}

// Raises `steepest` to the largest gradient of the interpolant of a cell with nodes v00, v10,
// v01, v11 (x first), in node units per cell side times `scale`. It is largest at a corner
// (|grad|^2 is convex on the cell); |gx| + |gy|, exact, bounds hypot's value, so a corner whose
// sum is no more than the largest so far is passed over.
inline void raise_steepest(double& steepest, double v00, double v10, double v01, double v11, double scale) {
    for (double gx : {v10 - v00, v11 - v01})
        for (double gy : {v01 - v00, v11 - v10})
            if ((std::abs(gx) + std::abs(gy)) * scale > steepest)
                steepest = std::max(steepest, std::hypot(gx, gy) * scale);
}

// The table's nodes before rounding: (cells_x + 1) x (cells_y + 1) values over cells of side h,
// and the source halfway between them, (2 cells_x + 1) x (2 cells_y + 1) values, row by row.
struct TableDraft {
    const double* values;
    const double* fine;
    std::uint32_t cells_x, cells_y;
    double h;
};

// A patch before rounding: table cell `cell`'s quadtree of splits, the root first. A split's
// square is at `level` (side 2^-level table cells) and (x, y) in squares of that side from the
// cell's corner; `source` holds the five nodes it adds as the source gives them (node_value's),
// `value` the same after continuity (where the other side of an edge is a leaf of the split's
// size, halfway between the split's corners there).
struct PatchDraft {
    struct Split {
        double source[5];
        double value[5];
        std::int32_t child[4] = {-1, -1, -1, -1};  // child quadrant's split (bit 0: right, bit 1: upper)
        // A child that is a leaf: its error with the source's nodes at its corners, once judged
        // (else negative).
        float error[4] = {-1, -1, -1, -1};
        std::uint16_t x = 0, y = 0;
        std::uint8_t level = 0;
    };
    std::uint32_t cell = 0;
    std::vector<Split> splits;
};

// Patches the table cells whose error (cell_error: the largest relative distance at the cell's
// centre and edge midpoints) exceeds `target`: each a quadtree whose leaves are split while their
// error at their own centre and edge midpoints does, neighbouring leaves at most one level apart,
// and split further where continuity takes a leaf past the target. Within `budget` table words
// (FIELD_SPLIT_WORDS a split), or none. Returns them in cell order; `error` (in: the table's error
// without patches) becomes the patched table's. None, and `met_fixed` set, where a patch would
// fall on one of the `fixed` cells (sorted: kinked cells, whose error is taken as 0 here, split
// for the grading of patches beside them).
std::vector<PatchDraft> draft_patches(ThreadPool& pool, const FieldSource& f, const Box& box, const TableDraft& d,
                                      const std::vector<double>& cell_error, double target, std::uint64_t budget,
                                      const std::vector<std::uint32_t>& fixed, double& error, bool& met_fixed);

// Gives t (its lattice, quantum and nodes set) the patches' splits in lattice units, indexed by
// cell, and their bounds.
void install_patches(FieldTable& t, const std::vector<PatchDraft>& patches, ThreadPool& pool);

// A table's bounds as a chunk of its cells or patches sees them: the box's least and greatest r,
// and the steepest gradient (in node units per table cell). Chunks join in any order: min and
// max are exact.
struct BoundsPart {
    std::uint32_t lo = UINT32_MAX, hi = 0;
    double steepest = 0;
    void join(const BoundsPart& o) {
        lo = std::min(lo, o.lo);
        hi = std::max(hi, o.hi);
        steepest = std::max(steepest, o.steepest);
    }
};

// Joins the patches' bounds into `bounds`: r at their nodes (as the table's nodes are taken,
// clipped to the box) and their cells' gradients. The patches go to the pool's threads.
void patch_bounds(const FieldTable& t, BoundsPart& bounds, ThreadPool& pool);

}  // namespace vrpd::detail
