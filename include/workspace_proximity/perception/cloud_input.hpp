#pragma once
/// A point cloud as the perception front end reads it: float x, y, z at a given stride in a
/// flat byte array (sensor_msgs/PointCloud2's layout, without ROS), organised (height > 1)
/// or not. ROS-free.

#include <cstdint>

namespace workspace_proximity {
namespace perception {

/// Why a whole cloud is refused. A refused cloud changes nothing; the rest keeps working.
enum class CloudRejection : std::uint8_t {
  kNone = 0,
  kMissingXyz,     ///< no float32 x, y or z field (offset -1)
  kBadLayout,      ///< steps, offsets or sizes that do not fit the data
  kTooManyPoints,  ///< more points than the configured capacity: an absurd size
};

/// Snake-case name of a rejection ("missing_xyz", ...), for logs and diagnostics.
const char* cloudRejectionName(CloudRejection rejection);

/// Borrowed view of one cloud's bytes. Each point's x, y, z are native-endian float32.
struct CloudView {
  const std::uint8_t* data = nullptr;
  std::int64_t data_size = 0;   ///< bytes at `data`
  std::int64_t width = 0;       ///< points per row
  std::int64_t height = 1;      ///< rows; 1: unorganised
  std::int64_t point_step = 0;  ///< bytes from one point to the next within a row
  std::int64_t row_step = 0;    ///< bytes from one row to the next
  int x_offset = -1;            ///< bytes into a point; -1: no float32 x field
  int y_offset = -1;
  int z_offset = -1;

  std::int64_t points() const { return width * height; }
};

/// kNone when every point's x, y and z lie inside the data and the cloud has at most
/// `max_points` points; otherwise the first problem found.
CloudRejection checkCloud(const CloudView& cloud, std::int64_t max_points);

/// A view of `count` packed xyz float triples (12 bytes a point, unorganised).
CloudView packedXyz(const float* xyz, std::int64_t count);

}  // namespace perception
}  // namespace workspace_proximity
