#include "stridemap/preprocess/scan_filter_chain.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "scan_copy.hpp"
#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr std::array<std::pair<std::string_view, ScanFilterKind>, 4> kind_names{{
    {"range-clustering", ScanFilterKind::range_clustering},
    {"scan-sequence", ScanFilterKind::scan_sequence},
    {"shadow", ScanFilterKind::shadow},
    {"speckle", ScanFilterKind::speckle},
}};

constexpr std::string_view valid_names =
    "range-clustering, scan-sequence, shadow, speckle, paper (= range-clustering,scan-sequence), none";

std::string_view trim(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

}  // namespace

std::string_view scan_filter_name(ScanFilterKind kind) {
  for (const auto& [name, value] : kind_names) {
    if (value == kind) return name;
  }
  return "unknown";
}

ScanFilterKind parse_scan_filter_kind(std::string_view name) {
  const std::string_view trimmed = trim(name);
  for (const auto& [known, value] : kind_names) {
    if (known == trimmed) return value;
  }
  throw InputError("unknown scan filter \"" + std::string(trimmed) + "\"; valid names: " +
                   std::string(valid_names));
}

std::vector<ScanFilterKind> parse_scan_filter_list(std::string_view names) {
  std::vector<ScanFilterKind> kinds;
  bool saw_none = false;
  std::size_t tokens = 0;
  const auto add = [&](ScanFilterKind kind) {
    if (std::find(kinds.begin(), kinds.end(), kind) != kinds.end()) {
      throw InputError("scan filter \"" + std::string(scan_filter_name(kind)) + "\" appears twice in \"" +
                       std::string(names) + "\" (\"paper\" already holds range-clustering and scan-sequence)");
    }
    kinds.push_back(kind);
  };
  std::string_view rest = names;
  while (true) {
    const std::size_t comma = rest.find(',');
    const std::string_view token = trim(rest.substr(0, comma));
    if (token.empty()) {
      throw InputError("empty name in the scan filter list \"" + std::string(names) +
                       "\"; valid names: " + std::string(valid_names));
    }
    ++tokens;
    if (token == "none") {
      saw_none = true;
    } else if (token == "paper") {
      add(ScanFilterKind::range_clustering);
      add(ScanFilterKind::scan_sequence);
    } else {
      add(parse_scan_filter_kind(token));
    }
    if (comma == std::string_view::npos) break;
    rest.remove_prefix(comma + 1);
  }
  if (saw_none && tokens > 1) {
    throw InputError("scan filter list \"" + std::string(names) +
                     "\": \"none\" cannot be combined with other filters");
  }
  return kinds;
}

std::vector<ScanFilterKind> parse_scan_filter_list(const std::vector<std::string>& names) {
  std::string joined;
  for (const std::string& name : names) {
    if (!joined.empty()) joined += ',';
    joined += name;
  }
  return parse_scan_filter_list(std::string_view(joined));
}

std::string scan_filter_list_name(const std::vector<ScanFilterKind>& kinds) {
  if (kinds.empty()) return "none";
  std::string text;
  for (const ScanFilterKind kind : kinds) {
    if (!text.empty()) text += ',';
    text += scan_filter_name(kind);
  }
  return text;
}

namespace {

std::vector<ScanFilterKind> checked_stages(std::vector<ScanFilterKind> stages) {
  for (std::size_t i = 0; i < stages.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (stages[i] == stages[j]) {
        throw InputError("scan filter chain: \"" + std::string(scan_filter_name(stages[i])) +
                         "\" is given twice (stages " + std::to_string(j) + " and " + std::to_string(i) + ")");
      }
    }
  }
  return stages;
}

}  // namespace

ScanFilterChain::ScanFilterChain(std::vector<ScanFilterKind> stages, const ScanFilterChainOptions& options)
    : stages_(checked_stages(std::move(stages))),
      range_clustering_(options.range_clustering),
      scan_sequence_(options.scan_sequence),
      shadow_(options.shadow),
      speckle_(options.speckle) {
  const auto found = std::find(stages_.begin(), stages_.end(), ScanFilterKind::scan_sequence);
  has_scan_sequence_ = found != stages_.end();
  scan_sequence_stage_ = static_cast<std::size_t>(found - stages_.begin());
}

