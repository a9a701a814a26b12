#include "workspace_proximity/rules/audit_trail.hpp"

#include "workspace_proximity/rules/format.hpp"

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
  if (stop == stopped_) return;
  stopped_ = stop;
  if (stop) {
    log_->write(report.stamp, audit_kind::kStopBegin, report.ssm.reason);
  } else {
    log_->write(report.stamp, audit_kind::kStopEnd,
                format("speed scale %.3f: ", report.ssm.speed_scale) + report.ssm.reason);
  }
}

}  // namespace workspace_proximity
