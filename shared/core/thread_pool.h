#ifndef FLEETMAP_SHARED_CORE_THREAD_POOL_H_
#define FLEETMAP_SHARED_CORE_THREAD_POOL_H_

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace fleetmap {

// A fixed set of worker threads that runs one index-parallel loop at a time. The particle
// filters hand it their per-particle work, the merge engine its independent map searches;
// which thread runs which index never affects the result, because every index owns its own
// state (and random stream) and writes only its own output.
class ThreadPool {
 public:
  // `threads` <= 1 runs everything on the calling thread.
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  // Calls body(i) for every i in [0, count) and returns when all are done. The calling thread
  // takes part. Not reentrant.
  void ParallelFor(size_t count, const std::function<void(size_t)>& body);

 private:
  void WorkerLoop();
  void RunChunk();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable work_ready_;
  std::condition_variable work_done_;
  const std::function<void(size_t)>* body_ = nullptr;
  size_t count_ = 0;
  size_t next_ = 0;
  size_t finished_ = 0;
  int64_t generation_ = 0;
  bool stop_ = false;
};

}  // namespace fleetmap

#endif  // FLEETMAP_SHARED_CORE_THREAD_POOL_H_
