// Large blocks for the host engines' arrays: whole huge pages, and kept for reuse once freed.
// On small pages a run's arrays cost a page fault per 4 KiB on first touch, a sixth of a run's
// time at r = 0.001 (docs/performance.md); a block advised as huge pages costs one per 2 MiB. A
// run frees its arrays as each round spends them and allocates the next round's at similar
// sizes: kept blocks serve them without a fresh mapping's faults and zeroing. A kept block
// larger than an array is split, its rest kept apart.
#pragma once

#include <cstddef>
#include <cstdint>

namespace vrpd::detail {

constexpr std::size_t kBlockAlign = std::size_t(2) << 20;  // a huge page

// `bytes` rounded up to whole huge pages.
std::size_t block_bytes(std::size_t bytes);
// A block of block_bytes(bytes), aligned to a huge page and offered to the kernel as huge pages:
// from the smallest kept block that fits (its rest kept apart), else fresh, the kept blocks (all
// smaller) first returned to the system. Throws std::bad_alloc.
void* take_block(std::size_t bytes);
// Keeps a block take_block gave, for a later take_block.
void give_block(void* p) noexcept;
// Returns the kept blocks to the system.
void release_blocks() noexcept;

// Calls release_blocks when it goes: declared before the arrays it outlives, it runs after they
// have given their blocks back, so that nothing stays kept past the work that used it.
struct BlocksReleased {
    BlocksReleased() = default;
    BlocksReleased(const BlocksReleased&) = delete;
    BlocksReleased& operator=(const BlocksReleased&) = delete;
    ~BlocksReleased() { release_blocks(); }
};

}  // namespace vrpd::detail
