#include "stridemap/live/live_mapping.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

// Poses held at once without allocating: 40 s of a 200 Hz estimator.
constexpr std::size_t kPosesReserved = 8192;

}  // namespace

double live_host_seconds() {
  return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

double live_monotonic_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double live_process_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

void LiveMappingOptions::validate() const {
  const auto positive = [](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw InputError(std::string("live mapping options: ") + name + " must be a positive number of seconds");
    }
  };
  positive(save_every_s, "save_every_s");
  positive(save_retry_s, "save_retry_s");
  positive(status_every_s, "status_every_s");
  if (!(pose_wait_s >= 0.0) || !std::isfinite(pose_wait_s)) {
    throw InputError("live mapping options: pose_wait_s must be >= 0 s");
  }
  if (!(duration_s >= 0.0) || !std::isfinite(duration_s)) {
    throw InputError("live mapping options: duration_s must be >= 0 s (0: no limit)");
  }
  if (!(max_pose_gap_s > 0.0)) throw InputError("live mapping options: max_pose_gap_s must be positive");
  if (max_poses_ahead == 0) throw InputError("live mapping options: max_poses_ahead must be positive");
}

LiveMapping::LiveMapping(const LiveMappingOptions& options, LiveScanSource& scans, LivePoseSource& poses,
                         LiveMappingHooks hooks)
    : options_((options.validate(), options)),
      scans_(scans),
      poses_(poses),
      hooks_(std::move(hooks)),
      sensor_(scans.parameters()),
      mapper_(options.mapper, scip::to_urg_parameters(sensor_)),
      track_(options.max_pose_gap_s) {
  // Scans wait at most pose_wait_s for their poses (then expire), and poses
  // run ahead of them by about as long: room for that, and some, from the
  // start, so that a slow moment later (a loaded host) allocates nothing.
  const double scans_per_s = std::max(1.0, sensor_.motor_speed_rpm / 60.0);
  const auto waiting = static_cast<std::size_t>(std::ceil((options_.pose_wait_s + 1.0) * scans_per_s)) + 16;
  mapper_.reserve(waiting);
  receive_times_.reserve(waiting);
  track_.reserve(kPosesReserved);
}

LiveMapping::LiveMapping(const LiveMappingOptions& options, LiveScanSource& scans, LivePoseSource& poses,
                         MapSaver& saver, LiveMappingHooks hooks)
    : LiveMapping(options, scans, poses, std::move(hooks)) {
  saver_ = &saver;
}

double LiveMapping::scan_time(const UrgScan& scan) const {
  return options_.clock == LiveClock::sensor ? sensor_time_seconds(scan.sensor_time_ms) : scan.host_time_s;
}

void LiveMapping::emit(LiveEvent::Kind kind, std::string message, const UrgDriverEvent* event) {
  if (!hooks_.on_event) return;
  LiveEvent e;
  e.kind = kind;
  e.message = std::move(message);
  e.driver_event = event;
  hooks_.on_event(e);
}

void LiveMapping::poll_poses() {
  if (poses_.poll(track_) > 0) {
    if (pose_times_.count == 0) pose_times_.add(track_.first_time_s());
    pose_times_.add(track_.last_time_s());
  }
  for (std::string& notice : poses_.take_notices()) emit(LiveEvent::Kind::pose_notice, std::move(notice));
}

void LiveMapping::tell_tile_notices() {
  for (std::string& notice : mapper_.take_tile_notices()) emit(LiveEvent::Kind::warning, std::move(notice));
}

bool LiveMapping::try_save(const LiveRunStats* run) {
  if (!saver_ && !hooks_.save) return true;
  try {
    if (saver_) {
      saver_->info().pose_lines_skipped = poses_.skipped_lines();
      saver_->save(mapper_, sensor_, run);
    } else {
      hooks_.save(mapper_, run);
    }
  } catch (const InputError& e) {
    ++save_failures_;
    last_save_error_ = e.what();
    save_failing_ = true;
    emit(LiveEvent::Kind::save_failed, last_save_error_);
    return false;
  }
  ++saves_;
  last_save_error_.clear();
  if (save_failing_) emit(LiveEvent::Kind::save_recovered, "the map is saved again");
  save_failing_ = false;
  return true;
}

namespace {

constexpr double kLatencyFloorS = 1e-6;
constexpr double kLatencyBinRatio = 1.01;
constexpr std::size_t kLatencyBins = 2083;  // 1.01^2083 > 1e9: up to 1000 s

std::size_t latency_bin(double latency_s) {
  if (!(latency_s > kLatencyFloorS)) return 0;
  const double bin = std::log(latency_s / kLatencyFloorS) / std::log(kLatencyBinRatio);
  return std::min(kLatencyBins - 1, static_cast<std::size_t>(bin));
}

}  // namespace

// Scans leave the mapper's queue in order; the ones integrated count for latency.
void LiveMapping::account(std::size_t integrated_before) {
  const std::size_t queued = receive_times_.size();
  const std::size_t consumed = queued - std::min(queued, mapper_.waiting());
  const std::size_t integrated = mapper_.stats().integrated - integrated_before;
  const double now = live_host_seconds();
  if (latency_bins_.empty()) latency_bins_.assign(kLatencyBins, 0);
  for (std::size_t i = 0; i < consumed; ++i) {
    // process() integrates before expire() skips, so the first ones are the integrated.
    if (i < integrated) {
      const double latency_s = now - receive_times_.front();
      ++latency_bins_[latency_bin(latency_s)];
      ++latency_count_;
      latency_sum_s_ += latency_s;
      latency_max_s_ = latency_count_ == 1 ? latency_s : std::max(latency_max_s_, latency_s);
    }
    receive_times_.pop_front();
  }
}

