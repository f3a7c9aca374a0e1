// An allocator for the host engines' large arrays of trivial elements.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <utility>

#ifdef __linux__
#include <sys/mman.h>
#endif

namespace vrpd::detail {

// Vectors of this allocator leave trivial elements uninitialised on a resize, so that the pool's
// threads, filling a fresh array, make the first touch of its pages in parallel. With kHugePages,
// an array of 2 MiB or more is aligned to 2 MiB and offered to the kernel as huge pages (where it
// takes them on advice): a fresh array then costs a page fault per 2 MiB, not per 4 KiB. That
// suits short-lived arrays written once (the field table's drafts); the samplers' own arrays stay
// on small pages (on huge ones the field's resolution runs slower: docs/performance.md).
template <class T, bool kHugePages = false>
struct Uninitialised : std::allocator<T> {
    static constexpr std::size_t kHuge = std::size_t(2) << 20;
    template <class U>
    struct rebind {
        using other = Uninitialised<U, kHugePages>;
    };
    Uninitialised() = default;
    template <class U>
    Uninitialised(const Uninitialised<U, kHugePages>&) noexcept {}
    T* allocate(std::size_t n) {
        if (n > (SIZE_MAX - kHuge) / sizeof(T)) throw std::bad_array_new_length();
        if (!kHugePages || n * sizeof(T) < kHuge) return std::allocator<T>::allocate(n);
        const std::size_t rounded = (n * sizeof(T) + kHuge - 1) / kHuge * kHuge;
        void* p = std::aligned_alloc(kHuge, rounded);
        if (p == nullptr) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
        madvise(p, rounded, MADV_HUGEPAGE);  // advice: where it is refused, the pages stay small
#endif
        return static_cast<T*>(p);
    }
    void deallocate(T* p, std::size_t n) {
        if (!kHugePages || n * sizeof(T) < kHuge)
            std::allocator<T>::deallocate(p, n);
        else
            std::free(p);
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

}  // namespace vrpd::detail
