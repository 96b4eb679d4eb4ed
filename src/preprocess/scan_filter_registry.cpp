#include "stridemap/preprocess/scan_filter_registry.hpp"

#include <algorithm>
#include <deque>
#include <limits>
#include <mutex>
#include <type_traits>

#include "stridemap/core/error.hpp"
#include "stridemap/preprocess/range_clustering.hpp"
#include "stridemap/preprocess/shadow_filter.hpp"
#include "stridemap/preprocess/speckle_filter.hpp"

namespace stridemap {
namespace {

template <class Filter>
class FilterStage final : public ScanFilterStage {
 public:
  template <class Options>
  explicit FilterStage(const Options& options) : filter_(options) {}
  ScanFilterStats apply(PlanarScan& scan, std::vector<std::uint8_t>& removed) override {
    return filter_.apply(scan, removed);
  }

 private:
  Filter filter_;
};

struct Registry {
  std::mutex mutex;
  // A deque: scan_filter_registration hands out references that later
  // registrations must not move.
  std::deque<ScanFilterRegistration> filters;
  std::vector<ScanFilterSet> sets;
};

bool valid_name(const std::string& name) {
  return !name.empty() && name != "none" &&
         std::none_of(name.begin(), name.end(), [](char c) { return c == ',' || c == ' ' || c == '\t' || c == '\n' || c == '\r'; });
}

bool name_taken(const Registry& registry, const std::string& name) {
  return std::any_of(registry.filters.begin(), registry.filters.end(), [&](const auto& f) { return f.name == name; }) ||
         std::any_of(registry.sets.begin(), registry.sets.end(), [&](const auto& s) { return s.name == name; });
}

// Called with the mutex held.
ScanFilterKind add_filter(Registry& registry, ScanFilterRegistration registration, bool streaming) {
  if (!valid_name(registration.name)) {
    throw InputError("scan filter registration: invalid name \"" + registration.name +
                     "\" (not empty, no comma or blank, not \"none\")");
  }
  if (name_taken(registry, registration.name)) {
    throw InputError("scan filter registration: \"" + registration.name + "\" is already registered");
  }
  if (!registration.make && !streaming) {
    throw InputError("scan filter registration: \"" + registration.name + "\" has no factory");
  }
  if (registry.filters.size() > std::numeric_limits<std::underlying_type_t<ScanFilterKind>>::max()) {
    throw InputError("scan filter registration: no kind left for \"" + registration.name + "\"");
  }
  registry.filters.push_back(std::move(registration));
  return static_cast<ScanFilterKind>(registry.filters.size() - 1);
}

void add_set(Registry& registry, ScanFilterSet set) {
  if (!valid_name(set.name)) {
    throw InputError("scan filter set registration: invalid name \"" + set.name + "\"");
  }
  if (name_taken(registry, set.name)) {
    throw InputError("scan filter set registration: \"" + set.name + "\" is already registered");
  }
  if (set.members.empty()) throw InputError("scan filter set registration: \"" + set.name + "\" has no filters");
  for (const std::string& member : set.members) {
    if (std::none_of(registry.filters.begin(), registry.filters.end(), [&](const auto& f) { return f.name == member; })) {
      throw InputError("scan filter set registration: \"" + set.name + "\" holds \"" + member +
                       "\", which is no registered scan filter");
    }
  }
  registry.sets.push_back(std::move(set));
}

template <class Filter, class Options>
auto built_in(Options ScanFilterChainOptions::*options) {
  return [options](const ScanFilterChainOptions& chain, const ScanFilterParameters&) -> std::unique_ptr<ScanFilterStage> {
    return std::make_unique<FilterStage<Filter>>(chain.*options);
  };
}

// The built-in filters in the order of ScanFilterKind: a kind is its index.
Registry& registry() {
  // Never destroyed: a registrar object in another file may outlive a
  // local static.
  static Registry& instance = *[] {
    auto* registry = new Registry;
    Registry& r = *registry;
    add_filter(r, {"range-clustering", "drops clusters too small or too short to be a surface (the paper's, section 5.3)", {},
                   built_in<RangeClusteringFilter>(&ScanFilterChainOptions::range_clustering)},
               false);
    add_filter(r, {"scan-sequence", "drops a sector scattered more than the next scan's, at edges across the scan (the paper's, eq. 12)",
                   {}, {}},
               true);
    add_filter(r, {"shadow", "drops the far side of veils at depth jumps (ROS laser_filters' baseline)", {},
                   built_in<ShadowFilter>(&ScanFilterChainOptions::shadow)},
               false);
    add_filter(r, {"speckle", "drops isolated points (ROS laser_filters' baseline)", {},
                   built_in<SpeckleFilter>(&ScanFilterChainOptions::speckle)},
               false);
    add_filter(r, {"between-scans", "drops beams that read between the ranges of the scans before and after (ours)", {}, {}}, true);
    add_set(r, {"paper", "the paper's combination", {"range-clustering", "scan-sequence"}});
    add_set(r, {"urg", "the paper's pair and the between-scans test (ours)",
                {"range-clustering", "scan-sequence", "between-scans"}});
    return registry;
  }();
  return instance;
}

}  // namespace

ScanFilterKind register_scan_filter(ScanFilterRegistration registration) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  return add_filter(r, std::move(registration), false);
}

void register_scan_filter_set(ScanFilterSet set) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  add_set(r, std::move(set));
}

std::vector<ScanFilterRegistration> registered_scan_filters() {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  return {r.filters.begin(), r.filters.end()};
}

std::vector<ScanFilterSet> registered_scan_filter_sets() {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  return r.sets;
}

const ScanFilterRegistration& scan_filter_registration(ScanFilterKind kind) {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  const auto index = static_cast<std::size_t>(kind);
  if (index >= r.filters.size()) {
    throw InputError("scan filter kind " + std::to_string(index) + " is not registered");
  }
  return r.filters[index];
}

std::string scan_filter_choices() {
  Registry& r = registry();
  const std::lock_guard lock(r.mutex);
  std::string text;
  for (const ScanFilterRegistration& filter : r.filters) text += (text.empty() ? "" : ", ") + filter.name;
  for (const ScanFilterSet& set : r.sets) {
    text += "; " + set.name + " = ";
    for (std::size_t i = 0; i < set.members.size(); ++i) text += (i == 0 ? "" : ",") + set.members[i];
  }
  return text + "; none";
}

}  // namespace stridemap
