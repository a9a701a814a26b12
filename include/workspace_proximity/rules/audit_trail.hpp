#pragma once
/// What the audit log (audit_log.hpp) hears from the cycles: the transitions of each cycle's
/// report, never the cycles themselves.
///   stop_begin  the speed scale reached 0 (a protective stop; also at the first cycle), with
///               safety_status's reason;
///   stop_end    the speed scale left 0, with its value and reason;
///   degraded    the status went from OK (or from nothing, at the first cycle) to DEGRADED,
///               with every reason (the status lines joined by " | ");
///   ok          the status went back to OK.
/// A further reason appearing while the status stays DEGRADED is no transition (/diagnostics
/// lists every reason). Stops only with speed and separation monitoring on.

#include <string>

#include "workspace_proximity/rules/audit_log.hpp"
#include "workspace_proximity/rules/cycle_report.hpp"

namespace workspace_proximity {

class AuditTrail {
 public:
  /// `log` is borrowed.
  explicit AuditTrail(AuditLog* log) : log_(log) {}

  /// One cycle's report: writes its transitions (usually none: a comparison of two flags).
  void cycle(const CycleReport& report);

 private:
  AuditLog* log_;
  bool stopped_ = false;   // the speed scale is 0
  bool degraded_ = false;  // the status is DEGRADED
  std::string reason_;     // scratch
};

}  // namespace workspace_proximity
