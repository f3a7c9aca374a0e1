// A fixed pool of worker threads for the host engine's data-parallel loops. parallel_for splits
// [0, n) into contiguous chunks, in order, that the threads claim as they come free, so a thread
// that starts late or runs slow takes fewer; the calling thread takes its share, so a 1-core
// machine still works. An exception in any chunk (out of memory, say) reaches the caller once
// every chunk running has stopped.
#pragma once

#include <atomic>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <utility>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace vrpd::detail {

class ThreadPool {
public:
    // `threads` threads, the caller's among them; 0: one per hardware thread (one where the count
    // is unknown). Throws Error naming the count if the threads cannot all be started (those that
    // were are stopped first).
    explicit ThreadPool(unsigned threads = 0);
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    unsigned size() const { return unsigned(workers_.size()) + 1; }
    // The cpu backend's device name on these threads: "cpu (host, N threads)".
    std::string device_name() const {
        return "cpu (host, " + std::to_string(size()) + (size() == 1 ? " thread)" : " threads)");
    }
    // The chunks parallel_for splits [0, n) into: one on one thread or for fewer than `grain`
    // items, else kChunksPerThread a thread.
    std::size_t chunks(std::size_t n, std::size_t grain = kGrain) const {
        return workers_.empty() || n < grain ? 1 : std::size_t(size()) * kChunksPerThread;
    }
    // Calls body(begin, end, chunk) on the chunks(n, grain) chunks covering [0, n) in order (chunk
    // c holds [n c / chunks, n (c + 1) / chunks)), on any thread. Returns when every chunk is done;
    // rethrows the first exception a chunk threw, once the chunks begun are done (the rest are
    // skipped). A caller's per-chunk results, kept by chunk index, are the same on every run.
    void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t, unsigned)>& body,
                      std::size_t grain = kGrain);
    // Calls body(worker) once for each worker < size(), each on its own thread and all at once
    // (parallel_for runs a small n on the caller alone), for work whose shares wait on each other.
    void each_worker(const std::function<void(unsigned)>& body);

private:
    // Below kGrain items a loop's chunks cost more to hand out than they save; above it each
    // thread gets kChunksPerThread on average.
    static constexpr std::size_t kGrain = 2048;
    static constexpr unsigned kChunksPerThread = 8;
    // Runs body over [0, n) in `chunks` chunks: claimed by the threads as they come free, or
    // (`per_thread`, chunks == size()) chunk t on thread t.
    void dispatch(std::size_t n, std::size_t chunks, bool per_thread,
                  const std::function<void(std::size_t, std::size_t, unsigned)>& body);
    void work(unsigned id);
    void stop();
    // Runs thread id's chunks of the job, keeping the first exception instead of letting it out.
    void run_chunks(unsigned id);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    const std::function<void(std::size_t, std::size_t, unsigned)>* job_ = nullptr;
    std::size_t job_size_ = 0, job_chunks_ = 0;
    bool job_per_thread_ = false;
    std::atomic<std::size_t> next_chunk_{0};
    // Written under mutex_; atomic so that a thread watching for a new job or for the workers'
    // end can read them without it.
    std::atomic<std::size_t> generation_{0};
    std::atomic<unsigned> pending_{0};
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
