#pragma once
// The scan filters by name. Each filter is one registration (name, one line
// on what it does, the options it reads, how to build it), and the list of
// registrations is the only list of filter names: the name parser, the
// chain, the tool's help texts, Python and the experiments read it. A filter
// registered at run time (a user's program, a test) is therefore usable by
// name everywhere a built-in one is (docs/architecture.md, "Adding a scan
// filter").
//
// Register before the first chain or name list is built and from one thread:
// the registry is for start-up, not for changing filters during a run.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "stridemap/core/planar_scan.hpp"
#include "stridemap/preprocess/scan_checks.hpp"
#include "stridemap/preprocess/scan_filter_chain.hpp"

namespace stridemap {

/// A filter that judges each scan on its own (no scan held between calls).
class ScanFilterStage {
 public:
  virtual ~ScanFilterStage() = default;
  /// Filters `scan` in place: removed beams become NaN and get removed[i] = 1
  /// (the mask resized to the scan, 0 elsewhere). The chain hands over scans
  /// whose only invalid range is NaN.
  virtual ScanFilterStats apply(PlanarScan& scan, std::vector<std::uint8_t>& removed) = 0;
};

/// One option of a registered filter that has no struct of its own in
/// ScanFilterChainOptions.
struct ScanFilterParameter {
  std::string name;
  double default_value = 0.0;
  std::string description;
};

struct ScanFilterRegistration {
  /// As written in a filter list ("speckle"): no comma or blank, and not a
  /// set's name or "none".
  std::string name;
  /// One line for help texts and Python.
  std::string description;
  /// The filter's own options, if any; their values come from
  /// ScanFilterChainOptions::parameters[name], the defaults from here.
  std::vector<ScanFilterParameter> parameters;
  /// Builds one stage of a chain from the chain's options (a built-in filter
  /// reads its struct there) and the values of `parameters`. Throws
  /// InputError on invalid options. Empty for scan-sequence and
  /// between-scans only: they hold a scan, and the chain runs them itself.
  std::function<std::unique_ptr<ScanFilterStage>(const ScanFilterChainOptions& options,
                                                 const ScanFilterParameters& values)>
      make;
};

/// A name that stands for several filters in a list ("paper", "urg").
struct ScanFilterSet {
  std::string name;
  std::string description;
  std::vector<std::string> members;  ///< registered filter names, in order of application
};

/// Adds a filter; returns its kind, which stays valid for the process.
/// Throws InputError on an invalid or taken name, a missing factory or a
/// full registry (256 kinds).
ScanFilterKind register_scan_filter(ScanFilterRegistration registration);

/// Adds a set of registered filters. Throws InputError on an invalid or
/// taken name or an unknown member.
void register_scan_filter_set(ScanFilterSet set);

/// For a registration from a namespace-scope object (the tests' way).
struct ScanFilterRegistrar {
  explicit ScanFilterRegistrar(ScanFilterRegistration registration)
      : kind(register_scan_filter(std::move(registration))) {}
  ScanFilterKind kind;
};

/// Every filter in registration order: the built-in ones first, in the
/// order of ScanFilterKind.
std::vector<ScanFilterRegistration> registered_scan_filters();
/// Every set in registration order ("paper", "urg" first).
std::vector<ScanFilterSet> registered_scan_filter_sets();

/// The registration of a kind; throws InputError for a kind never registered.
const ScanFilterRegistration& scan_filter_registration(ScanFilterKind kind);

/// What a filter list may hold, for help texts and error messages:
/// "range-clustering, ...; paper = range-clustering,scan-sequence; ...; none".
std::string scan_filter_choices();

}  // namespace stridemap
