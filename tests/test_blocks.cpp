// The host engines' kept blocks (cpu/blocks.h): a freed block serves the next array that fits in
// it, a larger one split with its rest kept apart; blocks are whole huge pages, aligned to one;
// nothing kept survives release_blocks. The allocator's vectors take them from 2 MiB on.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>
#include <vector>

#include "cpu/blocks.h"
#include "cpu/uninitialised.h"

using namespace vrpd::detail;

namespace {
constexpr std::size_t kMiB = std::size_t(1) << 20;
bool aligned(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % kBlockAlign == 0; }
}  // namespace

TEST_CASE("blocks: whole huge pages, reused smallest first, a larger one split", "[blocks]") {
    release_blocks();
    CHECK(block_bytes(1) == 2 * kMiB);
    CHECK(block_bytes(2 * kMiB) == 2 * kMiB);
    CHECK(block_bytes(2 * kMiB + 1) == 4 * kMiB);

    auto* six = static_cast<char*>(take_block(5 * kMiB + 3));  // 6 MiB
    auto* two = static_cast<char*>(take_block(2 * kMiB));
    REQUIRE(aligned(six));
    REQUIRE(aligned(two));
    std::memset(six, 0x5a, 6 * kMiB);  // every byte of the rounded block is there to write
    std::memset(two, 0xa5, 2 * kMiB);
    give_block(six);
    give_block(two);

    // The smallest kept block that fits: the 2 MiB one, not the 6 MiB one.
    CHECK(take_block(kMiB) == two);
    // A larger block split: its first 4 MiB lent, its last 2 MiB kept apart for the next.
    CHECK(take_block(3 * kMiB) == six);
    CHECK(take_block(2 * kMiB) == six + 4 * kMiB);
    // None kept fits: a fresh block.
    auto* fresh = static_cast<char*>(take_block(2 * kMiB));
    CHECK(aligned(fresh));
    CHECK(fresh != two);
    CHECK(fresh != six);
    CHECK(fresh != six + 4 * kMiB);
    for (char* p : {two, six, six + 4 * kMiB, fresh}) give_block(p);
    release_blocks();
    // Nothing kept: a request the 6 MiB block served is fresh memory, writable.
    auto* again = static_cast<char*>(take_block(6 * kMiB));
    std::memset(again, 1, 6 * kMiB);
    give_block(again);
    release_blocks();
}

#ifndef __SANITIZE_ADDRESS__  // under AddressSanitizer the allocator keeps every array on the heap
TEST_CASE("blocks: the allocator's vectors of 2 MiB and more reuse a freed array's block", "[blocks]") {
    release_blocks();
    using Big = std::vector<std::uint32_t, Uninitialised<std::uint32_t, true>>;
    const std::uint32_t* first = nullptr;
    {
        Big a(kMiB);  // 4 MiB
        first = a.data();
        CHECK(aligned(first));
    }
    {
        Big b(kMiB / 2);  // 2 MiB: the first 2 MiB of a's block
        CHECK(b.data() == first);
        Big c(kMiB / 2);  // its other half
        CHECK(c.data() == first + kMiB / 2);
    }
    // Small arrays stay with the standard allocator.
    Big small(16);
    CHECK(small.size() == 16);
    release_blocks();
}
#endif
