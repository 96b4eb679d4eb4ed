#include "stridemap/mapfile/grid_csv.hpp"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string_view>
#include <system_error>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/io/detail/atomic_output_file.hpp"

namespace stridemap::io {
namespace {

constexpr std::string_view kHeaderTag = "# stridemap grid";

// Shortest text that reads back to the same value; to_chars ignores the
// locale, so a German locale cannot turn the decimal point into a comma.
template <typename T>
void append_cell_number(std::string& line, T value) {
  if (std::isnan(value)) {
    line += "nan";
    return;
  }
  char text[64];
  const auto result = std::to_chars(text, text + sizeof text, value);
  line.append(text, result.ptr);
}

void check_header_text(const std::string& path, const char* field, const std::string& text) {
  if (text.find_first_of(";=\r\n") != std::string::npos) {
    throw InputError("cannot write grid CSV '" + path + "': option " + field + " '" + text +
                     "' contains ';', '=' or a line break, which the header line cannot hold");
  }
}

void append_option(const std::string& path, std::string& header, const char* key, const std::optional<double>& value) {
  if (!value) return;
  if (!std::isfinite(*value)) {
    throw InputError("cannot write grid CSV '" + path + "': option " + key + " is not finite");
  }
  header += "; ";
  header += key;
  header += '=';
  append_cell_number(header, *value);
}

std::string_view trim_cell(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

class CsvReader {
 public:
  explicit CsvReader(const std::string& path) : path_(path) {}

  [[noreturn]] void fail(std::size_t line_number, const std::string& reason) const {
    throw InputError("grid CSV '" + path_ + "' line " + std::to_string(line_number) + ": " + reason);
  }

  // Takes the metadata from a "# stridemap grid; key=value; ..." line; other
  // comments are ignored. Unknown keys are skipped for forward compatibility.
  void parse_header(std::string_view line, std::size_t line_number) {
    if (line.substr(0, kHeaderTag.size()) != kHeaderTag) return;
    line.remove_prefix(kHeaderTag.size());
    while (!line.empty()) {
      const auto end = line.find(';');
      const std::string_view item = trim_cell(line.substr(0, end));
      line = end == std::string_view::npos ? std::string_view{} : line.substr(end + 1);
      if (item.empty()) continue;
      const auto equals = item.find('=');
      if (equals == std::string_view::npos) fail(line_number, "header item '" + std::string(item) + "' is not key=value");
      const std::string_view key = trim_cell(item.substr(0, equals));
      const std::string_view value = trim_cell(item.substr(equals + 1));
      if (key == "rows") header_rows_ = parse_count(value, key, line_number);
      if (key == "cols") header_cols_ = parse_count(value, key, line_number);
      if (key == "layer") metadata_.layer_name = value;
      if (key == "units") metadata_.units = value;
      if (key == "cell_size_m") metadata_.cell_size_m = parse_real(value, key, line_number);
      if (key == "origin_x_m") metadata_.origin_x_m = parse_real(value, key, line_number);
      if (key == "origin_y_m") metadata_.origin_y_m = parse_real(value, key, line_number);
    }
  }

  // Appends the fields of one data line to `values_`.
  void parse_row(std::string_view line, std::size_t line_number) {
    std::size_t fields = 0;
    std::size_t start = 0;
    while (true) {
      const auto comma = line.find(',', start);
      const std::string_view field = trim_cell(line.substr(start, comma == std::string_view::npos ? line.npos : comma - start));
      ++fields;
      values_.push_back(parse_field(field, fields, line_number));
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (rows_ == 0) {
      cols_ = fields;
      first_row_line_ = line_number;
    } else if (fields != cols_) {
      fail(line_number, "has " + std::to_string(fields) + " fields, but the first row (line " +
                            std::to_string(first_row_line_) + ") has " + std::to_string(cols_));
    }
    ++rows_;
  }

  Eigen::MatrixXf finish(std::size_t last_line) const {
    if (rows_ == 0) fail(last_line, "the file holds no data rows");
    if (header_rows_ && *header_rows_ != rows_) {
      fail(last_line, "the header says rows=" + std::to_string(*header_rows_) + " but the file has " +
                          std::to_string(rows_) + " data rows");
    }
    if (header_cols_ && *header_cols_ != cols_) {
      fail(first_row_line_, "the header says cols=" + std::to_string(*header_cols_) + " but the rows have " +
                                std::to_string(cols_) + " fields");
    }
    Eigen::MatrixXf grid(static_cast<Eigen::Index>(rows_), static_cast<Eigen::Index>(cols_));
    for (std::size_t i = 0; i < rows_; ++i) {
      for (std::size_t j = 0; j < cols_; ++j) {
        grid(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = values_[i * cols_ + j];
      }
    }
    return grid;
  }

  std::size_t rows() const { return rows_; }
  const GridCsvOptions& metadata() const { return metadata_; }

 private:
  float parse_field(std::string_view field, std::size_t index, std::size_t line_number) const {
    const std::string where = "field " + std::to_string(index) + ": ";
    if (field.empty()) fail(line_number, where + "empty (write nan for an unknown cell)");
    float value = 0.0F;
    const auto result = std::from_chars(field.data(), field.data() + field.size(), value);
    if (result.ec == std::errc::result_out_of_range) {
      fail(line_number, where + "'" + std::string(field) + "' is out of float range");
    }
    if (result.ec != std::errc() || result.ptr != field.data() + field.size()) {
      fail(line_number, where + "'" + std::string(field) + "' is not a number");
    }
    return value;
  }

  std::size_t parse_count(std::string_view text, std::string_view key, std::size_t line_number) const {
    std::size_t count = 0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), count);
    if (result.ec != std::errc() || result.ptr != text.data() + text.size()) {
      fail(line_number, "header " + std::string(key) + "='" + std::string(text) + "' is not a count");
    }
    return count;
  }

  double parse_real(std::string_view text, std::string_view key, std::size_t line_number) const {
    double value = 0.0;
    const auto result = std::from_chars(text.data(), text.data() + text.size(), value);
    if (result.ec != std::errc() || result.ptr != text.data() + text.size() || !std::isfinite(value)) {
      fail(line_number, "header " + std::string(key) + "='" + std::string(text) + "' is not a finite number");
    }
    return value;
  }

  std::string path_;
  std::vector<float> values_;
  std::size_t rows_ = 0;
  std::size_t cols_ = 0;
  std::size_t first_row_line_ = 0;
  std::optional<std::size_t> header_rows_;
  std::optional<std::size_t> header_cols_;
  GridCsvOptions metadata_;
};

}  // namespace

void write_grid_csv(const std::string& path, const Eigen::MatrixXf& values, const GridCsvOptions& options) {
  if (values.size() == 0) {
    throw InputError("cannot write grid CSV '" + path + "': the grid is empty (" + std::to_string(values.rows()) +
                     " x " + std::to_string(values.cols()) + " cells)");
  }
  check_header_text(path, "layer_name", options.layer_name);
  check_header_text(path, "units", options.units);
  std::string header(kHeaderTag);
  if (!options.layer_name.empty()) header += "; layer=" + options.layer_name;
  if (!options.units.empty()) header += "; units=" + options.units;
  header += "; rows=" + std::to_string(values.rows()) + "; cols=" + std::to_string(values.cols());
  append_option(path, header, "cell_size_m", options.cell_size_m);
  append_option(path, header, "origin_x_m", options.origin_x_m);
  append_option(path, header, "origin_y_m", options.origin_y_m);
  header += "; rows_along=+x; cols_along=+y; unknown=nan\n";

  detail::AtomicOutputFile out(path, "grid CSV");
  out.write(header.data(), header.size());
  std::string line;
  for (Eigen::Index i = 0; i < values.rows(); ++i) {
    line.clear();
    for (Eigen::Index j = 0; j < values.cols(); ++j) {
      if (j > 0) line += ',';
      append_cell_number(line, values(i, j));
    }
    line += '\n';
    out.write(line.data(), line.size());
  }
  out.commit();
}

Eigen::MatrixXf read_grid_csv(const std::string& path, GridCsvOptions* metadata) {
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) {
    throw InputError("cannot read grid CSV '" + path + "': it is a folder");
  }
  std::ifstream file(path, std::ios::binary);
  if (!file) {
    const int error_number = errno;
    throw InputError("cannot read grid CSV '" + path + "': " +
                     (error_number == ENOENT ? std::string("the file does not exist")
                                             : "cannot open it (" + std::generic_category().message(error_number) + ")"));
  }
  return read_grid_csv(file, path, metadata);
}

Eigen::MatrixXf read_grid_csv(std::istream& input, const std::string& source_name, GridCsvOptions* metadata) {
  CsvReader reader(source_name);
  std::string line;
  std::size_t line_number = 0;
  std::size_t blank_line = 0;  // first blank line after data, an error if more data follows
  while (std::getline(input, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string_view text = trim_cell(line);
    if (text.empty()) {
      if (reader.rows() > 0 && blank_line == 0) blank_line = line_number;
      continue;
    }
    if (text.front() == '#') {
      reader.parse_header(text, line_number);
      continue;
    }
    if (blank_line != 0) reader.fail(blank_line, "blank line between data rows");
    reader.parse_row(text, line_number);
  }
  if (input.bad()) throw InputError("cannot read grid CSV '" + source_name + "': read failed");
  Eigen::MatrixXf grid = reader.finish(line_number);
  if (metadata != nullptr) *metadata = reader.metadata();
  return grid;
}

}  // namespace stridemap::io
