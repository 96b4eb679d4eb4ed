#pragma once
// The scan log kept while mapping live (`live --record`): what the sensor
// sends, in the order it comes, so that `stridemap map` can make the same
// map again. A failed write never ends the mapping: it ends the recording,
// and the error waits for the end of the run.
#include <cstdint>
#include <memory>
#include <string>

#include "stridemap/live/live_mapping.hpp"
#include "stridemap/recordings/scan_log.hpp"

namespace stridemap {

class ScanRecorder {
 public:
  /// Records nothing.
  ScanRecorder() = default;
  /// Creates (or with `append` adds to) the log at `path` and writes the
  /// connected sensor's description. Throws InputError naming the path: a
  /// log that cannot be started is refused before any mapping.
  ScanRecorder(const std::string& path, const std::string& device, bool append, const LiveScanSource& sensor);

  /// A log is open and no write has failed.
  bool recording() const { return log_ != nullptr && error_.empty(); }

  /// Each returns false when this write failed: error() says why, and
  /// nothing more is written.
  bool scan(const UrgScan& scan);
  /// A fault is recorded as it happened; a (re)connection with the
  /// sensor's description; other events are not the log's.
  bool event(const LiveEvent& event, const LiveScanSource& sensor);
  bool flush();

  /// The first write that failed, empty when none did.
  const std::string& error() const { return error_; }

 private:
  template <typename Write>
  bool attempt(Write&& write);

  std::unique_ptr<io::ScanLogWriter> log_;
  std::string error_;
};

}  // namespace stridemap
