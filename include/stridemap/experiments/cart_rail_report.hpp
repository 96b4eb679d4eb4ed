#pragma once
// Outputs of the cart-rail experiment: PNG maps with legends, the grids as
// CSV, summary.json (shape documented in docs/experiments.md) and the
// printed table.
#include <string>

#include "stridemap/experiments/cart_rail.hpp"

namespace stridemap {

struct CartRailRunInfo {
  std::string sensor = "urg";
  std::string scene_path;
};

/// summary.json's text.
std::string cart_rail_summary_json(const CartRailResult& result, const CartRailOptions& options,
                                   const CartRailRunInfo& info);

/// The numbers of summary.json as a table for the terminal.
std::string cart_rail_table(const CartRailResult& result, const CartRailRunInfo& info);

/// Writes everything into `directory` (created if missing). Throws
/// InputError naming the file when something cannot be written.
void write_cart_rail_outputs(const CartRailResult& result, const CartRailOptions& options,
                             const CartRailRunInfo& info, const std::string& directory);

}  // namespace stridemap
