// Private to puff::sim: a small persistent thread pool for the simulator's step. Starting threads
// every step would cost more than it saves: on the project's 2-core VM one std::thread start and
// join took a median 25 us and a 90th percentile of 4 ms (the scheduler was busy), against a step
// of about 1 ms. The pool starts its threads once. Waking a sleeping thread costs tens of
// microseconds on a VM, so a thread that finishes a job watches for the next one for a short
// while (kSpin) before it sleeps, and so does the caller waiting for the last job to finish:
// steps that follow each other closely (a simulation run) never sleep.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <thread>
#include <type_traits>
#include <vector>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace puff::sim::detail {

class Workers {
 public:
  /// `threads` >= 1 in all, counting the caller: threads - 1 are started.
  explicit Workers(int threads) {
    pool_.reserve(static_cast<std::size_t>(threads > 1 ? threads - 1 : 0));
    for (int t = 1; t < threads; ++t) pool_.emplace_back([this, t] { loop(t); });
  }
  ~Workers() {
    stop_.store(true, std::memory_order_release);
    { std::lock_guard<std::mutex> lock(m_); }
    wake_.notify_all();
    for (std::thread& th : pool_) th.join();
  }
  Workers(const Workers&) = delete;
  Workers& operator=(const Workers&) = delete;

  int threads() const { return static_cast<int>(pool_.size()) + 1; }

  /// Calls fn(t) for t = 0 on the calling thread and for t in [1, count) (count <= threads()) on
  /// the pool threads that pick the job up before fn(0) returns; returns when every call made has
  /// returned. So `fn` must share its work out dynamically (a thread the scheduler runs late does
  /// none of it) and must not throw.
  template <class Fn>
  void run(int count, Fn&& fn) {
    if (count <= 1 || pool_.empty()) {
      fn(0);
      return;
    }
    using F = std::remove_reference_t<Fn>;
    call_.store([](void* ctx, int t) { (*static_cast<F*>(ctx))(t); }, std::memory_order_relaxed);
    ctx_.store(const_cast<void*>(static_cast<const void*>(&fn)), std::memory_order_relaxed);
    count_.store(count, std::memory_order_relaxed);
    finished_.store(0, std::memory_order_relaxed);
    epoch_ = static_cast<std::uint32_t>(epoch_ + 1);
    job_.store(static_cast<std::uint64_t>(epoch_) << 32, std::memory_order_release);  // open, no claims
    { std::lock_guard<std::mutex> lock(m_); }  // a thread between its check and its sleep sees the job
    wake_.notify_all();
    fn(0);
    // Close the job: threads that have not claimed it by now skip it.
    const auto taken = static_cast<std::uint32_t>(job_.fetch_or(kClosed, std::memory_order_acq_rel) & kClaims);
    const auto done = [&] { return finished_.load(std::memory_order_acquire) >= taken; };
    if (spinUntil(done)) return;
    std::unique_lock<std::mutex> lock(m_);
    done_.wait(lock, done);
  }

 private:
  static constexpr std::uint64_t kClosed = 1ULL << 31, kClaims = kClosed - 1;
  static constexpr std::chrono::microseconds kSpin{200};

  // Polls `ready` for up to kSpin; whether it became true.
  template <class Ready>
  static bool spinUntil(const Ready& ready) {
    const auto until = std::chrono::steady_clock::now() + kSpin;
    for (int i = 0;; ++i) {
      if (ready()) return true;
#if defined(__x86_64__) || defined(__i386__)
      _mm_pause();
#endif
      if ((i & 63) == 63 && std::chrono::steady_clock::now() > until) return ready();
    }
  }

  void loop(int t) {
    std::uint32_t seen = 0;  // the last job's epoch this thread looked at
    for (;;) {
      const auto fresh = [&] {
        return stop_.load(std::memory_order_acquire) ||
               static_cast<std::uint32_t>(job_.load(std::memory_order_acquire) >> 32) != seen;
      };
      if (!spinUntil(fresh)) {
        std::unique_lock<std::mutex> lock(m_);
        wake_.wait(lock, fresh);
      }
      if (stop_.load(std::memory_order_acquire)) return;
      // Claim the open job (one more claim in its word), unless it is closed or needs fewer threads.
      std::uint64_t word = job_.load(std::memory_order_acquire);
      bool claimed = false;
      for (;;) {
        if ((word & kClosed) || t >= count_.load(std::memory_order_relaxed)) break;
        if (job_.compare_exchange_weak(word, word + 1, std::memory_order_acq_rel, std::memory_order_acquire)) {
          claimed = true;
          break;
        }
      }
      seen = static_cast<std::uint32_t>(word >> 32);
      if (!claimed) continue;
      call_.load(std::memory_order_relaxed)(ctx_.load(std::memory_order_relaxed), t);
      finished_.fetch_add(1, std::memory_order_acq_rel);
      { std::lock_guard<std::mutex> lock(m_); }  // the caller, if asleep, checked before this
      done_.notify_one();
    }
  }

  // The job: epoch (high 32 bits), closed flag (bit 31), claims (low bits).
  std::atomic<std::uint64_t> job_{0};
  std::uint32_t epoch_ = 0;  // the caller's count of jobs
  std::atomic<void (*)(void*, int)> call_{nullptr};
  std::atomic<void*> ctx_{nullptr};
  std::atomic<int> count_{0};
  std::atomic<std::uint32_t> finished_{0};
  std::atomic<bool> stop_{false};
  std::mutex m_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> pool_;
};

}  // namespace puff::sim::detail
