#pragma once
// A team of worker threads shared by the modules (the water's tiles, the soil's rows). No
// OpenMP, so no OMP_WAIT_POLICY or GOMP_SPINCOUNT changes its speed: a game embedding Shore
// sets no environment variable. Idle workers sleep on a condition variable; run()
// wakes them and hands out items one at a time from an atomic counter that the caller
// works through too. A worker that wakes after every item is taken finds none and goes
// back to sleep, so the caller never waits for a thread that has not started: the only
// wait is for items already being worked on.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace shore {

class Team {
 public:
  /// A function of (item, slot): slot 0 is the caller, 1.. the workers.
  struct Job {
    virtual void operator()(int item, int slot) = 0;

   protected:
    ~Job() = default;
  };

  /// threads >= 1: the caller plus threads - 1 workers.
  explicit Team(int threads);
  ~Team();
  Team(const Team&) = delete;
  Team& operator=(const Team&) = delete;

  [[nodiscard]] int size() const noexcept { return static_cast<int>(workers_.size()) + 1; }
  /// Runs job(item, slot) for every item in [0, items) and returns when all are done.
  void run(int items, Job& job);

  template <class Fn>
  void run(int items, Fn&& fn) {
    struct Wrap final : Job {
      explicit Wrap(Fn& target) : fn(target) {}
      void operator()(int item, int slot) override { fn(item, slot); }
      Fn& fn;
    } wrap(fn);
    run(items, static_cast<Job&>(wrap));
  }

 private:
  void work(int slot);
  /// Claims and runs items of `generation` until none are left.
  void drain(std::uint32_t generation, int items, Job& job, int slot);

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable wake_;
  std::uint32_t generation_ = 0;  // guarded by mutex_
  bool stop_ = false;             // guarded by mutex_
  int items_ = 0;                 // guarded by mutex_
  Job* job_ = nullptr;            // guarded by mutex_
  /// (generation << 32) | next item: a claim succeeds only for the current generation.
  std::atomic<std::uint64_t> claim_{0};
  std::atomic<int> done_{0};
};

}  // namespace shore
