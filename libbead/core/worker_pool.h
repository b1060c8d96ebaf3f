// WorkerPool: a fixed set of threads that run the items of a job in
// parallel, the caller's thread among them. Created once and reused job
// after job (a stream of archive windows), so no thread is started per
// window. An exception thrown by an item is rethrown by Run() on the
// caller's thread (the first one; the job's other items still finish).
#pragma once

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace bead {

class WorkerPool {
 public:
  // threads: how many run items, the caller's included (0: all cores).
  explicit WorkerPool(unsigned threads = 0);
  ~WorkerPool();
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;

  unsigned size() const { return static_cast<unsigned>(workers_.size()) + 1; }

  // Calls item(i, worker) for every i in [0, count), each once; `worker`
  // in [0, size()) names the thread (for per-thread scratch). Returns when
  // all are done.
  void Run(std::size_t count, const std::function<void(std::size_t, unsigned)>& item);

 private:
  void Work(unsigned worker);
  void Drain(unsigned worker);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_, idle_;
  const std::function<void(std::size_t, unsigned)>* item_ = nullptr;
  std::size_t count_ = 0, next_ = 0;
  unsigned busy_ = 0;
  std::size_t generation_ = 0;
  bool stop_ = false;
  std::exception_ptr error_;
};

}  // namespace bead
