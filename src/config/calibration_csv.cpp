#include "stridemap/config/calibration_csv.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string_view>

#include "stridemap/core/error.hpp"

namespace stridemap {
namespace {

constexpr std::size_t minimum_pairs = 4;

std::string_view trim(std::string_view text) {
  const auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; };
  while (!text.empty() && is_space(text.front())) text.remove_prefix(1);
  while (!text.empty() && is_space(text.back())) text.remove_suffix(1);
  return text;
}

std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      fields.push_back(trim(line.substr(start)));
      return fields;
    }
    fields.push_back(trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

class LineErrors {
 public:
  explicit LineErrors(const std::string& source) : source_(source) {}
  [[noreturn]] void fail(int line, const std::string& what) const {
    std::ostringstream message;
    message << source_ << ":" << line << ": " << what;
    throw InputError(message.str());
  }

 private:
  const std::string& source_;
};

// Position and unit of the two columns, found from the header line.
struct ColumnLayout {
  int measured_column = -1;
  int true_column = -1;
  double measured_to_m = 1.0;
  double true_to_m = 1.0;
};

constexpr const char* expected_header = "'measured_m,true_m' or 'measured_mm,true_mm'";

ColumnLayout parse_header(std::string_view line, int line_number, const LineErrors& errors) {
  const auto fields = split_fields(line);
  if (fields.size() != 2) {
    std::ostringstream what;
    what << "header has " << fields.size() << " columns, expected 2 (" << expected_header << ")";
    errors.fail(line_number, what.str());
  }
  ColumnLayout layout;
  for (int column = 0; column < 2; ++column) {
    const std::string_view name = fields[static_cast<std::size_t>(column)];
    int* target = nullptr;
    double* to_m = nullptr;
    double unit = 1.0;
    if (name == "measured_m" || name == "measured_mm") {
      target = &layout.measured_column;
      to_m = &layout.measured_to_m;
      unit = name == "measured_mm" ? 0.001 : 1.0;
    } else if (name == "true_m" || name == "true_mm") {
      target = &layout.true_column;
      to_m = &layout.true_to_m;
      unit = name == "true_mm" ? 0.001 : 1.0;
    } else {
      errors.fail(line_number, "unknown column '" + std::string(name) + "' in header, expected " +
                                   expected_header);
    }
    if (*target >= 0) {
      errors.fail(line_number, "column '" + std::string(name) +
                                   "' repeats a quantity already named in the header");
    }
    *target = column;
    *to_m = unit;
  }
  return layout;
}

double parse_value(std::string_view field, const char* column_name, int line_number,
                   const LineErrors& errors) {
  double value = 0.0;
  const char* end = field.data() + field.size();
  // from_chars rejects a leading '+', which hand-written files may carry.
  const char* begin = field.data();
  if (begin != end && *begin == '+') ++begin;
  const auto [stop, status] = std::from_chars(begin, end, value);
  if (status == std::errc::result_out_of_range && stop == end) {
    errors.fail(line_number, std::string(column_name) + " value '" + std::string(field) +
                                 "' is out of the range of a double");
  }
  if (field.empty() || status != std::errc() || stop != end) {
    errors.fail(line_number, std::string(column_name) + " value '" + std::string(field) +
                                 "' is not a number");
  }
  if (!std::isfinite(value)) {
    errors.fail(line_number, std::string(column_name) + " value '" + std::string(field) +
                                 "' is not finite");
  }
  if (value <= 0.0) {
    errors.fail(line_number, std::string(column_name) + " value '" + std::string(field) +
                                 "' is not a positive range");
  }
  return value;
}

}  // namespace

RangePairs read_range_pairs_csv(std::istream& input, const std::string& source_name) {
  const LineErrors errors(source_name);
  RangePairs pairs;
  ColumnLayout layout;
  bool have_header = false;
  std::string text;
  int line_number = 0;
  while (std::getline(input, text)) {
    ++line_number;
    std::string_view line = text;
    if (line_number == 1 && line.starts_with("\xEF\xBB\xBF")) line.remove_prefix(3);
    if (const std::size_t hash = line.find('#'); hash != std::string_view::npos) {
      line = line.substr(0, hash);
    }
    line = trim(line);
    if (line.empty()) continue;
    if (!have_header) {
      layout = parse_header(line, line_number, errors);
      have_header = true;
      continue;
    }
    const auto fields = split_fields(line);
    if (fields.size() != 2) {
      std::ostringstream what;
      what << fields.size() << " columns, expected 2 (measured, true)";
      errors.fail(line_number, what.str());
    }
    const auto measured_field = fields[static_cast<std::size_t>(layout.measured_column)];
    const auto true_field = fields[static_cast<std::size_t>(layout.true_column)];
    pairs.measured_m.push_back(parse_value(measured_field, "measured", line_number, errors) *
                               layout.measured_to_m);
    pairs.true_m.push_back(parse_value(true_field, "true", line_number, errors) *
                           layout.true_to_m);
    pairs.line.push_back(line_number);
  }
  if (input.bad()) errors.fail(line_number, "read error");
  if (!have_header) {
    errors.fail(std::max(line_number, 1), std::string("no header line (the file is empty or only comments), "
                                         "expected ") +
                                 expected_header);
  }
  if (pairs.measured_m.size() < minimum_pairs) {
    std::ostringstream what;
    what << "only " << pairs.measured_m.size()
         << " data rows up to the end of the file, fitting a cubic needs at least "
         << minimum_pairs;
    errors.fail(line_number, what.str());
  }
  return pairs;
}

RangePairs read_range_pairs_csv(const std::filesystem::path& path) {
  std::error_code status_error;
  if (std::filesystem::is_directory(path, status_error)) {
    throw InputError(path.string() + ": cannot read calibration CSV, it is a directory");
  }
  std::ifstream file(path);
  if (!file) {
    std::error_code ignored;
    const bool exists = std::filesystem::exists(path, ignored);
    throw InputError(path.string() + ": cannot open calibration CSV" +
                     (exists ? " (permission denied or not a file)" : " (no such file)"));
  }
  return read_range_pairs_csv(file, path.string());
}

}  // namespace stridemap
