#pragma once
// How a long loop of the library (an experiment, a log import, a soak) says
// how far it is, without knowing who listens: a plain callback in its
// options struct. The tool draws a progress bar from it on a terminal
// (apps/stridemap/progress_bar.hpp); a script or a binding may log it or ignore it.
#include <cstddef>
#include <functional>

namespace stridemap {

/// Called with the work done so far and the whole (in the loop's own units:
/// scans, configurations, seconds of simulated walk); `total` 0 when not
/// known in advance. Called from the loop's own thread, possibly once per
/// step, so it must be cheap; an empty function is never called.
using ProgressCallback = std::function<void(std::size_t done, std::size_t total)>;

/// For a loop made of `parts` runs of about the same size (an experiment's
/// cases): the callback for run `part` (from 0), which reports to `whole`
/// as if the runs were one loop, so a bar fills once instead of once per
/// run. Empty when `whole` is.
inline ProgressCallback progress_of_part(const ProgressCallback& whole, std::size_t part, std::size_t parts) {
  if (!whole) return {};
  return [whole, part, parts](std::size_t done, std::size_t total) {
    if (total == 0) {
      whole(part, parts);
    } else {
      whole(part * total + done, parts * total);
    }
  };
}

}  // namespace stridemap
