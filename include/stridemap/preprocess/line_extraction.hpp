#pragma once
// Co-linear groups of a 2D scan by split-and-merge (algorithms.md section 3):
// pre-segment at range breaks (the range-clustering test) and invalid beams,
// split each cluster recursively at the point farthest from the chord between
// its end points, merge neighbouring pieces whose union is still a line, and
// keep the pieces long enough to be structure. The scan-sequence filter uses
// it on scan k-1 to find edges across the scan.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "stridemap/core/planar_scan.hpp"
#include "stridemap/preprocess/beam_directions.hpp"
#include "stridemap/preprocess/range_clustering.hpp"
#include "stridemap/preprocess/range_sigma.hpp"

namespace stridemap {

struct LineExtractionOptions {
  /// beta_max of the pre-segmentation break test (as in range clustering) [rad].
  double max_incidence_angle_rad = 75.0 * 3.14159265358979323846 / 180.0;
  /// Noise allowance of the break test in standard deviations.
  double break_noise_sigmas = 3.0;
  /// A piece is split when a point lies farther than
  /// max(split_noise_sigmas * sigma_r, min_split_distance_m) from its chord.
  double split_noise_sigmas = 3.0;
  /// Lower limit of the split distance [m] (algorithms.md 3.3: 5 mm).
  double min_split_distance_m = 0.005;
  /// Segments with fewer points are dropped (algorithms.md 2.6: 8).
  std::size_t min_points = 8;
  /// Segments shorter than this are dropped [m] (about 3 map cells).
  double min_length_m = 0.04;
  /// Turns a beam's Delta r into sigma_r.
  RangeSigmaModel sigma;
  /// To decide whether a segment occludes what lies beyond an end, the first
  /// valid beam within this many beams past the end is compared with it, so
  /// that a few dropouts or removed points at an edge do not hide the jump.
  std::size_t occlusion_search_beams = 3;

  /// Throws InputError naming `owner` and the field when an option is out of range.
  void validate(const char* owner) const;
};

/// One co-linear group of beams, fitted by total least squares in the sensor
/// frame: points p with p . n = distance_m, n = (cos normal_angle, sin normal_angle).
struct LineSegment {
  std::size_t first_beam = 0;   ///< index of the first beam of the segment
  std::size_t last_beam = 0;    ///< index of the last beam (inclusive)
  std::size_t point_count = 0;  ///< valid beams in [first_beam, last_beam]
  double normal_angle_rad = 0.0;
  double distance_m = 0.0;      ///< distance of the line from the sensor (>= 0)
  double length_m = 0.0;        ///< extent of the points along the line
  double max_residual_m = 0.0;  ///< largest distance of a point from the line
  double mid_x_m = 0.0;         ///< centroid of the points, sensor frame
  double mid_y_m = 0.0;
  /// The first valid beam before first_beam (within occlusion_search_beams)
  /// breaks from the segment, is farther away and lies off the segment's line
  /// (by more than the split distance): the segment occludes what lies behind
  /// it at that end. A surface that merely continues at grazing incidence is
  /// no occlusion.
  bool occludes_before = false;
  bool occludes_after = false;  ///< the same after last_beam
};

/// Holds the scratch buffers; extract() allocates nothing once they have grown.
class LineExtractor {
 public:
  explicit LineExtractor(const LineExtractionOptions& options = {});

  const LineExtractionOptions& options() const { return options_; }

  /// Which segments extract() hands back.
  enum class Keep : std::uint8_t {
    all,
    /// Only those with occludes_before or occludes_after: the same segments
    /// as `all` with the others left out, found for less (a cluster neither
    /// of whose ends can occlude is not split, and one whose last end cannot
    /// is split and merged only up to its first segment).
    occluding,
  };

  /// Segments of `scan` in beam order. Invalid beams (range not finite and
  /// positive) never belong to a segment. The scan must be well formed
  /// (check_scan_shape); it is not modified. `known`, when given, is range
  /// clustering's test on this very scan (RangeBreaks): where that is this
  /// extractor's pre-segmentation test (the same band, noise sigmas and
  /// sigma model) it is taken instead of testing every pair again.
  void extract(const PlanarScan& scan, std::vector<LineSegment>& segments, Keep keep = Keep::all,
               const RangeBreaks* known = nullptr);

  /// cos/sin of the angles of the scan given to extract() last.
  const BeamDirections& directions() const { return directions_; }

 private:
  struct Piece {
    std::size_t first = 0;
    std::size_t last = 0;
  };
  // The next piece, in beam order, of the cluster on stack_ (split until it
  // lies within split_distance_m of its chord); false when none is left.
  bool next_piece(double split_distance_m, Piece& piece);
  std::size_t farthest_from_chord(const Piece& piece, double ax, double ay, double dx, double dy, bool plain,
                                  double split_distance_m) const;
  std::size_t farthest_from_point(const Piece& piece, double ax, double ay, double split_distance_m) const;
  // Sums of x and y over the beams from a piece's first up to `next`, added
  // in beam order: a merge candidate's continue those of the piece it grows
  // (grown()), the same additions in the same order as summing it from
  // scratch.
  struct PointSums {
    double x = 0.0;
    double y = 0.0;
    std::size_t next = 0;
  };
  void add_points(PointSums& sums, std::size_t last) const;
  struct Moments {
    double mean_x = 0.0;
    double mean_y = 0.0;
    double sxx = 0.0;  // about the means
    double syy = 0.0;
    double sxy = 0.0;
  };
  Moments moments(std::size_t first, std::size_t last, const PointSums& sums) const;
  Moments grown(const Moments& m, std::size_t first, std::size_t new_last, PointSums& sums) const;
  // Whether every point lies within max_residual_m of the line fit() makes.
  bool within(std::size_t first, std::size_t last, const Moments& m, double max_residual_m, double max_range_m) const;
  struct Normal {
    double x = 0.0;
    double y = 0.0;
  };
  // False, `line` unfinished, once a point lies farther than max_residual_m
  // from the line; `normal` is its unit normal, for occludes().
  bool fit(std::size_t first, std::size_t last, const Moments& m, double max_residual_m, LineSegment& line,
           Normal& normal) const;
  void process_cluster(const PlanarScan& scan, std::size_t first, std::size_t last, Keep keep,
                       std::vector<LineSegment>& segments);
  std::size_t occluded_beam(const PlanarScan& scan, std::size_t end_beam, bool forward) const;
  bool occludes(std::size_t beyond_beam, const PlanarScan& scan, const LineSegment& line, const Normal& normal,
                double split_distance_m) const;

  LineExtractionOptions options_;
  BeamDirections directions_;
  mutable RangeRatioBandMemo bands_;  // a cache: occluded_beam() stays a query
  std::vector<std::uint8_t> breaks_;
  std::vector<double> x_m_;  // only inside the clusters process_cluster() splits
  std::vector<double> y_m_;
  std::vector<Piece> stack_;  // parts of a cluster not yet split into pieces
};

}  // namespace stridemap
