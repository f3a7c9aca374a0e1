// Two radii on the host, until the first refinement: the active cells are the base cells without a
// sample, and the grid says which they are, so no list of them is made. Listing them (8 bytes a
// base cell, and the prefix sums of their darts, 4) would be the run's largest fresh arrays: the
// first round throws into every free base cell and refines each one. The darts, their numbering
// and the next active list are those of the listed cells' kernels (throw_base_cell,
// refine_cells_of_base, scatter_children) over start's list, bit for bit.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "shared/sampler.h"
#include "thread_pool.h"
#include "uninitialised.h"

namespace vrpd::detail {

// Of the base cells grid[0, bases), each chunk's (of a parallel_for) first cell without a sample
// among them all, chunk by chunk; the last entry is their count.
inline std::vector<std::uint64_t> free_base_offsets(ThreadPool& pool, const shared::uvec2* grid, std::size_t bases) {
    std::vector<std::uint64_t> first(pool.chunks(bases) + 1, 0);
    pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
        std::uint64_t free = 0;
        for (std::size_t i = b; i < e; ++i) free += shared::grid_is_sample(grid[i]) ? 0u : 1u;
        first[w + 1] = free;
    });
    chunk_offsets(first);
    return first;
}

// Lists the corners of the base cells without a sample into `cells`, in base cell order.
template <class Corners>
void list_free_bases(ThreadPool& pool, const shared::Domain& dom, const shared::uvec2* grid, std::size_t bases,
                     Corners& cells) {
    const std::vector<std::uint64_t> first = free_base_offsets(pool, grid, bases);
    Corners(first.back()).swap(cells);
    pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
        std::uint64_t next = first[w];
        for (std::size_t i = b; i < e; ++i)
            if (!shared::grid_is_sample(grid[i])) cells[next++] = shared::base_corner(dom, shared::uint(i));
    });
}

// The first round's darts for every free base cell (a.side: the base cell's; a.param: exp(-λ)):
// each chunk of base cells counts its cells' darts (cell_dart_counts), kept in the words' .y,
// then numbers them from the sum of the counts before it, each word with darts becoming their
// range as mark_dart_range writes it. Returns the round's darts.
inline std::uint64_t mark_free_base_darts(ThreadPool& pool, const shared::CellArgs& a, shared::uvec2* grid) {
    constexpr std::size_t kBatch = 64;
    const std::size_t bases = std::size_t(a.domain.cells_x) * a.domain.cells_y;
    std::vector<std::uint64_t> first(pool.chunks(bases) + 1, 0);
    pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
        std::array<shared::uvec2, kBatch> corners;
        std::array<shared::uint, kBatch> counts, at;
        std::uint64_t sum = 0;
        for (std::size_t i = b; i < e; i += kBatch) {
            const std::size_t end = std::min(e, i + kBatch);
            shared::uint n = 0;
            for (std::size_t j = i; j < end; ++j) {
                if (shared::grid_is_sample(grid[j])) continue;
                corners[n] = shared::base_corner(a.domain, shared::uint(j));
                at[n++] = shared::uint(j);
            }
            shared::cell_dart_counts(a.round_key, corners.data(), n, a.param, counts.data());
            for (shared::uint k = 0; k < n; ++k) {
                grid[at[k]].y = counts[k];
                sum += counts[k];
            }
        }
        first[w + 1] = sum;
    });
    const std::uint64_t total = chunk_offsets(first);
    if (total >= shared::MAX_ROUND_DARTS) return total;  // the caller refuses the round
    pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
        shared::uint next = shared::uint(first[w]);
        for (std::size_t i = b; i < e; ++i) {
            shared::uvec2& word = grid[i];
            if (shared::grid_is_sample(word)) continue;
            const shared::uint count = word.y;
            word = count == 0u ? shared::uvec2(shared::GRID_EMPTY, shared::GRID_EMPTY)
                               : shared::uvec2(shared::GRID_TAG | next, next + count);
            next += count;
        }
    });
    return total;
}

// Throws the darts of every base cell whose word holds a range (mark_free_base_darts), as
// throw_base_cell throws a listed base cell's. `no_samples`: the grid holds none yet (throw_cell).
inline void throw_free_base_darts(ThreadPool& pool, const shared::CellArgs& a, shared::Grid grid, shared::Darts darts,
                                  bool no_samples) {
    const std::size_t bases = std::size_t(a.domain.cells_x) * a.domain.cells_y;
    pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned) {
        for (std::size_t i = b; i < e; ++i) {
            const shared::uvec2 w = grid.word[i];
            if (!shared::grid_is_darts(w)) continue;
            const shared::uvec2 range = shared::listed_darts(w);
            const shared::uvec2 base(shared::uint(i) % a.domain.cells_x, shared::uint(i) / a.domain.cells_x);
            const shared::uvec2 corner = shared::base_corner(a.domain, shared::uint(i));
            shared::uint undecided = 0;
            shared::StateBits states = shared::no_state_bits(range.x);
            shared::throw_cell(shared::local_domain(a.domain, base), grid, base, darts,
                               shared::cell_stream(a.round_key, corner), corner, a.side, range.x, range.y - range.x,
                               states, undecided, no_samples);
            shared::or_dart_states(darts, states.word, states.bits);
        }
    });
}

// The first refinement (a.side: the children's side; a.param: 4 children, or 1, the cell itself)
// of every base cell without a sample: refine_cells_of_base's surviving children of each, written
// to `cells` in base cell order as scatter_children writes them. Each chunk keeps its cells'
// nonzero masks, then writes their children from the sum of the counts before it. Returns the
// bytes the kept masks held.
template <class Corners>
std::uint64_t refine_free_bases(ThreadPool& pool, const shared::CellArgs& a, shared::Grid grid, Corners& cells) {
    const std::size_t bases = std::size_t(a.domain.cells_x) * a.domain.cells_y;
    std::vector<std::uint64_t> first(pool.chunks(bases) + 1, 0);
    std::vector<std::vector<std::pair<shared::uint, shared::uint>>> kept(pool.chunks(bases));
    pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
        std::uint64_t sum = 0;
        for (std::size_t i = b; i < e; ++i) {
            if (shared::grid_is_sample(grid.word[i])) continue;  // no children (refine_cells_of_base)
            shared::uvec2 corner = shared::base_corner(a.domain, shared::uint(i));
            shared::uint mask = 0, count = 0;
            shared::refine_cells_of_base(a, shared::Cells{&corner}, shared::Uints{&count}, shared::Uints{&mask}, grid,
                                         0u, 1u);
            if (mask == 0u) continue;
            kept[w].emplace_back(shared::uint(i), mask);
            sum += count;
        }
        first[w + 1] = sum;
    });
    Corners(chunk_offsets(first)).swap(cells);
    std::uint64_t bytes = 0;
    for (const auto& k : kept) bytes += capacity_bytes(k);
    pool.parallel_for(bases, [&](std::size_t, std::size_t, unsigned w) {
        std::uint64_t next = first[w];
        for (const auto& [i, mask] : kept[w]) {
            const shared::uvec2 corner = shared::base_corner(a.domain, i);
            for (shared::uint c = 0; c < a.param; c++)
                if ((mask & (1u << c)) != 0u) cells[next++] = shared::child_corner(corner, a.side, c);
        }
    });
    return bytes;
}

}  // namespace vrpd::detail
