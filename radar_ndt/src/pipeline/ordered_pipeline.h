#pragma once
// Internal to the dataset runners: the ordered pipeline both runs use. Items [begin, end) are
// prepared on worker threads, several at a time, and consumed one at a time in index order, so what
// consumes them (the odometry) sees exactly what a single thread would give it.

#include <cstddef>
#include <stdexcept>
#include <string>

#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

namespace radar_ndt {
namespace detail {

/// The number of threads `threads` asks for: itself when positive, every core the process may use
/// when 0.
inline int resolveThreads(int threads) {
  if (threads < 0) throw std::invalid_argument("threads must be >= 0 (0: every core), not " + std::to_string(threads));
  return threads > 0 ? threads : tbb::info::default_concurrency();
}

/// Calls `prepare(k)` for k in [begin, end) on `threads` threads (concurrently; 1: each on the
/// caller's thread just before it is consumed) and `consume(prepared)` with each result in order of
/// k, one call at a time (on any of the threads). An exception from `consume` stops the pipeline and
/// is rethrown; `prepare` reports its failures in what it returns.
template <class Prepared, class Prepare, class Consume>
void runOrdered(std::size_t begin, std::size_t end, int threads, Prepare&& prepare, Consume&& consume) {
  threads = resolveThreads(threads);
  if (threads == 1) {
    for (std::size_t k = begin; k < end; ++k) {
      Prepared p = prepare(k);
      consume(p);
    }
    return;
  }
  // Items in flight: enough to keep every thread preparing while one consumes, few enough that
  // memory does not grow with the sequence.
  const std::size_t tokens = 2 * static_cast<std::size_t>(threads);
  // More threads than cores are allowed when asked for (TBB's default limit is the core count).
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  tbb::task_arena arena(threads);
  arena.execute([&] {
    std::size_t next = begin;
    auto indices = [&](tbb::flow_control& control) -> std::size_t {
      if (next >= end) control.stop();
      return next < end ? next++ : 0;
    };
    tbb::parallel_pipeline(tokens, tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order, indices) &
                                       tbb::make_filter<std::size_t, Prepared>(
                                           tbb::filter_mode::parallel, [&](std::size_t k) { return prepare(k); }) &
                                       tbb::make_filter<Prepared, void>(tbb::filter_mode::serial_in_order,
                                                                        [&](Prepared p) { consume(p); }));
  });
}

}  // namespace detail
}  // namespace radar_ndt
