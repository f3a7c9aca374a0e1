// An allocator for the host engine's large arrays of trivial elements.
#pragma once

#include <memory>
#include <new>
#include <utility>

namespace vrpd::detail {

// Vectors of this allocator leave trivial elements uninitialised on a resize, so that the pool's
// threads, filling a fresh array, make the first touch of its pages in parallel.
template <class T>
struct Uninitialised : std::allocator<T> {
    template <class U>
    struct rebind {
        using other = Uninitialised<U>;
    };
    Uninitialised() = default;
    template <class U>
    Uninitialised(const Uninitialised<U>&) noexcept {}
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
