#pragma once
/// The monitor: the node's logic without ROS. It owns the ProximityWorld, the tracks, the
/// robot bodies and the input sources, and runs one cycle as
///   input (arrays -> TrackTable, robot poses -> RobotBodies) -> world.predict -> CycleReport,
/// the report including the speed and separation verdict (SsmCycle).
/// The ROS bridges feed it and render its report; the offline replay feeds it from a bag.
/// CycleRunner (cycle_runner.hpp) runs its cycle with reset, failure and timing.

#include <cstdint>
#include <string>
#include <vector>

#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/cycle_report.hpp"
#include "workspace_proximity/rules/cycle_timing.hpp"
#include "workspace_proximity/rules/drop.hpp"
#include "workspace_proximity/rules/level_policy.hpp"
#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/rules/perception_health.hpp"
#include "workspace_proximity/rules/robot_bodies.hpp"
#include "workspace_proximity/rules/source_table.hpp"
#include "workspace_proximity/rules/ssm_cycle.hpp"
#include "workspace_proximity/rules/stamp.hpp"
#include "workspace_proximity/rules/track_table.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace workspace_proximity {

/// Places an array's boxes in the fixed frame for Monitor::ingest, which asks only once the
/// array's stamp has passed its checks (no tf lookup is spent on an array refused anyway).
class ArrayPlacement {
 public:
  virtual ~ArrayPlacement() = default;
  /// The pose of the array's frame in the fixed frame at `stamp`, and its boxes in that frame
  /// (valid until ingest returns). False when the array is not used: a drop the placement
  /// counted itself (Monitor::drop), or the array waits.
  virtual bool place(Stamp stamp, Eigen::Isometry3d* fixed_from_frame,
                     const std::vector<BoxObservation>** boxes) = 0;
};

/// The monitor's counts at a glance, for diagnostics and summaries.
struct MonitorStatus {
  std::uint64_t cycles = 0;  ///< cycles run (failed ones not counted)
  std::uint64_t resets = 0;  ///< history resets: the clock went back
  Stamp last_cycle = 0;      ///< instant of the last cycle, ns (0: none yet)
  int tracks = 0;            ///< tracks now
  int robot_bodies = 0;
  int robot_unposed = 0;     ///< robot bodies not posed this cycle (stale or never seen)
  double ssm_reach = 0.0;    ///< m: how far from the robot the speed and separation check looks
};

class Monitor {
 public:
  /// `params` must have passed validate(). `robot`: every robot body (URDF and ~robot_bodies).
  /// `sources`: resolved input topic names; with `qualify` track ids are prefixed by them.
  /// `sink` (may be null) hears of every rejection.
  Monitor(const MonitorParams& params, std::vector<RobotBodySpec> robot,
          const std::vector<std::string>& sources, bool qualify, RejectionSink* sink);
  Monitor(const Monitor&) = delete;
  Monitor& operator=(const Monitor&) = delete;

