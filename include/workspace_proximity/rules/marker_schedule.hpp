#pragma once
/// When the node publishes markers (ROS-free): at most ~marker_rate, decided at each cycle,
/// and built half a period after the cycle that predicted them, so that their cost (and their
/// megabyte on the wire) never delays the contacts of the next cycle or coincides with this
/// one's delivery.

#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

class MarkerSchedule {
 public:
  /// The cycle at `now` publishes markers: true when a marker period (1 / `marker_rate`) less
  /// half a cycle (0.5 / `cycle_rate`) has passed since the last markers, so that 10 Hz on
  /// 30 Hz cycles is every third cycle; also the first time and after the clock went back.
  /// When true, `now` is the last markers' instant from then on. Rates in Hz.
  bool due(Stamp now, double marker_rate, double cycle_rate);

  /// Seconds after its cycle a MarkerArray is built: half a period of `cycle_rate` (Hz).
  static double delay(double cycle_rate) { return 0.5 / cycle_rate; }

 private:
  Stamp last_ = 0;  // instant of the last markers (0: none yet)
};

}  // namespace workspace_proximity
