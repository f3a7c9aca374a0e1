// An allocator for the host engines' large arrays of trivial elements.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <utility>

#include "blocks.h"

namespace vrpd::detail {

// Vectors of this allocator leave trivial elements uninitialised on a resize, so that the pool's
// threads, filling a fresh array, make the first touch of its pages in parallel. With kHugePages,
// an array of 2 MiB or more takes a block of blocks.h: aligned to 2 MiB and offered to the kernel
// as huge pages (a fresh block costs a page fault per 2 MiB, not per 4 KiB), and kept when freed
// for the next array, whose pages are then in place. The engines' large arrays and the field
// table's drafts take them. Under AddressSanitizer every array stays on the heap, where its
// bounds are checked.
template <class T, bool kHugePages = false>
struct Uninitialised : std::allocator<T> {
#ifdef __SANITIZE_ADDRESS__
    static constexpr bool kBlocks = false;  // AddressSanitizer checks the bounds of heap arrays only
#else
    static constexpr bool kBlocks = kHugePages;
#endif
    template <class U>
    struct rebind {
        using other = Uninitialised<U, kHugePages>;
    };
    Uninitialised() = default;
    template <class U>
    Uninitialised(const Uninitialised<U, kHugePages>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > (SIZE_MAX - kBlockAlign) / sizeof(T)) throw std::bad_array_new_length();
        if (!kBlocks || n * sizeof(T) < kBlockAlign) return std::allocator<T>::allocate(n);
        return static_cast<T*>(take_block(n * sizeof(T)));
    }
    void deallocate(T* p, std::size_t n) {
        if (!kBlocks || n * sizeof(T) < kBlockAlign)
            std::allocator<T>::deallocate(p, n);
        else
            give_block(p);
    }
    template <class U>
    void construct(U* p) noexcept {
        ::new (static_cast<void*>(p)) U;
    }
    template <class U, class... A>
    void construct(U* p, A&&... a) {
        ::new (static_cast<void*>(p)) U(std::forward<A>(a)...);
    }
};

// Resizes v to n elements (contents not kept), reallocating unless its capacity is within an
// eighth above n: the arrays' high-water marks from earlier rounds would otherwise add up.
template <class V>
void fit(V& v, std::size_t n) {
    if (v.capacity() < n || v.capacity() > n + n / 8) {
        V().swap(v);
        v.reserve(n);
    }
    v.resize(n);
}

// The bytes v holds.
template <class V>
std::uint64_t capacity_bytes(const V& v) {
    return v.capacity() * sizeof(typename V::value_type);
}

}  // namespace vrpd::detail
