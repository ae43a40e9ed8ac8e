// SPDX-License-Identifier: GPL-3.0-or-later
#include "MassSpringThreads.h"

#include <algorithm>
#include <array>

namespace plantmorph
{

MassSpringThreads::MassSpringThreads(int threads)
{
  if (threads <= 0)
  {
    threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  }
  for (int i = 1; i < threads; ++i)
  {
    this->Workers.emplace_back([this, i] { this->WorkerLoop(static_cast<std::size_t>(i)); });
  }
}

MassSpringThreads::~MassSpringThreads()
{
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Stop = true;
  }
  this->Start.notify_all();
  for (std::thread& worker : this->Workers)
  {
    worker.join();
  }
}

void MassSpringThreads::WorkerLoop(std::size_t index)
{
  std::size_t seen = 0;
  for (;;)
  {
    const std::function<void(std::size_t)>* task = nullptr;
    std::size_t count = 0;
    {
      std::unique_lock<std::mutex> lock(this->Mutex);
      this->Start.wait(lock, [&] { return this->Stop || this->Generation != seen; });
      if (this->Stop)
      {
        return;
      }
      seen = this->Generation;
      task = this->Task;
      count = this->TaskCount;
    }
    // Task t goes to thread t % threads: a fixed assignment.
    const std::size_t threads = this->Workers.size() + 1;
    for (std::size_t t = index; t < count; t += threads)
    {
      (*task)(t);
    }
    {
      std::lock_guard<std::mutex> lock(this->Mutex);
      if (--this->Pending == 0)
      {
        this->Done.notify_one();
      }
    }
  }
}

void MassSpringThreads::Run(std::size_t tasks, const std::function<void(std::size_t)>& task)
{
  if (this->Workers.empty() || tasks <= 1)
  {
    for (std::size_t t = 0; t < tasks; ++t)
    {
      task(t);
    }
    return;
  }
  {
    std::lock_guard<std::mutex> lock(this->Mutex);
    this->Task = &task;
    this->TaskCount = tasks;
    this->Pending = this->Workers.size();
    ++this->Generation;
  }
  this->Start.notify_all();
  const std::size_t threads = this->Workers.size() + 1;
  for (std::size_t t = 0; t < tasks; t += threads)
  {
    task(t);
  }
  std::unique_lock<std::mutex> lock(this->Mutex);
  this->Done.wait(lock, [&] { return this->Pending == 0; });
  this->Task = nullptr;
}

void MassSpringThreads::For(std::size_t n, const std::function<void(std::size_t, std::size_t)>& fn)
{
  const std::size_t threads = this->Workers.size() + 1;
  if (threads == 1 || n < 2048)
  {
    if (n > 0)
    {
      fn(0, n);
    }
    return;
  }
  const std::function<void(std::size_t)> task = [&](std::size_t t) {
    const std::size_t begin = n * t / threads;
    const std::size_t end = n * (t + 1) / threads;
    if (begin < end)
    {
      fn(begin, end);
    }
  };
  this->Run(threads, task);
}

double MassSpringThreads::Sum(std::size_t n, const std::function<double(std::size_t, std::size_t)>& fn)
{
  std::array<double, ReduceChunks> partial{};
  const std::function<void(std::size_t)> task = [&](std::size_t c) {
    const std::size_t begin = n * c / ReduceChunks;
    const std::size_t end = n * (c + 1) / ReduceChunks;
    partial[c] = begin < end ? fn(begin, end) : 0.0;
  };
  if (this->Workers.empty() || n < 2048)
  {
    for (std::size_t c = 0; c < ReduceChunks; ++c)
    {
      task(c);
    }
  }
  else
  {
    this->Run(ReduceChunks, task);
  }
  double sum = 0.0;
  for (double p : partial)
  {
    sum += p;
  }
  return sum;
}

} // namespace plantmorph
