// SPDX-License-Identifier: GPL-3.0-or-later
// A small persistent thread pool for WiltingSimulator's mass-spring system and Newmark integrator (see
// docs/methods/wilting.md). Plain C++17 (std::thread), no VTK: the algorithm layer and the benchmark thread alike.
//
// Determinism: For() hands out a fixed partition of [0, n) and callers only write disjoint outputs from it, so its
// results do not depend on the number of threads. Sum() always cuts [0, n) into the same ReduceChunks pieces, sums
// each piece in index order and then adds the pieces in chunk order, so a reduction is bit-identical whether it runs
// on 1 or 16 threads.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace plantmorph
{

class MassSpringThreads
{
public:
  /// Pieces a reduction is always cut into (independent of the thread count).
  static constexpr std::size_t ReduceChunks = 32;

  /// `threads` <= 0: std::thread::hardware_concurrency() (at least 1). 1: everything runs on the caller's thread.
  explicit MassSpringThreads(int threads = 1);
  ~MassSpringThreads();
  MassSpringThreads(const MassSpringThreads&) = delete;
  MassSpringThreads& operator=(const MassSpringThreads&) = delete;

  int Threads() const { return static_cast<int>(this->Workers.size()) + 1; }

  /// Calls fn(begin, end) over disjoint ranges covering [0, n), in parallel. Small n runs serially.
  void For(std::size_t n, const std::function<void(std::size_t, std::size_t)>& fn);

  /// Calls task(t) for t in [0, count), task t always on the same thread (t modulo the thread count).
  void Tasks(std::size_t count, const std::function<void(std::size_t)>& task) { this->Run(count, task); }

  /// The sum of fn(begin, end) over the ReduceChunks fixed ranges of [0, n), added in chunk order.
  double Sum(std::size_t n, const std::function<double(std::size_t, std::size_t)>& fn);

private:
  void Run(std::size_t tasks, const std::function<void(std::size_t)>& task);
  void WorkerLoop(std::size_t index);

  std::vector<std::thread> Workers;
  std::mutex Mutex;
  std::condition_variable Start;
  std::condition_variable Done;
  const std::function<void(std::size_t)>* Task = nullptr;
  std::size_t TaskCount = 0;
  std::size_t Generation = 0;
  std::size_t Pending = 0;
  bool Stop = false;
};

} // namespace plantmorph