  // ---- input ----
  /// An array of source `i` arrived at `now`.
  void noteReceipt(int source, Stamp now) { sources_.noteReceipt(source, now); }
  /// One array of source `source`, stamped `stamp`, at `now`: its stamp is checked first (kFuture,
  /// kOld, kOutOfOrder are counted and reported), then `array` places its boxes in the fixed
  /// frame and they become tracks. Returns true when the array was used (its stamp passed and
  /// `array` placed it).
  bool ingest(int source, Stamp stamp, Stamp now, ArrayPlacement* array);
  /// As above for boxes already placed: `fixed_from_frame` is the pose of their frame in the
  /// fixed frame at `stamp`.
  bool ingest(int source, Stamp stamp, Stamp now, const Eigen::Isometry3d& fixed_from_frame,
              const std::vector<BoxObservation>& boxes);
  /// Counts (and reports) a drop of source `source`'s data decided outside the monitor (frame,
  /// superseded, failures).
  void drop(Drop reason, int source, std::string detail);
  /// Source `source`'s message is of a type or version it cannot read (foreign_types.hpp):
  /// dropped as kMessageType, and every status is DEGRADED with `detail` until acceptType().
  void refuseType(int source, const std::string& detail) {
    sources_.setRefusedType(source, detail);
    drop(Drop::kMessageType, source, detail);
  }
  /// Source `source`'s message is of a type it reads (ends refuseType's DEGRADED line).
  void acceptType(int source) {
    if (!sources_.source(source).refused_type.empty()) sources_.setRefusedType(source, {});
  }
  /// Robot body i this cycle (RobotBodies::pose, posePath, markUnknown): the robot bridges.
  bool poseRobot(int i, const BodyMotion& motion, const std::string& stale_reason = std::string()) {
    return robot_.pose(i, motion, stale_reason);
  }
  bool poseRobotPath(int i, const MotionSegment* segments, int count,
                     const std::string& stale_reason = std::string()) {
    return robot_.posePath(i, segments, count, stale_reason);
  }
  void markRobotUnknown(int i, const std::string& why) { robot_.markUnknown(i, why); }
  /// A problem that lasts as long as the node runs (e.g. a robot link that cannot be
  /// modelled): every cycle's status is DEGRADED with this line.
  void addPermanentIssue(const std::string& line) { permanent_issues_.push_back(line); }
  /// The perception front ends' statuses (~perception_status_topics, in that order): the
  /// bridges report each one received; the cycle's status and unseen share follow them.
  PerceptionHealth& perception() { return perception_; }
  const PerceptionHealth& perception() const { return perception_; }

  /// New parameters from now on (live tuning): horizon, timeouts, label margins and thresholds,
  /// the robot margin, pair rules and the track cap take effect at the next cycle; a changed
  /// margin re-shapes the bodies it applies to. The structure (fixed frame, input topics, robot
  /// bodies, the SSM outputs, the cycle trigger) stays as built. `params` must have passed
  /// validate().
  void setParams(const MonitorParams& params);

  // ---- the cycle (CycleRunner runs it: reset, failure and timing) ----
  /// True when `now` is before the last cycle (bag loop, simulation reset): call reset().
  bool clockWentBack(Stamp now) const { return last_cycle_ != 0 && now < last_cycle_; }
  /// Forgets every stamp: tracks (their pairs END), robot poses, sources' receipts.
  void reset();
  /// Expires old tracks, moves every track to `now`, predicts and builds the report.
  /// `clock` laps kInput after the track updates and kPredict after ProximityWorld::predict;
  /// the report, status and SSM verdict count towards the caller's next lap (kContacts).
  const CycleReport& cycle(Stamp now, StageClock* clock);
  /// A cycle failed (an exception): the next report says so; counted.
  void cycleFailed(Stamp now, const std::string& what);

  // ---- what it knows ----
  const CycleReport& report() const { return report_; }
  /// Counts at a glance (diagnostics, summaries).
  MonitorStatus status() const;
  const ProximityWorld& world() const { return world_; }
  const TrackTable& tracks() const { return tracks_; }
  const RobotBodies& robot() const { return robot_; }
  const SourceTable& sources() const { return sources_; }
  const DropCounters& drops() const { return drops_; }
  const LabelTable& labels() const { return labels_; }
  const MonitorParams& params() const { return params_; }
  /// The speed and separation stop latch: reset and mute requests, joint speeds (between cycles).
  StopLatch& latch() { return ssm_.latch(); }

 private:
  void buildStatus(Stamp now);

  MonitorParams params_;
  LabelTable labels_;
  RejectionSink* sink_;
  ProximityWorld world_;
  DropCounters drops_;
  SourceTable sources_;
  TrackTable tracks_;
  RobotBodies robot_;
  SsmCycle ssm_;
  std::vector<std::string> permanent_issues_;
  PerceptionHealth perception_;
  CycleReport report_;
  std::string detail_;  // scratch for rejections

  Stamp last_cycle_ = 0;
  std::uint64_t cycles_ = 0;
  std::uint64_t resets_ = 0;
};

}  // namespace workspace_proximity
