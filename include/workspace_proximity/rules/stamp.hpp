#pragma once
/// Time stamps of the rules layer: plain integers, so the layer needs no ROS and its
/// differences are exact (ros::Time arithmetic normalises through Durations, which is slow in
/// per-track loops and rounds nothing better).

#include <cstdint>

namespace workspace_proximity {

/// Nanoseconds since an arbitrary epoch (the ROS bridges use ros::Time::toNSec()). 0 means
/// "never" where a field says so.
using Stamp = std::int64_t;

/// t1 - t0 in seconds (exact to the nanosecond before the conversion to double).
inline double secondsBetween(Stamp t0, Stamp t1) { return static_cast<double>(t1 - t0) * 1e-9; }

/// A duration in seconds as nanoseconds (rounded to the nearest).
inline Stamp nanoseconds(double seconds) {
  return static_cast<Stamp>(seconds * 1e9 + (seconds >= 0.0 ? 0.5 : -0.5));
}

}  // namespace workspace_proximity
