// The kept blocks of blocks.h: one list of every block mapped, each lent or kept, under one lock.
#include "blocks.h"

#include <algorithm>
#include <cstdlib>
#include <mutex>
#include <new>
#include <vector>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace vrpd::detail {

namespace {

struct Block {
    char* p;
    std::size_t bytes;
    bool kept;  // else lent
};

std::mutex blocks_lock;  // engines may run on several threads
std::vector<Block> blocks;

char* map_block(std::size_t bytes) {
#ifdef __linux__
    // Mapped with a huge page's slack, then trimmed to an aligned run of `bytes`.
    const std::size_t span = bytes + kBlockAlign;
    void* raw = mmap(nullptr, span, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (raw == MAP_FAILED) throw std::bad_alloc();
    const auto at = reinterpret_cast<std::uintptr_t>(raw);
    const std::uintptr_t aligned = (at + kBlockAlign - 1) / kBlockAlign * kBlockAlign;
    if (aligned > at) munmap(raw, aligned - at);
    if (aligned + bytes < at + span) munmap(reinterpret_cast<void*>(aligned + bytes), at + span - aligned - bytes);
    char* p = reinterpret_cast<char*>(aligned);
#ifdef MADV_HUGEPAGE
    madvise(p, bytes, MADV_HUGEPAGE);  // advice: where it is refused, the pages stay small
#endif
    return p;
#else
    void* p = std::aligned_alloc(kBlockAlign, bytes);
    if (p == nullptr) throw std::bad_alloc();
    return static_cast<char*>(p);
#endif
}

// Unmaps the kept blocks and drops them from the list; the caller holds the lock.
void unmap_kept() {
    for (const Block& b : blocks) {
        if (!b.kept) continue;
#ifdef __linux__
        munmap(b.p, b.bytes);
#else
        std::free(b.p);
#endif
    }
    blocks.erase(std::remove_if(blocks.begin(), blocks.end(), [](const Block& b) { return b.kept; }), blocks.end());
}

}  // namespace

std::size_t block_bytes(std::size_t bytes) { return (bytes + kBlockAlign - 1) / kBlockAlign * kBlockAlign; }

void* take_block(std::size_t bytes) {
    bytes = block_bytes(bytes);
    const std::lock_guard<std::mutex> hold(blocks_lock);
    blocks.reserve(blocks.size() + 1);  // for a split's rest or a fresh block: the pushes below cannot fail
    Block* best = nullptr;
    for (Block& b : blocks)
        if (b.kept && b.bytes >= bytes && (best == nullptr || b.bytes < best->bytes)) best = &b;
    if (best != nullptr) {
        best->kept = false;
        char* p = best->p;
#ifdef __linux__
        // The rest of a larger block is kept apart, for a later array (a mapping's pages can be
        // unmapped in any runs).
        if (best->bytes > bytes) {
            const Block rest{p + bytes, best->bytes - bytes, true};
            best->bytes = bytes;
            blocks.push_back(rest);
        }
#endif
        return p;
    }
    // None fits: the kept blocks are all smaller, and would stay resident beside the fresh one.
    unmap_kept();
    char* p = map_block(bytes);
    blocks.push_back({p, bytes, false});
    return p;
}

void give_block(void* p) noexcept {
    const std::lock_guard<std::mutex> hold(blocks_lock);
    for (Block& b : blocks)
        if (b.p == p && !b.kept) {
            b.kept = true;
            return;
        }
}

void release_blocks() noexcept {
    const std::lock_guard<std::mutex> hold(blocks_lock);
    unmap_kept();
}

}  // namespace vrpd::detail
