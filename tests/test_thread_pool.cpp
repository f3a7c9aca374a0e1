// The host engines' thread pool: parallel_for's chunks cover the range once, in a fixed order the
// callers' per-chunk results rely on; the threads claim them as they come free; each_worker runs
// every worker at once; a chunk's exception reaches the caller and leaves the pool usable.
#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <stdexcept>
#include <tuple>
#include <vector>

#include "cpu/thread_pool.h"

using vrpd::detail::ThreadPool;

TEST_CASE("ThreadPool: parallel_for covers the range once, chunk c of k holding n c / k to n (c + 1) / k", "[pool]") {
    for (unsigned threads : {1u, 2u, 3u}) {
        ThreadPool pool(threads);
        for (std::size_t n : {std::size_t(1), std::size_t(100), std::size_t(2047), std::size_t(2048),
                              std::size_t(100003)}) {
            for (std::size_t grain : {std::size_t(1), std::size_t(2048)}) {
                const std::size_t k = pool.chunks(n, grain);
                CHECK(k == (threads == 1 || n < grain ? 1 : threads * 8u));
                std::mutex mutex;
                std::vector<std::tuple<unsigned, std::size_t, std::size_t>> seen;
                pool.parallel_for(
                    n,
                    [&](std::size_t b, std::size_t e, unsigned c) {
                        const std::lock_guard lock(mutex);
                        seen.emplace_back(c, b, e);
                    },
                    grain);
                std::sort(seen.begin(), seen.end());
                REQUIRE(seen.size() == k);
                for (std::size_t c = 0; c < k; ++c) {
                    CHECK(std::get<0>(seen[c]) == c);
                    CHECK(std::get<1>(seen[c]) == n * c / k);
                    CHECK(std::get<2>(seen[c]) == n * (c + 1) / k);
                }
            }
        }
    }
}

TEST_CASE("ThreadPool: a slow chunk holds only itself, the other threads take the rest", "[pool]") {
    // Chunk 0 waits until every other chunk is done: with chunks claimed as threads come free,
    // the other thread runs them all meanwhile; with a fixed share a thread, it would wait.
    ThreadPool pool(2);
    const std::size_t n = 100000, k = pool.chunks(n);
    REQUIRE(k > 2);
    std::mutex mutex;
    std::condition_variable changed;
    std::size_t done = 0;
    bool waited_out = false;
    pool.parallel_for(n, [&](std::size_t, std::size_t, unsigned c) {
        std::unique_lock lock(mutex);
        if (c == 0) {
            waited_out = !changed.wait_for(lock, std::chrono::seconds(20), [&] { return done == k - 1; });
            return;
        }
        ++done;
        changed.notify_all();
    });
    CHECK_FALSE(waited_out);
    CHECK(done == k - 1);
}

TEST_CASE("ThreadPool: each_worker runs every worker's body at once", "[pool]") {
    for (unsigned threads : {2u, 3u}) {
        ThreadPool pool(threads);
        std::mutex mutex;
        std::condition_variable changed;
        unsigned arrived = 0, waited_out = 0;
        std::vector<unsigned> workers;
        pool.each_worker([&](unsigned w) {
            std::unique_lock lock(mutex);
            workers.push_back(w);
            ++arrived;
            changed.notify_all();
            waited_out += !changed.wait_for(lock, std::chrono::seconds(20), [&] { return arrived == threads; });
        });
        std::sort(workers.begin(), workers.end());
        CHECK(waited_out == 0);
        REQUIRE(workers.size() == threads);
        for (unsigned w = 0; w < threads; ++w) CHECK(workers[w] == w);
    }
}

TEST_CASE("ThreadPool: a chunk's exception reaches the caller, and the pool runs the next loop", "[pool]") {
    ThreadPool pool(2);
    const std::size_t n = 50000;
    CHECK_THROWS_WITH(pool.parallel_for(n,
                                        [&](std::size_t, std::size_t, unsigned c) {
                                            if (c == 3) throw std::runtime_error("chunk 3");
                                        }),
                      "chunk 3");
    std::vector<char> hit(n, 0);
    pool.parallel_for(n, [&](std::size_t b, std::size_t e, unsigned) { std::fill(hit.begin() + b, hit.begin() + e, 1); });
    CHECK(std::count(hit.begin(), hit.end(), 1) == std::ptrdiff_t(n));
}
