#pragma once
// A map layer as a CSV table, for spreadsheets, numpy and pandas
// (docs/outputs.md describes the format):
//
//   # stridemap grid; layer=elevation; units=m; rows=100; cols=100; cell_size_m=0.01; ...
//   0.0125,0.013,nan,...
//
// One line per matrix row (row i = cell i along +X), one field per column
// (column j = cell j along +Y), values in the shortest decimal form that
// reads back to the same float, unknown cells as `nan`, infinities as `inf`
// and `-inf`.
#include <Eigen/Core>
#include <istream>
#include <optional>
#include <string>

namespace stridemap::io {

struct GridCsvOptions {
  // Name of the layer ("elevation", "certainty"); empty leaves it out.
  std::string layer_name;
  // Unit of the values ("m"); empty leaves it out.
  std::string units;
  // Cell side in metres; empty leaves it out.
  std::optional<double> cell_size_m;
  // Map-frame position of the centre of cell (0, 0), metres; empty leaves it out.
  std::optional<double> origin_x_m;
  std::optional<double> origin_y_m;
};

// Writes the grid with a one-line `#` header holding the options. The file
// appears at `path` only when complete (temporary file + rename). Throws
// InputError naming the path and the reason: empty grid, a text option that
// holds ';', '=' or a line break (it would break the header), a non-finite
// cell size or origin, missing or read-only folder, write failure.
void write_grid_csv(const std::string& path, const Eigen::MatrixXf& values, const GridCsvOptions& options);

// Reads a grid written by write_grid_csv, or any comma-separated table of
// numbers (`nan`, any case, for unknown; spaces around fields are allowed,
// empty fields are not). Lines starting with '#' are comments; the keys of a
// stridemap header fill `*metadata` when given. Throws InputError naming the
// file and the line (and field) of: a missing file, a non-numeric or empty
// field, a row whose field count differs from the first row's, a blank line
// between rows, rows/cols that contradict the header, or no data at all.
Eigen::MatrixXf read_grid_csv(const std::string& path, GridCsvOptions* metadata = nullptr);

// Same, from a stream; source_name stands for the file in messages.
Eigen::MatrixXf read_grid_csv(std::istream& input, const std::string& source_name,
                              GridCsvOptions* metadata = nullptr);

}  // namespace stridemap::io
