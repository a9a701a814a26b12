#pragma once
/// The monitor: the node's logic without ROS. It owns the ProximityWorld, the tracks, the
/// robot bodies and the input sources, and runs one cycle as
///   input (arrays -> TrackTable, robot poses -> RobotBodies) -> world.predict -> CycleReport,
/// the report including the speed and separation verdict (SpeedSeparation).
/// The ROS bridges feed it and render its report; the offline replay feeds it from a bag.

#include <cstdint>
#include <string>
#include <vector>

#include "workspace_proximity/monitor/box_observation.hpp"
#include "workspace_proximity/monitor/cycle_report.hpp"
#include "workspace_proximity/monitor/cycle_timing.hpp"
#include "workspace_proximity/monitor/drop.hpp"
#include "workspace_proximity/monitor/level_policy.hpp"
#include "workspace_proximity/monitor/monitor_params.hpp"
#include "workspace_proximity/monitor/robot_bodies.hpp"
#include "workspace_proximity/monitor/source_table.hpp"
#include "workspace_proximity/monitor/speed_separation.hpp"
#include "workspace_proximity/monitor/stamp.hpp"
#include "workspace_proximity/monitor/track_table.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace workspace_proximity {

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
  /// Checks an array's stamp (kFuture, kOld, kOutOfOrder); a bad one is counted and reported.
  /// Returns true when the array may be used.
  bool acceptStamp(int source, Stamp stamp, Stamp now);
  /// One array's boxes, `fixed_from_frame` being the pose of its frame in the fixed frame at
  /// `stamp`. Call acceptStamp first.
  void ingest(int source, Stamp stamp, const Eigen::Isometry3d& fixed_from_frame,
              const std::vector<BoxObservation>& boxes);
  /// Counts (and reports) a drop of source `source`'s data decided outside the monitor (frame,
  /// superseded, failures).
  void drop(Drop reason, int source, std::string detail);
  /// A problem that lasts as long as the node runs (e.g. a robot link that cannot be
  /// modelled): every cycle's status is DEGRADED with this line.
  void addPermanentIssue(const std::string& line) { permanent_issues_.push_back(line); }

  /// New parameters from now on (live tuning): horizon, timeouts, label margins and thresholds,
  /// the robot margin, pair rules and the track cap take effect at the next cycle; a changed
  /// margin re-shapes the bodies it applies to. The structure (fixed frame, input topics, robot
  /// bodies, the SSM outputs, the cycle trigger) stays as built. `params` must have passed
  /// validate().
  void setParams(const MonitorParams& params);

  RobotBodies& robot() { return robot_; }
  const RobotBodies& robot() const { return robot_; }

  // ---- the cycle ----
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
  /// Wall time of the whole cycle, outputs included (the node measures it), ms.
  void noteCycleTime(double ms);

  // ---- what it knows ----
  const CycleReport& report() const { return report_; }
  const ProximityWorld& world() const { return world_; }
  const TrackTable& tracks() const { return tracks_; }
  const SourceTable& sources() const { return sources_; }
  const DropCounters& drops() const { return drops_; }
  const LabelTable& labels() const { return labels_; }
  const MonitorParams& params() const { return params_; }
  CycleTiming& timing() { return timing_; }
  const CycleTiming& timing() const { return timing_; }
  const SpeedSeparation& ssm() const { return ssm_; }
  std::uint64_t cycles() const { return cycles_; }
  std::uint64_t resets() const { return resets_; }
  Stamp lastCycle() const { return last_cycle_; }
  double lastCycleMs() const { return last_cycle_ms_; }
  double maxCycleMs() const { return max_cycle_ms_; }

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
  SpeedSeparation ssm_;
  std::vector<std::string> permanent_issues_;
  CycleReport report_;
  CycleTiming timing_;
  std::string detail_;  // scratch for rejections

  Stamp last_cycle_ = 0;
  std::uint64_t cycles_ = 0;
  std::uint64_t resets_ = 0;
  double last_cycle_ms_ = 0.0;
  double max_cycle_ms_ = 0.0;
};

}  // namespace workspace_proximity
