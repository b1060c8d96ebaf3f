#include "libbead/core/worker_pool.h"

#include <algorithm>

namespace bead {

WorkerPool::WorkerPool(unsigned threads) {
  if (threads == 0) threads = std::max(1u, std::thread::hardware_concurrency());
  for (unsigned w = 1; w < threads; ++w) workers_.emplace_back([this, w] { Work(w); });
}

WorkerPool::~WorkerPool() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

// Takes items until none is left; mutex_ is not held while an item runs.
void WorkerPool::Drain(unsigned worker) {
  std::unique_lock<std::mutex> lock(mutex_);
  while (next_ < count_) {
    const std::size_t i = next_++;
    const auto* item = item_;
    lock.unlock();
    try {
      (*item)(i, worker);
    } catch (...) {
      lock.lock();
      if (!error_) error_ = std::current_exception();
      continue;
    }
    lock.lock();
  }
}

void WorkerPool::Work(unsigned worker) {
  std::size_t seen = 0;
  while (true) {
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      ++busy_;
    }
    Drain(worker);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      --busy_;
    }
    idle_.notify_all();
  }
}

void WorkerPool::Run(std::size_t count, const std::function<void(std::size_t, unsigned)>& item) {
  if (count == 0) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    item_ = &item;
    count_ = count;
    next_ = 0;
    error_ = nullptr;
    ++generation_;
  }
  if (count > 1) wake_.notify_all();
  Drain(0);
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [&] { return busy_ == 0; });
  item_ = nullptr;
  count_ = 0;
  if (error_) {
    std::exception_ptr e = error_;
    error_ = nullptr;
    std::rethrow_exception(e);
  }
}

}  // namespace bead
