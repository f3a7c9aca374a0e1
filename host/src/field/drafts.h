// The drafts a sizing field's table is refined through (field/table.cpp): the source at the nodes
// of a square grid and halfway between them, and how far the grid's interpolant is from it.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "table.h"
#include "../cpu/thread_pool.h"
#include "../cpu/uninitialised.h"

namespace vrpd::detail {

// The largest relative distance of the table from the source that its refinement aims at.
inline constexpr double kTargetError = 0.00075;

// The double-valued table at a resolution: its nodes, the source at the points halfway between
// them (which are the next resolution's nodes), and its largest relative error against the
// source at those of them inside the box.
// Its arrays are first touched by the row threads that fill them, on huge pages where granted.
using Doubles = std::vector<double, Uninitialised<double, true>>;
using Bytes = std::vector<std::uint8_t, Uninitialised<std::uint8_t, true>>;
struct Draft {
    std::uint32_t cells_x = 0, cells_y = 0;
    double h = 0;
    Doubles values;
    Doubles fine;  // (2 cells_x + 1) x (2 cells_y + 1), at spacing h / 2
    // With the source's branches (kinks): the branch mask the source takes beside each value,
    // and at the corners of the cells a kink crosses, the source on that kink's other branch
    // (`other`, as `values`; elsewhere unset). Empty without them.
    Bytes mask, mask_fine;
    Doubles other;
    double error = 0;
    std::uint64_t over = 0;  // the points where the error is past the target
    bool broken = false;     // a cell a kink crosses is no join of its branches (cell_model)
};

// How the table interpolates a draft's cell: its nodes (kPlain), or the least (kMin) or greatest
// (kMax) of its branches' interpolants where one kink crosses it (the source's branch masks at
// its corners differ in that kink's bit alone) and the source is that join of them at every
// corner, each branch a radius there. kBroken: kinks cross it otherwise; the table then takes no
// branches.
enum Join : int { kPlain = -1, kMin = int(shared::FIELD_KINK_MIN), kMax = int(shared::FIELD_KINK_MAX), kBroken = 2 };
struct CellModel {
    int join = kPlain;
    double a[4], b[4];  // the branches at the corners (field_interpolate's order)
};
// Cell (i, j) of d as the table interpolates it.
CellModel cell_model(const Draft& d, std::uint32_t i, std::uint32_t j);

// Calls row(j) for j in [0, n) on the pool's threads, from two rows on (a row holds hundreds of
// nodes or more); an Error stops the run as each_reporting says.
void for_rows(ThreadPool& pool, std::size_t n, const std::function<void(std::size_t)>& row);

// Per cell of the draft, the largest error at its centre and edge midpoints (those past a free
// box's far edges excepted, as the draft's own error does).
std::vector<double> cell_errors(ThreadPool& pool, const FieldSource& f, const Box& box, const Draft& d);

// The draft of cells_x x cells_y cells of side h, from its nodes if the last draft's `fine` holds
// them (with branches g, the last draft's `mask_fine` too).
Draft draft(ThreadPool& pool, const FieldSource& f, const FieldBranches& g, const Box& box, std::uint32_t cells_x,
            std::uint32_t cells_y, double h, Draft last);

}  // namespace vrpd::detail
