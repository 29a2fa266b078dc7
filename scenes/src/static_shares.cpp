#include "shore/scenes/static_shares.h"

#include <algorithm>
#include <thread>
#include <vector>

namespace shore::scenes {

void for_static_shares(int threads, std::ptrdiff_t count,
                       const std::function<void(std::ptrdiff_t, std::ptrdiff_t)>& fn) {
  const std::ptrdiff_t n = std::max(1, threads);
  const auto share = [&](std::ptrdiff_t k) { fn(count * k / n, count * (k + 1) / n); };
  std::vector<std::thread> workers;
  for (std::ptrdiff_t k = 1; k < n; ++k) workers.emplace_back(share, k);
  share(0);
  for (std::thread& t : workers) t.join();
}

int hardware_threads() { return std::max(1, static_cast<int>(std::thread::hardware_concurrency())); }

}  // namespace shore::scenes
