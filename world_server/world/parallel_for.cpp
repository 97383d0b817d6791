#include "world_server/world/parallel_for.hpp"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <vector>

namespace swarmform::parallel {
namespace {

thread_local bool t_in_body = false;  // nested calls run serially (no deadlock on the pool)

// Read once: hardware_concurrency() opens and reads /sys/devices/system/cpu/online, and the world asked
// for the worker count every tick (three system calls a round on the lockstep critical path).
std::size_t default_workers() {
  static const std::size_t workers = [] {
    if (const char* env = std::getenv("SWARMFORM_WORKERS")) {
      const long v = std::strtol(env, nullptr, 10);
      if (v >= 1) return static_cast<std::size_t>(std::min(v, 64L));
    }
    const unsigned hw = std::thread::hardware_concurrency();
    return std::clamp<std::size_t>(hw, 1, 2);
  }();
  return workers;
}

// workers - 1 threads sleep on a condition variable between runs; the caller is worker 0 and takes chunks
// too. A worker that wakes after the caller has taken the last chunk does not hold the run up: the caller
// closes the run once it finds no chunk left and then waits only for the workers that joined before (each
// is finishing a chunk it took). On a shared, loaded machine a woken worker may not be scheduled for
// milliseconds; the run then simply completes on the caller's thread, as with one worker.
class Pool {
 public:
  explicit Pool(std::size_t workers) : workers_(workers) {
    for (std::size_t w = 1; w < workers; ++w) {
      threads_.emplace_back([this, w] { loop(w); });
    }
  }
  ~Pool() {
    {
      std::lock_guard lock(m_);
      stop_ = true;
    }
    wake_.notify_all();
    threads_.clear();  // jthread joins
  }
  std::size_t size() const { return workers_; }

  void run(std::size_t n, const RangeBody& body) {
    {
      std::lock_guard lock(m_);
      body_ = &body;
      n_ = n;
      // ~8 chunks per worker: balance when another process takes a core for a while.
      chunk_ = std::max<std::size_t>(1, n / (workers_ * 8));
      next_.store(0);
      two_ends_ = workers_ == 2 && n <= 0xffffffffu;
      if (two_ends_) ends_.store(static_cast<std::uint64_t>(n) << 32);  // front 0, back n
      open_ = true;
      joined_ = 0;
      error_ = nullptr;
      ++generation_;
    }
    wake_.notify_all();
    drain(0);
    std::unique_lock lock(m_);
    open_ = false;  // no chunk is left: workers that wake from now on stay out of this run
    done_.wait(lock, [this] { return joined_ == 0; });
    body_ = nullptr;
    if (error_) std::rethrow_exception(error_);
  }

 private:
  void loop(std::size_t w) {
    std::uint64_t seen = 0;
    for (;;) {
      {
        std::unique_lock lock(m_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        if (!open_) continue;  // woke too late for this run
        ++joined_;
      }
      drain(w);
      {
        std::lock_guard lock(m_);
        --joined_;
      }
      done_.notify_one();
    }
  }

  void drain(std::size_t w) {
    t_in_body = true;
    try {
      if (two_ends_) {
        std::size_t begin = 0, end = 0;
        while (take_from_end(w == 0, begin, end)) (*body_)(begin, end, w);
      } else {
        for (;;) {
          const std::size_t begin = next_.fetch_add(chunk_);
          if (begin >= n_) break;
          (*body_)(begin, std::min(n_, begin + chunk_), w);
        }
      }
    } catch (...) {
      std::lock_guard lock(m_);
      if (!error_) error_ = std::current_exception();
      next_.store(n_);  // the others stop taking chunks
      ends_.store(0u);  // (two ends: they meet)
    }
    t_in_body = false;
  }

  // Two workers: the caller takes chunks from the front of [0, n), the other worker from the back, until
  // they meet. Index i is then handled by the same core from loop to loop and from tick to tick (the
  // meeting point moves a little), so a robot's controller, inbox and scratch stay in that core's cache;
  // handing chunks out in one order sent them to either core at random, and the CPU time at N = 100 was
  // 1.4x that of one worker (caches warmed twice, lines bouncing). ends_ packs front (low 32 bits) and
  // back (high 32 bits).
  bool take_from_end(bool front, std::size_t& begin, std::size_t& end) {
    std::uint64_t ends = ends_.load(std::memory_order_relaxed);
    for (;;) {
      const std::uint64_t lo = ends & 0xffffffffu, hi = ends >> 32;
      if (lo >= hi) return false;
      const std::uint64_t take = std::min<std::uint64_t>(chunk_, hi - lo);
      const std::uint64_t next = front ? ((hi << 32) | (lo + take)) : (((hi - take) << 32) | lo);
      if (ends_.compare_exchange_weak(ends, next, std::memory_order_acq_rel, std::memory_order_relaxed)) {
        begin = static_cast<std::size_t>(front ? lo : hi - take);
        end = static_cast<std::size_t>(front ? lo + take : hi);
        return true;
      }
    }
  }

  const std::size_t workers_;
  std::mutex m_;
  std::condition_variable wake_, done_;
  std::uint64_t generation_ = 0;
  std::size_t joined_ = 0;  // workers other than the caller inside the current run
  bool open_ = false;       // the current run still takes workers
  bool stop_ = false;
  const RangeBody* body_ = nullptr;
  std::size_t n_ = 0, chunk_ = 1;
  std::atomic<std::size_t> next_{0};
  bool two_ends_ = false;
  std::atomic<std::uint64_t> ends_{0};  // two workers: front and back of what is left (take_from_end)
  std::exception_ptr error_;
  std::vector<std::jthread> threads_;  // last: joined before the members above go
};

std::mutex g_run;             // one run at a time across the process
std::size_t g_requested = 0;  // 0: default
std::unique_ptr<Pool> g_pool;

std::size_t wanted() {
  return g_requested != 0 ? g_requested : default_workers();
}

}  // namespace

std::size_t worker_count() {
  std::lock_guard lock(g_run);
  return wanted();
}

void set_worker_count(std::size_t workers) {
  std::lock_guard lock(g_run);
  g_requested = workers;
  if (g_pool && g_pool->size() != wanted()) g_pool.reset();
}

void for_range(std::size_t n, const RangeBody& body, std::size_t min_per_worker) {
  if (n == 0) return;
  if (t_in_body || n < 2 * std::max<std::size_t>(1, min_per_worker)) {
    body(0, n, 0);
    return;
  }
  std::lock_guard lock(g_run);
  const std::size_t workers = wanted();
  if (workers <= 1) {
    body(0, n, 0);
    return;
  }
  if (!g_pool || g_pool->size() != workers) g_pool = std::make_unique<Pool>(workers);
  g_pool->run(n, body);
}

}  // namespace swarmform::parallel
