#include "workspace_proximity/perception/laser_scan.hpp"

#include <cmath>

namespace workspace_proximity {
namespace perception {

int ScanBand::layers() const {
  // A band scanToPoints would refuse counts as one layer here (no cast of a huge ratio).
  if (!(z_max > z_min) || !(z_step > 0.0f) || !((z_max - z_min) / z_step < 1e5f)) return 1;
  // The small slack keeps z_max itself when the band is a whole number of steps.
  return static_cast<int>(std::floor((z_max - z_min) / z_step + 1e-4f)) + 1;
}

ScanResult scanToPoints(const ScanView& scan, const ScanBand& band, float* xyz,
                        std::int64_t capacity) {
  ScanResult r;
  const bool header_ok = std::isfinite(scan.angle_min) && std::isfinite(scan.angle_increment) &&
                         std::isfinite(scan.range_min) && std::isfinite(scan.range_max) &&
                         scan.count >= 0 && (scan.count == 0 || scan.ranges != nullptr);
  const bool band_ok = std::isfinite(band.z_min) && std::isfinite(band.z_max) &&
                       std::isfinite(band.z_step) && band.z_step > 0.0f && band.z_max >= band.z_min &&
                       (band.z_max - band.z_min) / band.z_step < 1e5f;
  if (!header_ok || !band_ok || capacity < 0 || (capacity > 0 && xyz == nullptr)) {
    r.refused = true;
    return r;
  }
  const int layers = band.layers();
  for (std::int64_t i = 0; i < scan.count; ++i) {
    const float range = scan.ranges[i];
    // Negated: NaN is invalid too.
    if (!(range >= scan.range_min && range <= scan.range_max)) {
      ++r.invalid;
      continue;
    }
    ++r.beams;
    if (r.points + layers > capacity) {
      r.truncated = true;
      continue;
    }
    // The angle from its index, not by summing increments: no drift over 1000 beams.
    const float angle = scan.angle_min + static_cast<float>(i) * scan.angle_increment;
    const float x = range * std::cos(angle);
    const float y = range * std::sin(angle);
    for (int k = 0; k < layers; ++k) {
      float* p = xyz + 3 * r.points;
      p[0] = x;
      p[1] = y;
      p[2] = std::fmin(band.z_min + static_cast<float>(k) * band.z_step, band.z_max);
      ++r.points;
    }
  }
  return r;
}

}  // namespace perception
}  // namespace workspace_proximity
