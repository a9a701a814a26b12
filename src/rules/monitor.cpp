#include "workspace_proximity/rules/monitor.hpp"

#include <algorithm>

namespace workspace_proximity {
namespace {

WorldConfig worldConfig(const MonitorParams& params) {
  WorldConfig config;
  config.rules = makePairRules(params);
  config.broad_phase.coast_updates = params.broad_phase_lead;
  config.pair_threads = params.pair_threads;
  return config;
}

}  // namespace

Monitor::Monitor(const MonitorParams& params, std::vector<RobotBodySpec> robot,
                 const std::vector<std::string>& sources, bool qualify, RejectionSink* sink)
    : params_(params),
      labels_(params_),
      sink_(sink),
      world_(worldConfig(params_)),
      sources_(sources, qualify),
      tracks_(&world_, &labels_, params_.max_tracks, BoxLimits(), &drops_, sink),
      robot_(&world_, std::move(robot), params_.robot_margin),
      ssm_(params_.ssm),
      perception_(params_.perception_status_topics) {}

namespace {

// Boxes already in a known frame (tests, benchmarks, a caller without tf).
class PlacedArray final : public ArrayPlacement {
 public:
  PlacedArray(const Eigen::Isometry3d& fixed_from_frame, const std::vector<BoxObservation>& boxes)
      : fixed_from_frame_(fixed_from_frame), boxes_(boxes) {}
  bool place(Stamp, Eigen::Isometry3d* fixed_from_frame,
             const std::vector<BoxObservation>** boxes) override {
    *fixed_from_frame = fixed_from_frame_;
    *boxes = &boxes_;
    return true;
  }

 private:
  const Eigen::Isometry3d& fixed_from_frame_;
  const std::vector<BoxObservation>& boxes_;
};

}  // namespace

bool Monitor::ingest(int source, Stamp stamp, Stamp now, const Eigen::Isometry3d& fixed_from_frame,
                     const std::vector<BoxObservation>& boxes) {
  PlacedArray array(fixed_from_frame, boxes);
  return ingest(source, stamp, now, &array);
}

bool Monitor::ingest(int source, Stamp stamp, Stamp now, ArrayPlacement* placement) {
  // The stamp first: a refused array costs no tf lookup.
  const Drop why =
      sources_.checkStamp(source, stamp, now, params_.max_future, params_.track_timeout, &detail_);
  if (why != Drop::kCount) {
    drop(why, source, detail_);
    return false;
  }
  ArrayContext array;
  const std::vector<BoxObservation>* boxes = nullptr;
  if (!placement->place(stamp, &array.fixed_from_frame, &boxes)) return false;
  const Source& s = sources_.source(source);
  sources_.accept(source, stamp);
  array.source = s.name;
  array.qualifier = s.qualifier;
  array.stamp = stamp;
  array.robot_centre = robot_.centre();
  Drop last_drop = Drop::kCount;
  const int used = tracks_.ingest(array, *boxes, &last_drop);
  if (last_drop != Drop::kCount) sources_.noteDrop(source, last_drop);
  // Data from this source: at least one box, or an empty scene (nothing there is news too).
  if (used > 0 || boxes->empty()) sources_.markUsed(source, s.last_receipt);
  return true;
}

void Monitor::setParams(const MonitorParams& params) {
  // The rules change; the wiring (frames, topics, the robot's bodies, the SSM's outputs: the
  // kWiring rows of param_table.hpp) stays as the monitor was built.
  MonitorParams next = params;
  keepWiring(params_, &next);
  params_ = std::move(next);
  labels_ = LabelTable(params_);
  tracks_.refreshSettings(params_.max_tracks);
  robot_.setMargin(params_.robot_margin);
  world_.setRules(makePairRules(params_));
  ssm_.setParams(params_.ssm);
}

void Monitor::drop(Drop reason, int source, std::string detail) {
  drops_.add(reason);
  if (reason != Drop::kSuperseded) sources_.noteDrop(source, reason);
  if (sink_ != nullptr) {
    sink_->onRejection(
        Rejection{reason, sources_.source(source).name, std::string_view(), std::move(detail)});
  }
}

void Monitor::reset() {
  ++resets_;
  tracks_.clear();
  robot_.clear();
  sources_.reset();
  perception_.reset();
  ssm_.reset();
}

const CycleReport& Monitor::cycle(Stamp now, StageClock* clock) {
  beginCycle(now, clock);
  return finishCycle(clock);
}

const CycleReport& Monitor::beginCycle(Stamp now, StageClock* clock) {
  last_cycle_ = now;
  tracks_.expire(now, params_.track_timeout);
  tracks_.advance(now);
  ssm_.prepare(tracks_, labels_, robot_, &world_);
  clock->lap(CycleStage::kInput);

  // The speed and separation verdict needs the pairs within reach and the status, not the
  // contacts: it is decided before them, so that the safety output never waits for the
  // contact window and narrow phase of every other pair (issue 26).
  world_.predictNear(params_.horizon);
  clock->lap(CycleStage::kNear);
  // This cycle's events are not predicted yet: the report has none until finishCycle().
  report_.stamp = now;
  report_.events = nullptr;
  buildStatus(now);
  ssm_.evaluate(now, world_, tracks_, labels_, robot_, report_.degraded, report_.status_lines,
                &report_.ssm);
  clock->lap(CycleStage::kSsm);
  return report_;
}

const CycleReport& Monitor::finishCycle(StageClock* clock) {
  const std::vector<PairEvent>& events = world_.predictEvents();
  clock->lap(CycleStage::kPredict);
  ReportInputs in;
  in.now = report_.stamp;
  in.events = &events;
  in.world = &world_;
  in.tracks = &tracks_;
  in.robot = &robot_;
  in.labels = &labels_;
  in.stale_after = params_.stale_after;
  buildEventReport(in, &report_);
  report_.stats = world_.stats();
  clock->lap(CycleStage::kReport);
  ++cycles_;
  return report_;
}

void Monitor::buildStatus(Stamp now) {
  report_.status_lines.clear();
  // A source is silent after ~source_timeout, and never later than ~track_timeout: by then
  // its tracks are gone, and an empty scene from a silent source must not read as clear.
  sources_.silentLines(now, std::min(params_.source_timeout, params_.track_timeout),
                       params_.track_timeout, &report_.status_lines);
  robot_.statusLines(&report_.status_lines);
  tracks_.unboundedLines(&report_.status_lines);
  for (const std::string& line : permanent_issues_) report_.status_lines.push_back(line);
  // A perception front end degraded or silent (as a source: ~source_timeout) is DEGRADED.
  perception_.statusLines(now, params_.source_timeout, &report_.status_lines);
  report_.unseen_share = perception_.unseenShare(now, params_.source_timeout);
  report_.degraded = !report_.status_lines.empty();
}

void Monitor::cycleFailed(Stamp now, const std::string& what) {
  drops_.add(Drop::kCycleFailure);
  // Silence must not read as clear: the failed cycle's report has no events and says why.
  report_.stamp = now;
  report_.events = nullptr;
  report_.levels.clear();
  report_.stale.clear();
  report_.degraded = true;
  report_.status_lines.assign(1, "cycle failed: " + what);
  ssm_.failed(now, what, &report_.ssm);
}

MonitorStatus Monitor::status() const {
  MonitorStatus s;
  s.cycles = cycles_;
  s.resets = resets_;
  s.last_cycle = last_cycle_;
  s.tracks = tracks_.size();
  s.robot_bodies = robot_.size();
  s.robot_unposed = robot_.unknownCount();
  s.ssm_reach = ssm_.reach();
  return s;
}

}  // namespace workspace_proximity
