#include <optional>

#include "import_lines.hpp"
#include "stridemap/core/error.hpp"
#include "stridemap/recordings/log_import.hpp"

namespace stridemap::io {

ImportedData import_csv_ranges(std::string_view text, const std::string& source,
                               const CsvRangesImportOptions& options) {
  if (!(options.range_scale_m > 0.0) || !std::isfinite(options.range_scale_m)) {
    throw InputError(source + ": CSV ranges import: the range scale must be a positive number");
  }
  ImportedData out;
  out.format = "csv-ranges";
  out.version = detail::imported_version("CSV ranges");
  std::optional<detail::BeamSteps> layout;
  std::size_t beams = 0;
  bool seen_data = false;
  // Kept in file order until every time is known: which times are out of
  // order depends on all of them.
  struct Record {
    std::size_t line = 0;
    double time_s = 0.0;
    std::vector<std::uint32_t> values;
  };
  std::vector<Record> records;
  detail::for_each_line(detail::text_body(text, source), [&](std::string_view line, std::size_t number) {
    ++out.report.lines;
    const auto fields = detail::split_fields(line, true);
    if (fields.empty() || fields.front().front() == '#') {
      ++out.report.ignored;
      return;
    }
    double time_s = 0.0;
    if (!detail::parse_number(fields[0], time_s)) {
      if (!seen_data && number == 1) {
        ++out.report.ignored;  // a header line naming the columns
        return;
      }
      return detail::skip_line(out.report, source, number, "time '" + std::string(fields[0]) + "' is not a number");
    }
    seen_data = true;
    if (fields.size() < 2) return detail::skip_line(out.report, source, number, "a time without ranges");
    if (!layout) {
      try {
        layout = detail::beam_steps(options.angle_min_rad, options.angle_step_rad, fields.size() - 1,
                                    options.min_range_m, options.max_range_m, source);
      } catch (const InputError& e) {
        throw InputError(std::string(e.what()) + " (line " + std::to_string(number) + ", " +
                         std::to_string(fields.size() - 1) + " ranges)");
      }
      out.sensor = layout->sensor;
      out.sensor.model = "CSV ranges (imported)";
      beams = fields.size() - 1;
    }
    if (fields.size() - 1 != beams) {
      return detail::skip_line(out.report, source, number,
                               std::to_string(fields.size() - 1) + " ranges, the first scan had " +
                                   std::to_string(beams));
    }
    std::vector<std::uint32_t> values(beams);
    for (std::size_t k = 0; k < beams; ++k) {
      double range = 0.0;
      const std::string_view field = fields[k + 1];
      if (field == "nan" || field == "NaN" || field == "inf" || field == "-") {
        values[k] = 0;  // no return
        continue;
      }
      if (!detail::parse_number(field, range)) {
        return detail::skip_line(out.report, source, number,
                                 "range " + std::to_string(k + 1) + " ('" + std::string(field) + "') is not a number");
      }
      values[k] = detail::limited_range_to_raw_mm(range * options.range_scale_m, options.max_range_m,
                                                  out.sensor.max_distance_mm);
    }
    records.push_back(Record{number, time_s, std::move(values)});
  }, options.progress);
  records = detail::keep_increasing_times(std::move(records), &Record::time_s, out.report, source);
  out.scans.reserve(records.size());
  for (Record& record : records) {
    out.scans.push_back(detail::make_scan(out.scans.size(), record.time_s, records.front().time_s,
                                          layout->first_step, layout->cluster, std::move(record.values)));
  }
  out.report.scans = out.scans.size();
  return out;
}

}  // namespace stridemap::io
