// A minimal parallel loop for CPU passes over images (distance transforms, resolves, mips).
// Work is split into contiguous chunks, one per hardware thread; each index must write only its
// own outputs, so results are identical to a serial loop whatever the thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace puff::core {

/// Calls fn(i) for every i in [0, n), on up to std::thread::hardware_concurrency() threads.
/// `minPerThread` keeps tiny loops serial, where starting threads would cost more than it saves.
template <class Fn>
void parallelFor(std::size_t n, Fn&& fn, std::size_t minPerThread = 16) {
  const std::size_t hw = std::max(1u, std::thread::hardware_concurrency());
  const std::size_t threads = std::min(hw, std::max<std::size_t>(1, n / std::max<std::size_t>(1, minPerThread)));
  if (threads <= 1) {
    for (std::size_t i = 0; i < n; ++i) fn(i);
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(threads - 1);
  const std::size_t chunk = (n + threads - 1) / threads;
  for (std::size_t t = 1; t < threads; ++t) {
    pool.emplace_back([&fn, t, chunk, n] {
      for (std::size_t i = t * chunk; i < std::min(n, (t + 1) * chunk); ++i) fn(i);
    });
  }
  for (std::size_t i = 0; i < std::min(n, chunk); ++i) fn(i);
  for (auto& th : pool) th.join();
}

}  // namespace puff::core
