#pragma once
/// A planar laser scan as points: each valid range becomes a column of points in the scan
/// frame, from z_min to z_max (a floor scanner sees only legs: the column stands for the
/// person above and below the scan plane). ROS-free; writes into the caller's array.

#include <cstdint>

namespace workspace_proximity {
namespace perception {

/// Borrowed view of one sensor_msgs/LaserScan's numbers.
struct ScanView {
  const float* ranges = nullptr;
  std::int64_t count = 0;
  float angle_min = 0.0f;        ///< rad, beam 0, about the scan frame's z from its x
  float angle_increment = 0.0f;  ///< rad between beams
  float range_min = 0.0f;        ///< m; shorter ranges are invalid
  float range_max = 0.0f;        ///< m; longer ranges (and inf: no return) are invalid
};

/// The height band over which each beam's point is repeated.
struct ScanBand {
  float z_min = 0.0f;   ///< m, scan frame
  float z_max = 1.8f;   ///< m, scan frame
  /// m between points of a column: at most half the voxel size, so that float rounding at
  /// voxel faces never leaves a voxel of the column empty (one column, one cluster).
  float z_step = 0.025f;

  /// Points per column: floor((z_max - z_min) / z_step) + 1 (1 for an empty band).
  int layers() const;
};

struct ScanResult {
  std::int64_t points = 0;   ///< xyz triples written
  std::int64_t beams = 0;    ///< valid beams
  std::int64_t invalid = 0;  ///< NaN, inf, out of [range_min, range_max]
  bool truncated = false;    ///< out of capacity: some valid beams were not written
  bool refused = false;      ///< a bad band or header (non-finite, step <= 0): nothing written
};

/// Writes the scan's points (x, y, z floats, packed) into `xyz`, at most `capacity` points.
ScanResult scanToPoints(const ScanView& scan, const ScanBand& band, float* xyz,
                        std::int64_t capacity);

}  // namespace perception
}  // namespace workspace_proximity