LiveRunStats LiveMapping::run_stats() const {
  LiveRunStats run;
  run.duration_s = live_monotonic_seconds() - start_s_;
  run.cpu_s = live_process_cpu_seconds() - cpu_start_s_;
  run.driver = scans_.stats();
  run.saves = saves_;
  run.save_failures = save_failures_;
  run.pose_reopens = poses_.reopened();
  run.latency_samples = latency_count_;
  if (latency_count_ > 0) {
    run.latency_mean_s = latency_sum_s_ / static_cast<double>(latency_count_);
    run.latency_max_s = latency_max_s_;
    // The 99th percentile's bin, by its upper edge (at most 1 % high), never above the largest.
    const std::uint64_t rank =
        std::min(latency_count_ - 1, static_cast<std::uint64_t>(0.99 * static_cast<double>(latency_count_)));
    std::uint64_t seen = 0;
    for (std::size_t b = 0; b < latency_bins_.size(); ++b) {
      seen += latency_bins_[b];
      if (seen > rank) {
        run.latency_p99_s = std::min(latency_max_s_, kLatencyFloorS * std::pow(kLatencyBinRatio, static_cast<double>(b) + 1.0));
        break;
      }
    }
  }
  return run;
}

LiveMappingResult LiveMapping::run(const std::atomic<bool>& stop) {
  LiveMappingResult result;
  cpu_start_s_ = live_process_cpu_seconds();
  start_s_ = live_monotonic_seconds();
  double next_save = start_s_ + options_.save_every_s;
  double next_status = start_s_ + options_.status_every_s;
  UrgDriverEvent event;
  while (!stop.load() && result.fatal.empty()) {
    const double now = live_monotonic_seconds();
    if (options_.duration_s > 0.0 && now - start_s_ >= options_.duration_s) break;
    // Counted as handed out, not as the driver queues them.
    if (options_.max_scans > 0 && mapper_.stats().scans >= options_.max_scans && mapper_.waiting() == 0) break;
    if (now >= next_save) {
      // A failed save (disk full) is retried soon; mapping goes on meanwhile.
      next_save = now + (try_save(nullptr) ? options_.save_every_s : options_.save_retry_s);
    }
    if (now >= next_status) {
      emit(LiveEvent::Kind::status, {});
      next_status = now + options_.status_every_s;
    }
    poll_poses();
    const std::size_t integrated_before = mapper_.stats().integrated;
    const bool room = options_.max_scans == 0 || mapper_.stats().scans < options_.max_scans;
    if (scans_.next(event, 0.05)) {
      switch (event.kind) {
        case UrgDriverEvent::Kind::scan: {
          if (!room) break;  // beyond --max-scans: neither mapped nor recorded
          if (hooks_.on_scan) hooks_.on_scan(event.scan);
          // Into the kept scan's storage: no allocation per scan.
          raw_ = event.scan.raw;
          raw_.time_s = scan_time(event.scan);
          scan_times_.add(raw_.time_s);
          mapper_.add(raw_, now);
          receive_times_.push_back(event.scan.host_receive_time_s);
          poll_poses();
          break;
        }
        case UrgDriverEvent::Kind::fault:
          emit(LiveEvent::Kind::fault, event.message, &event);
          break;
        case UrgDriverEvent::Kind::connected:
          emit(LiveEvent::Kind::connected, event.message, &event);
          if (!(scans_.parameters() == sensor_)) {
            result.fatal = "another sensor answered after the reconnection (" + scans_.parameters().model +
                           "); restart live mapping for it";
          }
          break;
      }
    }
    mapper_.process(track_, false);
    tell_tile_notices();
    mapper_.expire(now - options_.pose_wait_s);
    account(integrated_before);
    if (track_.size() > options_.max_poses_ahead) {
      // Poses far ahead of every scan: the clocks do not match. Keep memory bounded and say so once.
      if (!warned_clock_) {
        emit(LiveEvent::Kind::warning,
             std::to_string(track_.size()) + " poses and no scan within their times; do the poses use the clock "
             "of the scans (" + std::string(options_.clock == LiveClock::sensor ? "sensor" : "host") + ")?");
        warned_clock_ = true;
      }
      track_.drop_before(track_.last_time_s() - 60.0);
    }
  }
  scans_.stop();
  // The end: poses are complete now, as they are for a replay of the same data.
  poll_poses();
  const std::size_t integrated_before = mapper_.stats().integrated;
  mapper_.process(track_, true);
  account(integrated_before);
  mapper_.finish();
  tell_tile_notices();
  // The last save matters most: a few tries before giving up.
  for (int attempt = 0; attempt < 3; ++attempt) {
    result.run = run_stats();
    if (try_save(&result.run)) break;
  }
  result.run = run_stats();
  result.last_save_error = last_save_error_;
  return result;
}

}  // namespace stridemap
