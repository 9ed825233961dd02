// Private to puff::sim: a small persistent thread pool for the simulator's step. Starting threads
// every step would cost more than it saves: on the project's 2-core VM one std::thread start and
// join took a median 25 us and a 90th percentile of 4 ms (the scheduler was busy), against a step
// of about 1 ms. The pool starts its threads once; a step wakes them with one notify and waits for
// them with another.
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

  /// Calls fn(t) for every t in [0, count) (count <= threads()), t = 0 on the calling thread, the
  /// others on the pool; returns when every call has. `fn` must not throw.
  template <class Fn>
  void run(int count, Fn&& fn) {
    if (count <= 1) {
      fn(0);
      return;
    }
    using F = std::remove_reference_t<Fn>;
    {
      std::lock_guard<std::mutex> lock(m_);
      call_ = [](void* ctx, int t) { (*static_cast<F*>(ctx))(t); };
      ctx_ = const_cast<void*>(static_cast<const void*>(&fn));
      count_ = count;
      pending_ = count - 1;
      ++generation_;
    }
    wake_.notify_all();
    fn(0);
    std::unique_lock<std::mutex> lock(m_);
    done_.wait(lock, [this] { return pending_ == 0; });
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
        if (t >= count_) continue;  // this round needs fewer threads
        call = call_, ctx = ctx_;
      }
      call(ctx, t);
      bool last = false;
      {
        std::lock_guard<std::mutex> lock(m_);
        last = --pending_ == 0;
      }
      if (last) done_.notify_one();
    }
  }

  std::mutex m_;
  std::condition_variable wake_, done_;
  std::uint64_t generation_ = 0;
  int count_ = 0, pending_ = 0;
  bool stop_ = false;
  void (*call_)(void*, int) = nullptr;
  void* ctx_ = nullptr;
  std::vector<std::thread> pool_;
};

}  // namespace puff::sim::detail
