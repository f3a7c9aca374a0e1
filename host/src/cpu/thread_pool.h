// A fixed pool of worker threads for the host engine's data-parallel loops. parallel_for splits
// [0, n) into contiguous chunks; the calling thread takes a share, so a 1-core machine still works.
// An exception in any share (out of memory, say) reaches the caller once every share has stopped.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <utility>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace vrpd::detail {

class ThreadPool {
public:
    // Throws Error naming the count if the threads cannot all be started (those that were are
    // stopped first).
    explicit ThreadPool(unsigned threads = std::thread::hardware_concurrency());
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    unsigned size() const { return unsigned(workers_.size()) + 1; }
    // Calls body(begin, end, worker) on disjoint chunks covering [0, n); worker < size(). Returns
    // when every chunk is done; rethrows the first exception a chunk threw, after all are done.
    void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t, unsigned)>& body);
    // Calls body(worker) once for each worker < size(), each on its own thread and all at once
    // (parallel_for runs a small n on the caller alone), for work whose shares wait on each other.
    void each_worker(const std::function<void(unsigned)>& body);

private:
    // Runs body over [0, n) in size() chunks, one a worker.
    void dispatch(std::size_t n, const std::function<void(std::size_t, std::size_t, unsigned)>& body);
    void work(unsigned id);
    void stop();
    // Runs one chunk, keeping its exception (the first of the job's) instead of letting it out.
    void run_chunk(std::size_t n, unsigned id, const std::function<void(std::size_t, std::size_t, unsigned)>& body);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    const std::function<void(std::size_t, std::size_t, unsigned)>* job_ = nullptr;
    std::size_t job_size_ = 0;
    std::size_t generation_ = 0;
    unsigned pending_ = 0;
    bool stop_ = false;
    std::exception_ptr error_;  // the first exception of the current job
};

// Per-chunk counts in first[w + 1] (chunk w of a parallel_for, first[0] = 0) become each chunk's
// first index in the chunks' order; returns the total.
inline std::uint64_t chunk_offsets(std::vector<std::uint64_t>& first) {
    for (std::size_t w = 1; w < first.size(); ++w) first[w] += first[w - 1];
    return first.back();
}

}  // namespace vrpd::detail
