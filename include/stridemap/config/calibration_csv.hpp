#pragma once
// (measured, true) range pairs for the range calibration fit (Fig. 6), read
// from a small CSV file that a user writes by hand or from a logging script.
//
// Format: the first line that is neither blank nor a comment is the header,
// naming two columns: one of `measured_m` / `measured_mm` and one of
// `true_m` / `true_mm`, in either order (millimetre columns are converted to
// metres). Then one pair per line, comma separated. `#` starts a comment that
// runs to the end of the line; blank lines are ignored; spaces around fields
// and Windows line ends are accepted.
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

namespace stridemap {

struct RangePairs {
  std::vector<double> measured_m;  ///< raw sensor range of each pair [m]
  std::vector<double> true_m;      ///< reference range of each pair [m]
  std::vector<int> line;           ///< 1-based source line of each pair
};

/// Reads the pairs from a file. Throws InputError naming the file, the line
/// and what is wrong: missing file, no header, unknown or duplicate columns,
/// wrong column count, a non-numeric, non-finite or non-positive value, or
/// fewer than 4 pairs (too few to fit a cubic).
RangePairs read_range_pairs_csv(const std::filesystem::path& path);

/// Same, from a stream; source_name stands for the file in messages.
RangePairs read_range_pairs_csv(std::istream& input, const std::string& source_name);

}  // namespace stridemap
