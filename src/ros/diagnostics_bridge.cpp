#include "workspace_proximity/ros/diagnostics_bridge.hpp"

#include <string>

#include <diagnostic_msgs/DiagnosticStatus.h>

namespace workspace_proximity {

void diagnose(const MonitorBridges& bridges, Stamp now, const std::string& fingerprint,
              diagnostic_updater::DiagnosticStatusWrapper* status) {
  const Monitor& monitor = bridges.monitor();
  const CycleRunner& runner = bridges.runner();
  const BridgeCounters counters = bridges.counters();
  const MonitorStatus counts = monitor.status();
  const CycleReport& report = monitor.report();
  const double period_ms = 1000.0 / monitor.params().rate;
  if (runner.lastCycleMs() > period_ms) {
    status->summaryf(diagnostic_msgs::DiagnosticStatus::ERROR,
                     "cycle takes %.1f ms, longer than the %.1f ms period", runner.lastCycleMs(),
                     period_ms);
  } else if (report.degraded) {
    status->summary(diagnostic_msgs::DiagnosticStatus::WARN,
                    "degraded: " + report.status_lines.front());
  } else {
    status->summary(diagnostic_msgs::DiagnosticStatus::OK, "predicting");
  }
  status->add("config fingerprint", fingerprint);
  status->add("cycles", counts.cycles);
  status->add("cycle time (ms)", runner.lastCycleMs());
  status->add("max cycle time (ms)", runner.maxCycleMs());
  const CycleTiming& timing = runner.timing();
  for (int i = 0; i < CycleTiming::kStages; ++i) {
    const auto stage = static_cast<CycleStage>(i);
    status->addf(std::string("stage ") + CycleTiming::name(stage) + " (ms, last/p99)", "%.3f/%.3f",
                 timing.last(stage), timing.percentile(stage, 0.99));
  }
  status->add("tracks", counts.tracks);
  status->add("robot bodies", counts.robot_bodies);
  status->add("robot bodies not posed", counts.robot_unposed);
  status->add("tf failures", counters.tf_failures);
  if (counters.joints) {
    status->add("joint states received", counters.joint.joint_states);
    status->add("trajectories accepted", counters.joint.trajectories);
    status->add("trajectories ignored", counters.joint.trajectories_ignored);
    status->add("trajectories dropped (not followed)", counters.joint.trajectories_dropped);
    if (!counters.joint.last_trajectory_problem.empty()) {
      status->add("last trajectory problem", counters.joint.last_trajectory_problem);
    }
  }
  status->add("broad-phase pairs", report.stats.broad_pairs);
  status->add("predicted contacts", report.stats.contacts);
  status->add("history resets (clock jumps)", counts.resets);
  const SsmVerdict& ssm = report.ssm;
  if (ssm.enabled) {
    status->addf("speed scale", "%.3f", ssm.speed_scale);
    status->addf("speed scale raw", "%.3f", ssm.raw_scale);
    if (ssm.limited && monitor.world().contains(ssm.robot) && monitor.world().contains(ssm.object)) {
      status->addf("speed scale limited by", "%s - %s: %.2f m, S_p %.2f m",
                   monitor.world().desc(ssm.object).id.c_str(), monitor.world().desc(ssm.robot).id.c_str(),
                   ssm.separation, ssm.required_separation);
    } else {
      status->add("speed scale limited by", "nothing within reach");
    }
    status->add("speed scale reason", ssm.reason);
    status->addf("speed and separation reach (m)", "%.2f", counts.ssm_reach);
  }
  if (monitor.perception().size() > 0) {
    // NaN: unknown (a front end silent, or its share not computed yet).
    status->addf("unseen share", "%.3f", report.unseen_share);
  }
  const SourceTable& sources = monitor.sources();
  for (int i = 0; i < sources.size(); ++i) {
    const Source& s = sources.source(i);
    status->add("source " + s.name + " rate (Hz)", s.rate);
    status->add("source " + s.name + " age (s)",
                s.last_receipt == 0 ? -1.0 : secondsBetween(s.last_receipt, now));
  }
  for (int i = 0; i < static_cast<int>(Drop::kCount); ++i) {
    const auto reason = static_cast<Drop>(i);
    const std::uint64_t n = monitor.drops().count(reason);
    if (n > 0) status->add(std::string("dropped: ") + dropName(reason), n);
  }
  for (const std::string& line : report.status_lines) status->add("degraded", line);
}

}  // namespace workspace_proximity
