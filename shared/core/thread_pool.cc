#include "shared/core/thread_pool.h"

namespace fleetmap {

ThreadPool::ThreadPool(int threads) {
  for (int i = 1; i < threads; ++i) workers_.emplace_back([this] { WorkerLoop(); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  work_ready_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void ThreadPool::ParallelFor(size_t count, const std::function<void(size_t)>& body) {
  if (workers_.empty() || count <= 1) {
    for (size_t i = 0; i < count; ++i) body(i);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    body_ = &body;
    count_ = count;
    next_ = 0;
    finished_ = 0;
    ++generation_;
  }
  work_ready_.notify_all();
  RunChunk();
  std::unique_lock<std::mutex> lock(mutex_);
  work_done_.wait(lock, [this] { return finished_ == count_; });
  body_ = nullptr;
}

// Takes indices one at a time until none are left.
void ThreadPool::RunChunk() {
  while (true) {
    size_t index;
    const std::function<void(size_t)>* body;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (body_ == nullptr || next_ >= count_) return;
      index = next_++;
      body = body_;
    }
    (*body)(index);
    bool all_done;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      all_done = ++finished_ == count_;
    }
    if (all_done) work_done_.notify_all();
  }
}

void ThreadPool::WorkerLoop() {
  int64_t seen = 0;
  while (true) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      work_ready_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
    }
    RunChunk();
  }
}

}  // namespace fleetmap
