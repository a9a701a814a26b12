#include "workspace_proximity/perception/cloud_input.hpp"

#include <algorithm>

namespace workspace_proximity {
namespace perception {

const char* cloudRejectionName(CloudRejection rejection) {
  switch (rejection) {
    case CloudRejection::kNone: return "none";
    case CloudRejection::kMissingXyz: return "missing_xyz";
    case CloudRejection::kBadLayout: return "bad_layout";
    case CloudRejection::kTooManyPoints: return "too_many_points";
  }
  return "unknown";
}

CloudRejection checkCloud(const CloudView& cloud, std::int64_t max_points) {
  if (cloud.x_offset < 0 || cloud.y_offset < 0 || cloud.z_offset < 0) {
    return CloudRejection::kMissingXyz;
  }
  if (cloud.width < 0 || cloud.height < 0 || cloud.data_size < 0) return CloudRejection::kBadLayout;
  if (cloud.width == 0 || cloud.height == 0) return CloudRejection::kNone;  // empty: fine
  // Before any product: width x height must not overflow.
  if (cloud.width > max_points || cloud.height > max_points ||
      cloud.width * cloud.height > max_points) {
    return CloudRejection::kTooManyPoints;
  }
  const std::int64_t field_end =
      4 + std::max(cloud.x_offset, std::max(cloud.y_offset, cloud.z_offset));
  if (cloud.data == nullptr || cloud.point_step < field_end || cloud.point_step > cloud.data_size) {
    return CloudRejection::kBadLayout;
  }
  // Each row's last point ends inside the row, rows do not overlap, the last row ends inside
  // the data (every product below is bounded by the checks before it: no overflow).
  const std::int64_t row_bytes = (cloud.width - 1) * cloud.point_step + field_end;
  if (cloud.height > 1 && (cloud.row_step < row_bytes || cloud.row_step > cloud.data_size)) {
    return CloudRejection::kBadLayout;
  }
  const std::int64_t last_row = cloud.height > 1 ? (cloud.height - 1) * cloud.row_step : 0;
  if (row_bytes > cloud.data_size || last_row > cloud.data_size - row_bytes) {
    return CloudRejection::kBadLayout;
  }
  return CloudRejection::kNone;
}

CloudView packedXyz(const float* xyz, std::int64_t count) {
  CloudView v;
  v.data = reinterpret_cast<const std::uint8_t*>(xyz);
  v.data_size = count * 12;
  v.width = count;
  v.height = 1;
  v.point_step = 12;
  v.row_step = count * 12;
  v.x_offset = 0;
  v.y_offset = 4;
  v.z_offset = 8;
  return v;
}

}  // namespace perception
}  // namespace workspace_proximity
