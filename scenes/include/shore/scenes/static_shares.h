#pragma once
// Memory-bandwidth measurements (the triads): a loop split into `threads` equal shares, share
// k always on the k-th thread of the call, so the first touch and every later pass of an
// element run on the same share. Plain std::thread (started per call: a triad pass over
// arrays of 100 MB dwarfs a thread start), no OpenMP, so no environment variable changes it.

#include <cstddef>
#include <functional>

namespace shore::scenes {

/// Calls fn(begin, end) for the `threads` equal shares of [0, count), share 0 on the caller;
/// returns when all are done. threads >= 1.
void for_static_shares(int threads, std::ptrdiff_t count,
                       const std::function<void(std::ptrdiff_t, std::ptrdiff_t)>& fn);

/// The machine's hardware threads (at least 1).
int hardware_threads();

}  // namespace shore::scenes
