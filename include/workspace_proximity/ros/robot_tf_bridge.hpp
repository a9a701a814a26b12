#pragma once
/// Robot bodies posed from tf every cycle: the newest transform of each body's frame into the
/// fixed frame, extrapolated to the cycle instant with a velocity from finite differences over
/// ~velocity_window of tf history. A body tf cannot pose (missing, older than ~tf_timeout,
/// stamped ahead of the clock) is marked unknown in the monitor; a body whose history is still
/// shorter than the window (at start-up and after every reset) is posed but stale, since its
/// velocity is not known yet. Needs no master.

#include <cstdint>
#include <string>
#include <vector>

#include <tf2/buffer_core.h>

#include "workspace_proximity/rules/monitor.hpp"

namespace workspace_proximity {

class RobotTfBridge {
 public:
  /// `monitor` and `tf` are borrowed.
  RobotTfBridge(Monitor* monitor, tf2::BufferCore* tf);

  /// Poses every robot body at `now`, except those another bridge poses (setClaimed).
  void update(Stamp now);
  /// Robot body i is posed by another bridge (the joint states), not from tf.
  void setClaimed(int i, bool claimed);

  /// Motion of `frame` (times `offset`) in the fixed frame at `now`, as for a body: false with
  /// the reason when tf cannot give it; a non-empty `stale` when its velocity is not known yet.
  bool frameMotion(const std::string& frame, const Eigen::Isometry3d& offset, Stamp now,
                   BodyMotion* motion, std::string* why, std::string* stale);

  /// Robot body poses tf could not give.
  std::uint64_t tfFailures() const { return tf_failures_; }

 private:
  // Motion of robot body i at `now`; false with the reason when tf cannot give it. A body
  // whose velocity is not known yet is given a motion without velocity and a `stale` reason.
  bool motionOf(int i, Stamp now, BodyMotion* motion, std::string* why, std::string* stale);

  Monitor* monitor_;
  tf2::BufferCore* tf_;
  const MonitorParams& params_;
  std::uint64_t tf_failures_ = 0;
  std::vector<std::uint8_t> claimed_;  // per robot body
};

}  // namespace workspace_proximity
