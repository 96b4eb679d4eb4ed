// A scan filter added from outside the library by one registration: the
// name parser, the help text and the chain take it like a built-in one
// (docs/architecture.md, "Adding a scan filter").
#include "stridemap/preprocess/scan_filter_registry.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"
#include "test_scans.hpp"

namespace stridemap {
namespace {

// Keeps one beam in every `period`: a filter no built-in resembles.
class KeepOneInPeriod final : public ScanFilterStage {
 public:
  explicit KeepOneInPeriod(double period) : period_(static_cast<std::size_t>(period)) {}
  ScanFilterStats apply(PlanarScan& scan, std::vector<std::uint8_t>& removed) override {
    ScanFilterStats stats;
    stats.beams = scan.size();
    removed.assign(scan.size(), 0);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (i % period_ == 0 || std::isnan(scan.range_m[i])) continue;
      removed[i] = 1;
      ++stats.removed;
    }
    apply_removal_mask(scan, removed);
    return stats;
  }

 private:
  std::size_t period_;
};

const ScanFilterRegistrar keep_one_in_period({
    "keep-one-in-period",
    "keeps one beam in every `period`",
    {{"period", 2.0, "beams per kept beam"}},
    [](const ScanFilterChainOptions&, const ScanFilterParameters& values) -> std::unique_ptr<ScanFilterStage> {
      const double period = values.at("period");
      if (!(period >= 1.0)) throw InputError("keep-one-in-period: period must be at least 1");
      return std::make_unique<KeepOneInPeriod>(period);
    },
});

PlanarScan registry_test_scan(std::size_t beams) {
  PlanarScan scan = test::centred_scan(beams);
  test::put_on_line_x(scan, 0, beams - 1, 0.5);
  return scan;
}

TEST(ScanFilterRegistry, ARegisteredFilterIsListedAndParsedByName) {
  const std::vector<ScanFilterRegistration> filters = registered_scan_filters();
  ASSERT_GT(filters.size(), 5u);
  EXPECT_EQ(filters[static_cast<std::size_t>(keep_one_in_period.kind)].name, "keep-one-in-period");
  EXPECT_EQ(scan_filter_name(keep_one_in_period.kind), "keep-one-in-period");
  EXPECT_EQ(parse_scan_filter_kind("keep-one-in-period"), keep_one_in_period.kind);
  EXPECT_EQ(parse_scan_filter_list("paper, keep-one-in-period"),
            (std::vector<ScanFilterKind>{ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence,
                                         keep_one_in_period.kind}));
  EXPECT_EQ(scan_filter_list_name(parse_scan_filter_list("keep-one-in-period,shadow")), "keep-one-in-period,shadow");
  EXPECT_NE(scan_filter_choices().find("between-scans, keep-one-in-period;"), std::string::npos)
      << scan_filter_choices();
  // The unknown-name message lists it too.
  const std::string message = test::input_error_message([] { parse_scan_filter_list("veil"); });
  EXPECT_NE(message.find("keep-one-in-period"), std::string::npos) << message;
}

TEST(ScanFilterRegistry, TheBuiltInFiltersKeepTheirKindsAndSets) {
  const std::vector<ScanFilterRegistration> filters = registered_scan_filters();
  for (const ScanFilterKind kind : {ScanFilterKind::range_clustering, ScanFilterKind::scan_sequence,
                                    ScanFilterKind::shadow, ScanFilterKind::speckle, ScanFilterKind::between_scans}) {
    EXPECT_EQ(filters[static_cast<std::size_t>(kind)].name, scan_filter_name(kind));
    EXPECT_FALSE(filters[static_cast<std::size_t>(kind)].description.empty());
  }
  const std::vector<ScanFilterSet> sets = registered_scan_filter_sets();
  ASSERT_GE(sets.size(), 2u);
  EXPECT_EQ(sets[0].name, "paper");
  EXPECT_EQ(sets[1].name, "urg");
  EXPECT_EQ(scan_filter_list_name(parse_scan_filter_list("urg")), "range-clustering,scan-sequence,between-scans");
}

TEST(ScanFilterRegistry, ARegisteredFilterRunsInAChainAfterTheHeldScan) {
  ScanFilterChain chain(parse_scan_filter_list("scan-sequence,keep-one-in-period"));
  EXPECT_EQ(chain.stage_count(), 2u);
  EXPECT_EQ(chain.delay_scans(), 1u);
  const PlanarScan scan = registry_test_scan(40);
  PlanarScan out;
  EXPECT_FALSE(chain.push(scan, out));
  ASSERT_TRUE(chain.push(scan, out));
  const std::vector<std::uint8_t>& removed = chain.removed_by_stage(1);
  ASSERT_EQ(removed.size(), 40u);
  for (std::size_t i = 0; i < 40; ++i) {
    EXPECT_EQ(removed[i], i % 2 == 1 ? 1 : 0) << i;
    EXPECT_EQ(std::isnan(out.range_m[i]), i % 2 == 1) << i;
  }
  EXPECT_EQ(chain.stats_of_stage(1).removed, 20u);
  EXPECT_EQ(chain.removed_by_any(), removed);
}

TEST(ScanFilterRegistry, ParametersComeFromTheChainOptionsOverTheDefaults) {
  ScanFilterChainOptions options;
  options.parameters["keep-one-in-period"]["period"] = 4.0;
  ScanFilterChain chain({keep_one_in_period.kind}, options);
  PlanarScan out;
  ASSERT_TRUE(chain.push(registry_test_scan(40), out));
  EXPECT_EQ(chain.stats_of_stage(0).removed, 30u);

  options.parameters["keep-one-in-period"]["period"] = 0.0;
  EXPECT_THROW(ScanFilterChain({keep_one_in_period.kind}, options), InputError);
  options.parameters["keep-one-in-period"] = {{"stride", 3.0}};
  EXPECT_NE(test::input_error_message([&] { ScanFilterChain({}, options); }).find("no parameter \"stride\""),
            std::string::npos);
  options.parameters = {{"veil", {}}};
  EXPECT_THROW(ScanFilterChain({}, options), InputError);
}

TEST(ScanFilterRegistry, BadRegistrationsAreRefused) {
  const auto make = [](const ScanFilterChainOptions&, const ScanFilterParameters&) -> std::unique_ptr<ScanFilterStage> {
    return std::make_unique<KeepOneInPeriod>(2.0);
  };
  EXPECT_THROW(register_scan_filter({"shadow", "taken", {}, make}), InputError);
  EXPECT_THROW(register_scan_filter({"paper", "a set's name", {}, make}), InputError);
  EXPECT_THROW(register_scan_filter({"none", "reserved", {}, make}), InputError);
  EXPECT_THROW(register_scan_filter({"a,b", "comma", {}, make}), InputError);
  EXPECT_THROW(register_scan_filter({"no-factory", "", {}, {}}), InputError);
  EXPECT_THROW(register_scan_filter_set({"odd", "", {"veil"}}), InputError);
  EXPECT_THROW(ScanFilterChain({static_cast<ScanFilterKind>(250)}), InputError);
}

}  // namespace
}  // namespace stridemap
