#include <cmath>
#include <cstddef>
#include <random>
#include <string>
#include <vector>

#include "stridemap/core/error.hpp"
#include "stridemap/sim/height_field.hpp"

namespace stridemap {
namespace {

// Samples along one axis so that the grid covers [lo, hi]; the last sample
// may lie up to one resolution step beyond hi.
double samples_along(double lo, double hi, double resolution_m) {
  return std::ceil((hi - lo) / resolution_m - 1e-9) + 1.0;
}

// C2-continuous fade, so that slopes and curvature are continuous across
// lattice cells (no creases for the ray caster to catch on).
double quintic_fade(double t) { return t * t * t * (t * (t * 6.0 - 15.0) + 10.0); }

struct Lattice {
  double spacing_m = 1.0;
  int columns = 0;
  std::vector<double> values;  ///< uniform in [-1, 1], row-major

  double at(double gx, double gy) const {
    const int i = static_cast<int>(std::floor(gx));
    const int j = static_cast<int>(std::floor(gy));
    const double sx = quintic_fade(gx - i), sy = quintic_fade(gy - j);
    const auto value = [&](int ii, int jj) {
      return values[static_cast<std::size_t>(jj) * static_cast<std::size_t>(columns) + ii];
    };
    const double bottom = value(i, j) + sx * (value(i + 1, j) - value(i, j));
    const double top = value(i, j + 1) + sx * (value(i + 1, j + 1) - value(i, j + 1));
    return bottom + sy * (top - bottom);
  }
};

}  // namespace

std::optional<SceneProblem> ProceduralTerrainOptions::first_problem() const {
  using namespace scene_rules;
  const auto problem = [](std::string field, std::string message) {
    return std::optional<SceneProblem>(SceneProblem{std::move(field), "", std::move(message)});
  };
  const std::pair<const char*, double> extent[] = {
      {"extent.min_x_m", min_x_m}, {"extent.min_y_m", min_y_m}, {"extent.max_x_m", max_x_m}, {"extent.max_y_m", max_y_m}};
  for (const auto& [field, value] : extent) {
    if (auto message = finite(value)) return problem(field, *message);
  }
  if (!(max_x_m > min_x_m)) {
    return problem("extent.max_x_m", "expected a number greater than min_x_m = " + format_number(min_x_m) +
                                         ", got " + format_number(max_x_m));
  }
  if (!(max_y_m > min_y_m)) {
    return problem("extent.max_y_m", "expected a number greater than min_y_m = " + format_number(min_y_m) +
                                         ", got " + format_number(max_y_m));
  }
  if (auto message = positive(resolution_m)) return problem("resolution_m", *message);
  const double columns = samples_along(min_x_m, max_x_m, resolution_m);
  const double rows = samples_along(min_y_m, max_y_m, resolution_m);
  if (columns * rows > static_cast<double>(max_height_field_samples)) {
    return problem("resolution_m", "gives " + format_number(columns) + " x " + format_number(rows) +
                                       " samples over the extent, more than the limit of " +
                                       std::to_string(max_height_field_samples));
  }
  if (auto message = non_negative(amplitude_m)) return problem("amplitude_m", *message);
  if (auto message = positive(wavelength_m)) return problem("wavelength_m", *message);
  if (octaves < 1 || octaves > 8) {
    return problem("octaves", "expected a whole number from 1 to 8, got " + std::to_string(octaves));
  }
  if (wavelength_m / std::pow(2.0, octaves - 1) < 1e-6) {
    return problem("wavelength_m", "finest octave would be shorter than 1 micrometre");
  }
  // The noise lattices cover the sampled grid, which may reach a whole step
  // beyond the extent: a coarse resolution can make them far larger than the
  // samples themselves (found by fuzzing: 4 GB for a 2 x 2 sample grid).
  double lattice_values = 0.0;
  for (int k = 0; k < octaves; ++k) {
    const double spacing = wavelength_m / std::pow(2.0, k);
    lattice_values += (std::ceil((columns - 1.0) * resolution_m / spacing) + 2.0) *
                      (std::ceil((rows - 1.0) * resolution_m / spacing) + 2.0);
  }
  if (lattice_values > static_cast<double>(max_height_field_samples)) {
    return problem("wavelength_m", "needs " + format_number(lattice_values) +
                                       " noise lattice values over the sampled grid, more than the limit of " +
                                       std::to_string(max_height_field_samples) +
                                       " (make the wavelength or the resolution smaller, or use fewer octaves)");
  }
  if (auto message = finite(base_elevation_m)) return problem("base_elevation_m", *message);
  if (auto message = scene_rules::reflectance(reflectance)) return problem("reflectance", *message);
  return rock_field_problem(rocks);
}

HeightField make_procedural_height_field(const ProceduralTerrainOptions& options, std::uint64_t seed) {
  if (auto problem = options.first_problem()) {
    throw InputError(problem->field_path + ": " + problem->message);
  }
  HeightField field;
  field.resolution_m = options.resolution_m;
  field.base_elevation_m = options.base_elevation_m;
  field.reflectance = options.reflectance;
  field.nx = static_cast<int>(samples_along(options.min_x_m, options.max_x_m, options.resolution_m));
  field.ny = static_cast<int>(samples_along(options.min_y_m, options.max_y_m, options.resolution_m));
  field.min_x_m = options.min_x_m;
  field.min_y_m = options.min_y_m;
  field.max_x_m = options.min_x_m + (field.nx - 1) * options.resolution_m;
  field.max_y_m = options.min_y_m + (field.ny - 1) * options.resolution_m;

  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Lattice> lattices(static_cast<std::size_t>(options.octaves));
  double spacing = options.wavelength_m;
  for (Lattice& lattice : lattices) {
    lattice.spacing_m = spacing;
    lattice.columns = static_cast<int>(std::ceil((field.max_x_m - field.min_x_m) / spacing)) + 2;
    const int rows = static_cast<int>(std::ceil((field.max_y_m - field.min_y_m) / spacing)) + 2;
    lattice.values.resize(static_cast<std::size_t>(lattice.columns) * static_cast<std::size_t>(rows));
    for (double& value : lattice.values) value = uniform(rng);
    spacing *= 0.5;
  }
  // Weights halve per octave; dividing by their sum keeps the noise in
  // [-1, 1], since each octave interpolates values from [-1, 1] convexly.
  double weight_sum = 0.0;
  for (int k = 0; k < options.octaves; ++k) weight_sum += std::pow(0.5, k);

  field.samples.resize(static_cast<std::size_t>(field.nx) * static_cast<std::size_t>(field.ny));
  for (int j = 0; j < field.ny; ++j) {
    for (int i = 0; i < field.nx; ++i) {
      double noise = 0.0, weight = 1.0;
      for (const Lattice& lattice : lattices) {
        noise += weight * lattice.at(i * field.resolution_m / lattice.spacing_m, j * field.resolution_m / lattice.spacing_m);
        weight *= 0.5;
      }
      field.samples[static_cast<std::size_t>(j) * static_cast<std::size_t>(field.nx) + i] =
          static_cast<float>(options.base_elevation_m + options.amplitude_m * noise / weight_sum);
    }
  }
  add_rocks(options.rocks, seed, field);
  return field;
}

}  // namespace stridemap
