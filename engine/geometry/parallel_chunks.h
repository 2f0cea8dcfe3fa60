// Deterministic parallel loops over index ranges: [0, n) is cut into
// consecutive chunks, each run on its own thread into its own output, and
// the caller joins the outputs in chunk order. As long as the work on an
// index depends on nothing but that index, the joined result is the same for
// any number of chunks.
#pragma once
#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace anisurf {

// The number of threads the engine's loops may use (a process-wide setting:
// the command line's --threads); 0: one per hardware thread.
inline std::atomic<int>& thread_limit() {
  static std::atomic<int> limit{0};
  return limit;
}

// The threads a loop may use: thread_limit(), or the hardware's.
inline int available_threads() {
  const int limit = thread_limit().load();
  return limit > 0 ? limit : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
}

// How many chunks to cut n indices into: one per available thread, but no
// chunk under min_per_chunk indices (threads cost more than small loops).
inline int chunk_count(int n, int min_per_chunk) {
  return std::clamp(n / std::max(min_per_chunk, 1), 1, available_threads());
}

// Calls work(chunk, begin, end) for `chunks` consecutive ranges covering
// [0, n), the first on the calling thread and the others on threads of
// their own; returns when all are done.
template <class Work>
void run_chunks(int n, int chunks, Work work) {
  auto bounds = [&](int c) { return static_cast<int>(static_cast<long long>(n) * c / chunks); };
  std::vector<std::thread> threads;
  threads.reserve(static_cast<std::size_t>(chunks > 1 ? chunks - 1 : 0));
  for (int c = 1; c < chunks; ++c) threads.emplace_back([&, c] { work(c, bounds(c), bounds(c + 1)); });
  work(0, bounds(0), bounds(1));
  for (std::thread& t : threads) t.join();
}

}  // namespace anisurf
