#pragma once
/// The audit trail's file (~audit_log): a CSV file that records every protective stop, every
/// DEGRADED transition, every parameter change and the node's start, each line with the
/// fingerprint of the configuration in force (config_fingerprint.hpp). Appended, never
/// truncated, and flushed line by line: each line is one write(2) to a descriptor opened with
/// O_APPEND, so a line written is in the file even if the node dies the next instant (not
/// fsync'd: a power cut may lose the last lines the kernel still held).
///
/// Columns (the header line, written when the file is new or empty):
///   wall_time           the machine's clock, UTC, ISO 8601 to the microsecond
///                       ("2026-11-27T01:47:10.123456Z");
///   ros_stamp           the node's clock (ROS time, sim time in a simulation), s since its
///                       epoch to the nanosecond ("1795400830.123456789");
///   kind                what happened (the audit_kind names below; other components add theirs);
///   reason              why, in words;
///   config_fingerprint  16 hex digits: the configuration in force when it happened.
/// Fields are quoted as RFC 4180 says: a field with a comma, a quote, a CR or a LF is enclosed in
/// quotes, its quotes doubled (a reason may span lines inside its quotes).
///
/// Not on the hot path: a line is written only when something happens, never every cycle.

#include <cstdint>
#include <stdexcept>
#include <string>

#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

/// The kinds this package writes. Other writers may add their own (lower case, '_', no comma).
namespace audit_kind {
constexpr const char* kStart = "start";              ///< the node started (its fingerprint)
constexpr const char* kShutdown = "shutdown";        ///< the node stops
constexpr const char* kStopBegin = "stop_begin";     ///< speed scale reached 0: protective stop
constexpr const char* kStopEnd = "stop_end";         ///< speed scale left 0
constexpr const char* kDegraded = "degraded";        ///< status OK -> DEGRADED, with the reasons
constexpr const char* kOk = "ok";                    ///< status DEGRADED -> OK
constexpr const char* kParams = "params";            ///< parameters changed (which, old -> new)
constexpr const char* kParamsRefused = "params_refused";  ///< a change refused, with why
}  // namespace audit_kind

/// A path that cannot be opened (or its header written): a startup error naming the path.
class AuditLogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class AuditLog {
 public:
  /// The header line, without its line break.
  static constexpr const char* kHeader = "wall_time,ros_stamp,kind,reason,config_fingerprint";

  /// Opens `path` for appending (created when missing; the header line when it is empty).
  /// Throws AuditLogError naming the path and the system's reason when it cannot.
  AuditLog(const std::string& path, std::string fingerprint);
  ~AuditLog();
  AuditLog(const AuditLog&) = delete;
  AuditLog& operator=(const AuditLog&) = delete;

  /// The fingerprint written on the lines from now on.
  void setFingerprint(const std::string& fingerprint) { fingerprint_ = fingerprint; }
  const std::string& fingerprint() const { return fingerprint_; }
  const std::string& path() const { return path_; }

  /// One line now (the machine's clock), at ROS time `stamp` (ns). Returns false when the line
  /// could not be written whole (failed() then stays true: the trail has a gap).
  bool write(Stamp stamp, const std::string& kind, const std::string& reason);
  /// The same at wall time `wall_ns` (ns since 1970-01-01 UTC).
  bool writeAt(std::int64_t wall_ns, Stamp stamp, const std::string& kind, const std::string& reason);

  /// A line could not be written since the file was opened.
  bool failed() const { return failures_ > 0; }
  std::uint64_t failures() const { return failures_; }
  /// The first failure in words ("audit log /x.csv: a line could not be written: No space left
  /// on device"), "" before any.
  const std::string& error() const { return error_; }

 private:
  // Writes every byte (retrying short writes); false with the reason in `why`.
  bool writeAll(const std::string& bytes, std::string* why);

  std::string path_;
  int fd_ = -1;
  bool partial_ = false;  // the last write stopped inside its line
  std::string fingerprint_;
  std::string line_;  // reused
  std::uint64_t failures_ = 0;
  std::string error_;
};

/// `field` as a CSV field (RFC 4180): as it is, or quoted with its quotes doubled when it holds
/// a comma, a quote, a CR or a LF.
std::string csvField(const std::string& field);

/// `wall_ns` (ns since 1970-01-01 UTC) as ISO 8601 UTC to the microsecond
/// ("2026-11-27T01:47:10.123456Z"; truncated, not rounded).
std::string isoUtc(std::int64_t wall_ns);

/// `stamp` (ns) as seconds with nine decimals ("1795400830.123456789"; "-0.5" as "-0.500000000").
std::string stampText(Stamp stamp);

}  // namespace workspace_proximity
