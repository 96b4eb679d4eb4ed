#include "stridemap/preprocess/scan_filter_chain.hpp"

#include <algorithm>
#include <stdexcept>
#include <utility>

#include "scan_copy.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/preprocess/scan_filter_registry.hpp"

namespace stridemap {
namespace {

std::string_view trim(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

std::string joined_names(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ",") + name;
  return text;
}

}  // namespace

std::string_view scan_filter_name(ScanFilterKind kind) {
  try {
    return scan_filter_registration(kind).name;
  } catch (const InputError&) {
    return "unknown";
  }
}

ScanFilterKind parse_scan_filter_kind(std::string_view name) {
  const std::string_view trimmed = trim(name);
  const std::vector<ScanFilterRegistration> filters = registered_scan_filters();
  for (std::size_t i = 0; i < filters.size(); ++i) {
    if (filters[i].name == trimmed) return static_cast<ScanFilterKind>(i);
  }
  throw InputError("unknown scan filter \"" + std::string(trimmed) + "\"; valid names: " + scan_filter_choices());
}

std::vector<ScanFilterKind> parse_scan_filter_list(std::string_view names) {
  const std::vector<ScanFilterSet> sets = registered_scan_filter_sets();
  std::vector<ScanFilterKind> kinds;
  std::vector<const ScanFilterSet*> sets_used;
  bool saw_none = false;
  std::size_t tokens = 0;
  const auto add = [&](ScanFilterKind kind) {
    if (std::find(kinds.begin(), kinds.end(), kind) != kinds.end()) {
      std::string sets_text;
      for (const ScanFilterSet* set : sets_used) {
        sets_text += (sets_text.empty() ? " (" : ", ") + ("\"" + set->name + "\" = ") + joined_names(set->members);
      }
      throw InputError("scan filter \"" + std::string(scan_filter_name(kind)) + "\" appears twice in \"" +
                       std::string(names) + "\"" + sets_text + (sets_text.empty() ? "" : ")"));
    }
    kinds.push_back(kind);
  };
  std::string_view rest = names;
  while (true) {
    const std::size_t comma = rest.find(',');
    const std::string_view token = trim(rest.substr(0, comma));
    if (token.empty()) {
      throw InputError("empty name in the scan filter list \"" + std::string(names) +
                       "\"; valid names: " + scan_filter_choices());
    }
    ++tokens;
    const auto set = std::find_if(sets.begin(), sets.end(), [&](const ScanFilterSet& s) { return s.name == token; });
    if (token == "none") {
      saw_none = true;
    } else if (set != sets.end()) {
      sets_used.push_back(&*set);
      for (const std::string& member : set->members) add(parse_scan_filter_kind(member));
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
    (void)scan_filter_registration(stages[i]);  // throws for a kind never registered
    for (std::size_t j = 0; j < i; ++j) {
      if (stages[i] == stages[j]) {
        throw InputError("scan filter chain: \"" + std::string(scan_filter_name(stages[i])) +
                         "\" is given twice (stages " + std::to_string(j) + " and " + std::to_string(i) + ")");
      }
    }
  }
  const auto at = [&](ScanFilterKind kind) {
    return static_cast<std::size_t>(std::find(stages.begin(), stages.end(), kind) - stages.begin());
  };
  const std::size_t spread = at(ScanFilterKind::scan_sequence), between = at(ScanFilterKind::between_scans);
  if (spread < stages.size() && between < stages.size() && spread + 1 != between && between + 1 != spread) {
    throw InputError("scan filter chain: \"scan-sequence\" (stage " + std::to_string(spread) +
                     ") and \"between-scans\" (stage " + std::to_string(between) +
                     ") must be next to each other: they judge the same three scans in one pass");
  }
  return stages;
}

ScanSequenceOptions sequence_options(const std::vector<ScanFilterKind>& stages, ScanSequenceOptions options) {
  const auto has = [&](ScanFilterKind kind) { return std::find(stages.begin(), stages.end(), kind) != stages.end(); };
  options.spread_test = has(ScanFilterKind::scan_sequence);
  options.between_scans.enabled = has(ScanFilterKind::between_scans);
  return options;
}

// The built-in filters' options are checked whether or not they are stages,
// so that a caller can check a set of options once with any chain.
const ScanFilterChainOptions& checked_options(const ScanFilterChainOptions& options) {
  options.range_clustering.validate();
  options.scan_sequence.validate();
  options.shadow.validate();
  options.speckle.validate();
  const std::vector<ScanFilterRegistration> filters =
      options.parameters.empty() ? std::vector<ScanFilterRegistration>{} : registered_scan_filters();
  for (const auto& given : options.parameters) {
    const std::string& name = given.first;
    const auto filter = std::find_if(filters.begin(), filters.end(), [&](const auto& f) { return f.name == name; });
    if (filter == filters.end()) {
      throw InputError("scan filter options: parameters for \"" + name + "\", which is no registered scan filter");
    }
    for (const auto& value : given.second) {
      const std::string& parameter = value.first;
      if (std::none_of(filter->parameters.begin(), filter->parameters.end(),
                       [&](const ScanFilterParameter& p) { return p.name == parameter; })) {
        throw InputError("scan filter options: \"" + name + "\" has no parameter \"" + parameter + "\"");
      }
    }
  }
  return options;
}

ScanFilterParameters parameter_values(const ScanFilterRegistration& filter, const ScanFilterChainOptions& options) {
  ScanFilterParameters values;
  for (const ScanFilterParameter& parameter : filter.parameters) values[parameter.name] = parameter.default_value;
  if (const auto given = options.parameters.find(filter.name); given != options.parameters.end()) {
    for (const auto& [name, value] : given->second) values[name] = value;
  }
  return values;
}

}  // namespace

ScanFilterChain::~ScanFilterChain() = default;
ScanFilterChain::ScanFilterChain(ScanFilterChain&&) noexcept = default;
ScanFilterChain& ScanFilterChain::operator=(ScanFilterChain&&) noexcept = default;

ScanFilterChain::ScanFilterChain(std::vector<ScanFilterKind> stages, const ScanFilterChainOptions& options)
    : stages_(checked_stages(std::move(stages))),
      scan_sequence_(sequence_options(stages_, checked_options(options).scan_sequence)) {
  for (std::size_t stage = 0; stage < stages_.size(); ++stage) {
    if (stages_[stage] == ScanFilterKind::scan_sequence) spread_stage_ = stage;
    if (stages_[stage] == ScanFilterKind::between_scans) between_stage_ = stage;
    const ScanFilterRegistration& filter = scan_filter_registration(stages_[stage]);
    if (stages_[stage] == ScanFilterKind::range_clustering) {
      range_clustering_.emplace(options.range_clustering);  // what its registration makes
      stateless_.push_back(nullptr);
      continue;
    }
    stateless_.push_back(filter.make ? filter.make(options, parameter_values(filter, options)) : nullptr);
  }
  for (StageMasks* masks : {&incoming_, &held_, &output_}) {
    masks->removed.resize(stages_.size());
    masks->stats.resize(stages_.size());
  }
  has_scan_sequence_ = spread_stage_ != absent || between_stage_ != absent;
  scan_sequence_stage_ = std::min(spread_stage_, between_stage_);
  after_sequence_stage_ = 1 + (spread_stage_ != absent && between_stage_ != absent
                                   ? std::max(spread_stage_, between_stage_)
                                   : scan_sequence_stage_);
}

// The scan-sequence filter's mask holds both tests' removals: split it
// between the stages, so that each removed beam is marked by one stage.
void ScanFilterChain::take_sequence_masks() {
  const std::vector<std::uint8_t>& between = scan_sequence_.last_removed_between_scans();
  const ScanFilterStats& all = scan_sequence_.last_stats();
  const bool both = spread_stage_ != absent && between_stage_ != absent;
  // A stage alone has all of them; the between-scans ones are a subset of all.
  const std::size_t between_removed =
      both ? static_cast<std::size_t>(std::count(between.begin(), between.end(), std::uint8_t{1})) : all.removed;
  if (between_stage_ != absent) {
    output_.removed[between_stage_] = between;
    output_.stats[between_stage_] = all;
    output_.stats[between_stage_].removed = between_removed;
  }
  if (spread_stage_ != absent) {
    // The filter refills its mask on the next push: this one is handed on.
    std::vector<std::uint8_t>& spread = output_.removed[spread_stage_];
    std::swap(spread, sequence_removed_);
    if (both) {
      // Plain pointers: a byte store could alias a vector's own pointers,
      // which would keep the loop from vectorising.
      const std::size_t n = std::min(spread.size(), between.size());
      std::uint8_t* to = spread.data();
      const std::uint8_t* from = between.data();
      for (std::size_t i = 0; i < n; ++i) to[i] &= static_cast<std::uint8_t>(!from[i]);
    }
    output_.stats[spread_stage_] = all;
    output_.stats[spread_stage_].removed = both ? all.removed - between_removed : all.removed;
  }
  // The later of the two stages sees the earlier one's removals as unusable input.
  if (both) {
    output_.stats[std::max(spread_stage_, between_stage_)].invalid_input +=
        output_.stats[std::min(spread_stage_, between_stage_)].removed;
  }
}

void ScanFilterChain::run_stateless(std::size_t stage, PlanarScan& scan, StageMasks& masks) {
  if (stages_[stage] == ScanFilterKind::range_clustering) {
    masks.stats[stage] = range_clustering_->apply(scan, masks.removed[stage]);
    return;
  }
  // The scan-sequence stages have none: they stream, handled by push/flush.
  if (stateless_[stage]) masks.stats[stage] = stateless_[stage]->apply(scan, masks.removed[stage]);
}

void ScanFilterChain::run_on_work(std::size_t stage, bool& prepared, std::size_t& invalid) {
  if (prepared && stages_[stage] == ScanFilterKind::range_clustering) {
    // It only turns valid ranges into NaN, each counted as removed.
    incoming_.stats[stage] = range_clustering_->apply_prepared(work_, incoming_.removed[stage], invalid);
    invalid += incoming_.stats[stage].removed;
    return;
  }
  run_stateless(stage, work_, incoming_);
  prepared = false;  // a registered filter may leave any value
}

bool ScanFilterChain::push(const PlanarScan& scan, PlanarScan& out) {
  detail::copy_scan(scan, work_);
  // Every chain, also an empty one, hands out scans whose only invalid value is NaN.
  std::size_t invalid = prepare_scan_for_filter(work_, normalize_mask_, "scan filter chain").invalid_input;
  bool prepared = true;
  const std::size_t before_sequence = has_scan_sequence_ ? scan_sequence_stage_ : stages_.size();
  // Range clustering's test on this scan, while the work scan differs from
  // the one it tested only by the NaNs of its removals.
  const RangeBreaks* breaks = nullptr;
  for (std::size_t stage = 0; stage < before_sequence; ++stage) {
    run_on_work(stage, prepared, invalid);
    breaks = prepared && stages_[stage] == ScanFilterKind::range_clustering ? &range_clustering_->last_breaks() : nullptr;
  }
  if (!has_scan_sequence_) {
    std::swap(output_, incoming_);
    detail::copy_scan(work_, out);
    finish_output(out);
    return true;
  }
  const bool ready = prepared ? scan_sequence_.push_prepared(work_, invalid, out, sequence_removed_, breaks)
                              : scan_sequence_.push(work_, out, sequence_removed_);
  if (ready) {
    // `out` is the scan held since the previous push: its earlier stages'
    // masks were kept in held_.
    std::swap(output_, held_);
    take_sequence_masks();
    for (std::size_t stage = after_sequence_stage_; stage < stages_.size(); ++stage) {
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
  take_sequence_masks();
  for (std::size_t stage = after_sequence_stage_; stage < stages_.size(); ++stage) {
    run_stateless(stage, out, output_);
  }
  finish_output(out);
  return true;
}

void ScanFilterChain::reset() { scan_sequence_.reset(); }

void ScanFilterChain::finish_output(PlanarScan& out) {
  removed_any_.assign(out.size(), 0);
  for (std::size_t stage = 0; stage < stages_.size(); ++stage) {
    // Plain pointers: a byte store could alias a vector's own pointers, which
    // would keep the loop from vectorising.
    const std::size_t n = std::min(output_.removed[stage].size(), removed_any_.size());
    const std::uint8_t* removed = output_.removed[stage].data();
    std::uint8_t* any = removed_any_.data();
    for (std::size_t i = 0; i < n; ++i) any[i] = static_cast<std::uint8_t>(any[i] | removed[i]);
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
