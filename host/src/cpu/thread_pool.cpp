// ThreadPool: see thread_pool.h.
#include "thread_pool.h"

#include <algorithm>

#include <fmt/format.h>

#include "vrpd/vrpd.h"

namespace vrpd::detail {
namespace {
std::pair<std::size_t, std::size_t> chunk(std::size_t n, unsigned parts, unsigned i) {
    return {n * i / parts, n * (i + 1) / parts};
}

// A round's loops follow each other within microseconds, and a sleeping thread takes tens of them
// to wake: a worker watches for the next job, and the caller for the workers' end, this many
// pauses (tens of microseconds) before sleeping.
constexpr unsigned kWatchPauses = 2048;

// Pauses until done() or kWatchPauses have passed; whether done() held.
template <class Done>
bool watch(Done done) {
    for (unsigned i = 0; i < kWatchPauses; ++i) {
        if (done()) return true;
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
    }
    return done();
}
}  // namespace

ThreadPool::ThreadPool(unsigned threads) {
    if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
    try {
        workers_.reserve(threads - 1);
        for (unsigned i = 1; i < threads; ++i) workers_.emplace_back([this, i] { work(i); });
    } catch (const std::exception& e) {
        const std::size_t started = workers_.size() + 1;
        stop();
        throw Error(fmt::format("cannot start {} host threads ({} started: {}); use fewer (--threads)", threads,
                                started, e.what()));
    }
}

ThreadPool::~ThreadPool() { stop(); }

void ThreadPool::stop() {
    {
        std::lock_guard lock(mutex_);
        stop_ = true;
    }
    wake_.notify_all();
    for (auto& t : workers_) t.join();
    workers_.clear();
}

void ThreadPool::run_chunks(unsigned id) {
    const auto& body = *job_;
    try {
        if (job_per_thread_) {
            auto [b, e] = chunk(job_size_, unsigned(job_chunks_), id);
            body(b, e, id);
            return;
        }
        for (std::size_t c; (c = next_chunk_.fetch_add(1, std::memory_order_relaxed)) < job_chunks_;) {
            auto [b, e] = chunk(job_size_, unsigned(job_chunks_), unsigned(c));
            body(b, e, unsigned(c));
        }
    } catch (...) {
        next_chunk_.store(job_chunks_, std::memory_order_relaxed);  // the chunks not begun are skipped
        std::lock_guard lock(mutex_);
        if (!error_) error_ = std::current_exception();
    }
}

void ThreadPool::parallel_for(std::size_t n, const std::function<void(std::size_t, std::size_t, unsigned)>& body,
                              std::size_t grain) {
    if (n == 0) return;
    const std::size_t parts = chunks(n, grain);
    if (parts == 1) {
        body(0, n, 0);
        return;
    }
    dispatch(n, parts, false, body);
}

void ThreadPool::each_worker(const std::function<void(unsigned)>& body) {
    if (workers_.empty()) {
        body(0);
        return;
    }
    dispatch(size(), size(), true, [&](std::size_t, std::size_t, unsigned w) { body(w); });
}

void ThreadPool::dispatch(std::size_t n, std::size_t chunks, bool per_thread,
                          const std::function<void(std::size_t, std::size_t, unsigned)>& body) {
    {
        std::lock_guard lock(mutex_);
        job_ = &body;
        job_size_ = n;
        job_chunks_ = chunks;
        job_per_thread_ = per_thread;
        next_chunk_.store(0, std::memory_order_relaxed);
        pending_ = unsigned(workers_.size());
        error_ = nullptr;
        ++generation_;
    }
    wake_.notify_all();
    run_chunks(0);
    watch([this] { return pending_.load(std::memory_order_acquire) == 0; });
    std::unique_lock lock(mutex_);
    done_.wait(lock, [this] { return pending_ == 0; });  // no chunk may outlive the data it uses
    job_ = nullptr;
    if (error_) std::rethrow_exception(std::exchange(error_, nullptr));
}

void ThreadPool::work(unsigned id) {
    std::size_t seen = 0;
    for (;;) {
        watch([&] { return generation_.load(std::memory_order_acquire) != seen; });
        {
            std::unique_lock lock(mutex_);
            wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
            if (stop_) return;
            seen = generation_;
        }
        run_chunks(id);
        {
            std::lock_guard lock(mutex_);
            --pending_;
        }
        done_.notify_one();
    }
}

}  // namespace vrpd::detail
