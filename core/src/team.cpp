#include "shore/core/team.h"

namespace shore {

Team::Team(int threads) {
  for (int k = 1; k < threads; ++k) workers_.emplace_back([this, k] { work(k); });
}

Team::~Team() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void Team::drain(std::uint32_t generation, int items, Job& job, int slot) {
  std::uint64_t c = claim_.load(std::memory_order_acquire);
  for (;;) {
    if (static_cast<std::uint32_t>(c >> 32) != generation || static_cast<int>(c & 0xffffffffu) >= items) return;
    if (!claim_.compare_exchange_weak(c, c + 1, std::memory_order_acq_rel)) continue;
    job(static_cast<int>(c & 0xffffffffu), slot);
    if (done_.fetch_add(1, std::memory_order_acq_rel) + 1 == items) done_.notify_one();
    c = claim_.load(std::memory_order_acquire);
  }
}

void Team::work(int slot) {
  std::uint32_t seen = 0;
  for (;;) {
    std::uint32_t generation = 0;
    int items = 0;
    Job* job = nullptr;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation = generation_;
      items = items_;
      job = job_;
    }
    drain(generation, items, *job, slot);
  }
}

void Team::run(int items, Job& job) {
  if (items <= 0) return;
  std::uint32_t generation = 0;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    generation = ++generation_;
    items_ = items;
    job_ = &job;
    done_.store(0, std::memory_order_relaxed);
    claim_.store(static_cast<std::uint64_t>(generation) << 32, std::memory_order_release);
  }
  if (!workers_.empty()) wake_.notify_all();
  drain(generation, items, job, 0);
  // Only items already taken by a worker are left: wait for them, briefly spinning, then
  // sleeping on the counter.
  for (int spin = 0; spin < 256; ++spin)
    if (done_.load(std::memory_order_acquire) == items) return;
  for (int d = done_.load(std::memory_order_acquire); d != items; d = done_.load(std::memory_order_acquire))
    done_.wait(d, std::memory_order_acquire);
}

}  // namespace shore