void ScanFilterChain::run_stateless(std::size_t stage, PlanarScan& scan, StageMasks& masks) {
  std::vector<std::uint8_t>& removed = masks.removed[stage];
  switch (stages_[stage]) {
    case ScanFilterKind::range_clustering:
      masks.stats[stage] = range_clustering_.apply(scan, removed);
      break;
    case ScanFilterKind::shadow:
      masks.stats[stage] = shadow_.apply(scan, removed);
      break;
    case ScanFilterKind::speckle:
      masks.stats[stage] = speckle_.apply(scan, removed);
      break;
    case ScanFilterKind::scan_sequence:
      break;  // streaming; handled by push/flush
  }
}

bool ScanFilterChain::push(const PlanarScan& scan, PlanarScan& out) {
  detail::copy_scan(scan, work_);
  // Every chain, also an empty one, hands out scans whose only invalid value is NaN.
  prepare_scan_for_filter(work_, normalize_mask_, "scan filter chain");
  const std::size_t before_sequence = has_scan_sequence_ ? scan_sequence_stage_ : stages_.size();
  for (std::size_t stage = 0; stage < before_sequence; ++stage) run_stateless(stage, work_, incoming_);
  if (!has_scan_sequence_) {
    std::swap(output_, incoming_);
    detail::copy_scan(work_, out);
    finish_output(out);
    return true;
  }
  const bool ready = scan_sequence_.push(work_, out, sequence_removed_);
  if (ready) {
    // `out` is the scan held since the previous push: its earlier stages'
    // masks were kept in held_.
    std::swap(output_, held_);
    std::swap(output_.removed[scan_sequence_stage_], sequence_removed_);
    output_.stats[scan_sequence_stage_] = scan_sequence_.last_stats();
    for (std::size_t stage = scan_sequence_stage_ + 1; stage < stages_.size(); ++stage) {
      run_stateless(stage, out, output_);
    }
    finish_output(out);
  }
  std::swap(held_, incoming_);
  return ready;
}

bool ScanFilterChain::flush(PlanarScan& out) {
  if (!has_scan_sequence_ || !scan_sequence_.flush(out, sequence_removed_)) return false;
  std::swap(output_, held_);
  std::swap(output_.removed[scan_sequence_stage_], sequence_removed_);
  output_.stats[scan_sequence_stage_] = scan_sequence_.last_stats();
  for (std::size_t stage = scan_sequence_stage_ + 1; stage < stages_.size(); ++stage) {
    run_stateless(stage, out, output_);
  }
  finish_output(out);
  return true;
}

void ScanFilterChain::reset() { scan_sequence_.reset(); }

void ScanFilterChain::finish_output(PlanarScan& out) {
  removed_any_.assign(out.size(), 0);
  for (std::size_t stage = 0; stage < stages_.size(); ++stage) {
    const std::vector<std::uint8_t>& removed = output_.removed[stage];
    for (std::size_t i = 0; i < removed.size() && i < removed_any_.size(); ++i) {
      removed_any_[i] = static_cast<std::uint8_t>(removed_any_[i] | removed[i]);
    }
  }
}

const std::vector<std::uint8_t>& ScanFilterChain::removed_by_stage(std::size_t stage) const {
  if (stage >= stages_.size()) {
    throw std::out_of_range("ScanFilterChain::removed_by_stage: stage " + std::to_string(stage) + " of " +
                            std::to_string(stages_.size()));
  }
  return output_.removed[stage];
}

const ScanFilterStats& ScanFilterChain::stats_of_stage(std::size_t stage) const {
  if (stage >= stages_.size()) {
    throw std::out_of_range("ScanFilterChain::stats_of_stage: stage " + std::to_string(stage) + " of " +
                            std::to_string(stages_.size()));
  }
  return output_.stats[stage];
}

}  // namespace stridemap
