#pragma once
/// Speed and separation monitoring over one cycle: which robot-object pairs the rule sees, the
/// scale of each (ssm_rule.hpp's formula), the limiting pair, and the output a controller acts on
/// (capped while DEGRADED, with hysteresis). ROS-free; the monitor runs it every cycle.
///
/// A track's own errors (BoxObservation's position_error, velocity_error) count when its
/// tracker gave them: v_h = max(0, v . u + velocity_error, ssm_min_speed) for the direction u
/// towards the robot, and the pair needs max(0, position_error - Z_d) more than S_p (its d is
/// that much smaller). A track whose velocity is unknown has nominal velocity 0: v_h is its
/// label's ssm_min_speed (the `unknown` label's 1.6 m/s, the standard's walking speed).
///
/// Every pair within reach is considered, not only pairs with a predicted contact. A pair
/// allows full speed once d >= S_p(v_max) + extra with its own approach speed, and v_h is at
/// most max(|v| + velocity_error, ssm_min_speed) of the object, so no pair farther than
///   R = max over monitored tracks of S_p(v_max) + extra, v_h = max(|v| + e, ssm_min_speed)
/// can lower the scale. Before each predict, every robot body's reach in the world
/// (ProximityWorld::setReach) is set to R: the world's scan of the robot's bodies against
/// every body (ProximityWorld::predictNear, before the broad phase) then reports every object
/// whose bare shape is within R of a robot body now, with the distance and nearest points
/// (ProximityWorld::nearPairs). The robot's bodies get the reach, not the objects': they are
/// few, so the scan stays linear in the objects.

#include <cstdint>
#include <string>
#include <vector>

#include "workspace_proximity/rules/level_policy.hpp"
#include "workspace_proximity/rules/ssm_rule.hpp"
#include "workspace_proximity/rules/stamp.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace workspace_proximity {

class TrackTable;
class RobotBodies;

/// The latch's constants from the ~ssm/ parameters.
LatchParams latchParams(const SsmParams& params);

class SsmCycle {
 public:
  explicit SsmCycle(const SsmParams& params);
  /// New constants (live tuning) from the next cycle; the filter keeps its output.
  void setParams(const SsmParams& params);
  const SsmParams& params() const { return params_; }

  /// Before predict: which tracks are monitored (~ssm/labels), and every present robot body's
  /// reach set to R (0 while disabled). Allocation-free once the slots have been seen.
  void prepare(const TrackTable& tracks, const LabelTable& labels, const RobotBodies& robot,
               ProximityWorld* world);
  /// After predict: the rule over the world's near pairs, the DEGRADED cap (with the first of
  /// `status_lines` as the reason) and the filter at `now`, into `out`.
  void evaluate(Stamp now, const ProximityWorld& world, const TrackTable& tracks,
                const LabelTable& labels, const RobotBodies& robot, bool degraded,
                const std::vector<std::string>& status_lines, SsmVerdict* out);
  /// A cycle failed: nothing is known, the scale goes to at most degraded_scale.
  void failed(Stamp now, const std::string& why, SsmVerdict* out);
  /// Forgets the filter's history (clock went back): the output drops to 0; the latch keeps
  /// a stop (StopLatch::reset).
  void reset() {
    filter_.reset();
    latch_.reset();
  }
  /// The stop latch: restart interlock, stop category, muting. Requests (reset, mute, joint
  /// speeds) go to it between cycles.
  StopLatch& latch() { return latch_; }
  const StopLatch& latch() const { return latch_; }

  /// The largest reach set by the last prepare(), m.
  double reach() const { return reach_; }

 private:
  // Starts `out`: no pair read yet, the raw scale `raw_scale` (in [0, 1]), DEGRADED as
  // `degraded`. False when monitoring is off: `out` is then final (scale 1).
  bool startVerdict(double raw_scale, bool degraded, SsmVerdict* out) const;
  void output(Stamp now, bool degraded, SsmVerdict* out);

  SsmParams params_;
  SpeedScaleFilter filter_;
  StopLatch latch_;
  std::vector<std::uint8_t> monitored_;  // per world body slot: a monitored track
  std::vector<std::uint8_t> muted_;      // per world body slot: a muted track (this cycle)
  double reach_ = 0.0;
  char buffer_[256];  // reason text, formatted without allocating
};

}  // namespace workspace_proximity
