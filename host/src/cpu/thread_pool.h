// A fixed pool of worker threads for the host engine's data-parallel loops. parallel_for splits
// [0, n) into contiguous chunks; the calling thread takes a share, so a 1-core machine still works.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace vrpd::detail {

class ThreadPool {
public:
    explicit ThreadPool(unsigned threads = std::thread::hardware_concurrency());
    ~ThreadPool();
    ThreadPool(const ThreadPool&) = delete;
    ThreadPool& operator=(const ThreadPool&) = delete;

    unsigned size() const { return unsigned(workers_.size()) + 1; }
    // Calls body(begin, end, worker) on disjoint chunks covering [0, n); worker < size().
    void parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t, unsigned)>& body);

private:
    void work(unsigned id);

    std::vector<std::thread> workers_;
    std::mutex mutex_;
    std::condition_variable wake_, done_;
    const std::function<void(std::size_t, std::size_t, unsigned)>* job_ = nullptr;
    std::size_t job_size_ = 0;
    std::size_t generation_ = 0;
    unsigned pending_ = 0;
    bool stop_ = false;
};

}  // namespace vrpd::detail
