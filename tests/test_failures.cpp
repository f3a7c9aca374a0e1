// Failure injection: the k-th allocation of a run fails (a replaced global operator new, armed
// only around the run), for every k a run makes. Each such run must end in an exception the CLI
// turns into one line and exit 2: never an abort, a hang, or a worker left running. Thread starts
// allocate too, so a failed start is among them. Its own test binary: the replacement applies to
// the whole process. Catch2's runner is the shared one (main.cpp).
#include <catch2/catch.hpp>

#include <atomic>
#include <cstdlib>
#include <new>

#include "support.h"
#include "vrpd/vrpd.h"

namespace {
std::atomic<long> countdown{-1};  // >= 0: allocations left before one fails
std::atomic<long> counted{0};     // allocations while counting
std::atomic<bool> counting{false};
}  // namespace

void* operator new(std::size_t n) {
    if (counting.load(std::memory_order_relaxed)) counted.fetch_add(1, std::memory_order_relaxed);
    if (countdown.load(std::memory_order_relaxed) >= 0 && countdown.fetch_sub(1) == 0) throw std::bad_alloc();
    if (void* p = std::malloc(n ? n : 1)) return p;
    throw std::bad_alloc();
}
void* operator new[](std::size_t n) { return operator new(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

using namespace vrpd;

TEST_CASE("any allocation of a host run may fail: the run throws, and nothing aborts or hangs", "[failures]") {
    // Workers beside the caller, whatever the machine: cpu on 3 threads resolves in parallel, on 2
    // in arrival order, a strip a thread, whose threads wait on each other.
    for (auto [b, threads] : {std::pair{Backend::Cpu, 3u}, {Backend::Cpu, 2u}, {Backend::Serial, 3u}}) {
        SampleOptions o = test::options(0.02, 3, b);
        o.threads = threads;
        counting = true;
        const std::size_t expected = sample(o).size();
        counting = false;
        const long total = counted.exchange(0);
        INFO("backend " << int(b) << " threads " << threads << ": " << total << " allocations in a run");
        REQUIRE(total > 20);
        long thrown = 0;
        for (long k = 0; k < total; ++k) {
            countdown = k;
            try {
                const Sampling s = sample(o);
                CHECK(s.size() == expected);  // the failure hit nothing this run needed
            } catch (const std::bad_alloc&) {
                ++thrown;
            } catch (const Error&) {  // a thread that could not start
                ++thrown;
            }
            countdown = -1;
        }
        // Runs allocate alike, so nearly every k must have hit the run.
        CHECK(thrown >= total * 9 / 10);
    }
}
