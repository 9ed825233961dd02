// Private to puff::sim: a small persistent thread pool for the simulator's step. Starting threads
// every step would cost more than it saves: on the project's 2-core VM one std::thread start and
// join took a median 25 us and a 90th percentile of 4 ms (the scheduler was busy), against a step
// of about 1 ms. The pool starts its threads once; a step wakes them with one notify, and waits
// only for those that woke while the caller was working.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

namespace puff::sim::detail {

class Workers {
 public:
  /// `threads` >= 1 in all, counting the caller: threads - 1 are started.
  explicit Workers(int threads) {
    pool_.reserve(static_cast<std::size_t>(threads > 1 ? threads - 1 : 0));
    for (int t = 1; t < threads; ++t) pool_.emplace_back([this, t] { loop(t); });
  }
  ~Workers() {
    {
      std::lock_guard<std::mutex> lock(m_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& th : pool_) th.join();
  }
  Workers(const Workers&) = delete;
  Workers& operator=(const Workers&) = delete;

  int threads() const { return static_cast<int>(pool_.size()) + 1; }

  /// Calls fn(t) for t = 0 on the calling thread and for t in [1, count) (count <= threads()) on
  /// the pool threads that wake before fn(0) returns; returns when every call made has returned.
  /// So `fn` must share its work out dynamically (a thread the scheduler wakes late does none of
  /// it) and must not throw.
  template <class Fn>
  void run(int count, Fn&& fn) {
    if (count <= 1 || pool_.empty()) {
      fn(0);
      return;
    }
    using F = std::remove_reference_t<Fn>;
    {
      std::lock_guard<std::mutex> lock(m_);
      call_ = [](void* ctx, int t) { (*static_cast<F*>(ctx))(t); };
      ctx_ = const_cast<void*>(static_cast<const void*>(&fn));
      count_ = count;
      open_ = true;
      taken_ = finished_ = 0;
      ++generation_;
    }
    wake_.notify_all();
    fn(0);
    std::unique_lock<std::mutex> lock(m_);
    open_ = false;  // threads not awake yet skip this round
    done_.wait(lock, [this] { return finished_ == taken_; });
  }

 private:
  void loop(int t) {
    std::uint64_t seen = 0;
    for (;;) {
      void (*call)(void*, int) = nullptr;
      void* ctx = nullptr;
      {
        std::unique_lock<std::mutex> lock(m_);
        wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
        if (stop_) return;
        seen = generation_;
        if (!open_ || t >= count_) continue;  // too late, or this round needs fewer threads
        ++taken_;
        call = call_, ctx = ctx_;
      }
      call(ctx, t);
      bool last = false;
      {
        std::lock_guard<std::mutex> lock(m_);
        last = ++finished_ == taken_ && !open_;
      }
      if (last) done_.notify_one();
    }
  }

  std::mutex m_;
  std::condition_variable wake_, done_;
  std::uint64_t generation_ = 0;
  int count_ = 0, taken_ = 0, finished_ = 0;
  bool open_ = false, stop_ = false;
  void (*call_)(void*, int) = nullptr;
  void* ctx_ = nullptr;
  std::vector<std::thread> pool_;
};

}  // namespace puff::sim::detail
