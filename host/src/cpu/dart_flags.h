// Two radii on the host: a flag a base cell for the cells that get darts in a round (the kernels'
// flag_dart_cells and flag_free_cell write them), kept zero between rounds: the listing clears
// each flag it takes, so that no round zeroes the array or scans it on one thread.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "shared/kernels.h"
#include "thread_pool.h"
#include "uninitialised.h"

namespace vrpd::detail {

class DartFlags {
public:
    // The flags of `bases` base cells, every one 0: zeroed on the pool's threads at the first
    // round, kept from the last round after it.
    shared::Uints zeroed(ThreadPool& pool, std::size_t bases) {
        if (flags_.size() != bases) {
            Flags(bases).swap(flags_);
            pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned) {
                std::fill(flags_.begin() + b, flags_.begin() + e, 0u);
            });
        }
        return {flags_.data()};
    }

    // Lists the flagged base cells' corners in base cell order into `out` and clears their flags:
    // each chunk of base cells counts its flags, then lists its cells from the sum of the counts
    // before it.
    template <class Corners>
    void list(ThreadPool& pool, const shared::Domain& dom, Corners& out) {
        const std::size_t bases = flags_.size();
        std::vector<std::uint64_t> first(pool.chunks(bases) + 1, 0);
        pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
            shared::uint count = 0;  // a plain sum, which the compiler vectorises
            for (std::size_t i = b; i < e; ++i) count += flags_[i] != 0u ? 1u : 0u;
            first[w + 1] = count;
        });
        out.resize(chunk_offsets(first));
        pool.parallel_for(bases, [&](std::size_t b, std::size_t e, unsigned w) {
            std::uint64_t at = first[w];
            for (std::size_t i = b; i < e; ++i)
                if (flags_[i] != 0u) {
                    out[at++] = shared::base_corner(dom, shared::uint(i));
                    flags_[i] = 0u;
                }
        });
    }

    // Gives the memory back; a run that failed may have left flags set.
    void release() { Flags().swap(flags_); }
    std::uint64_t bytes() const { return capacity_bytes(flags_); }

private:
    using Flags = std::vector<shared::uint, Uninitialised<shared::uint, true>>;
    Flags flags_;
};

}  // namespace vrpd::detail
