#include "workspace_proximity/rules/audit_trail.hpp"

#include "workspace_proximity/rules/format.hpp"
#include "workspace_proximity/rules/stop_latch.hpp"

namespace workspace_proximity {

void AuditTrail::cycle(const CycleReport& report) {
  // DEGRADED first: a stop caused by DEGRADED (degraded_scale 0) follows its cause.
  if (report.degraded != degraded_) {
    degraded_ = report.degraded;
    if (degraded_) {
      reason_.clear();
      for (const std::string& line : report.status_lines) {
        if (!reason_.empty()) reason_ += " | ";
        reason_ += line;
      }
      log_->write(report.stamp, audit_kind::kDegraded, reason_);
    } else {
      log_->write(report.stamp, audit_kind::kOk, "every input fresh, every robot body posed");
    }
  }
  if (!report.ssm.enabled) return;
  const bool stop = report.ssm.speed_scale <= 0.0;
  if (stop != stopped_) {
    stopped_ = stop;
    if (stop) {
      log_->write(report.stamp, audit_kind::kStopBegin, report.ssm.reason);
    } else {
      log_->write(report.stamp, audit_kind::kStopEnd,
                  format("speed scale %.3f: ", report.ssm.speed_scale) + report.ssm.reason);
    }
  }
  // The stop latch's transitions (resets, mutes, the category 1 halt, the hold's release),
  // under the latch's own names; its "stop" is stop_begin above.
  const LatchEvents* events = report.ssm.latch_events;
  if (events == nullptr) return;
  for (int i = 0; i < events->size(); ++i) {
    const LatchEvent& e = (*events)[i];
    if (e.kind == LatchEventKind::kStop) continue;
    log_->write(report.stamp, latchEventName(e.kind), e.reason);
  }
}

}  // namespace workspace_proximity
