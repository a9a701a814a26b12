#include "workspace_proximity/rules/audit_log.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>

namespace workspace_proximity {

std::string csvField(const std::string& field) {
  if (field.find_first_of(",\"\r\n") == std::string::npos) return field;
  std::string out = "\"";
  for (const char c : field) {
    if (c == '"') out += '"';
    out += c;
  }
  out += '"';
  return out;
}

std::string isoUtc(std::int64_t wall_ns) {
  // Floor division, so that an instant before 1970 still gets its microseconds right.
  std::int64_t seconds = wall_ns / 1000000000;
  std::int64_t ns = wall_ns % 1000000000;
  if (ns < 0) {
    ns += 1000000000;
    --seconds;
  }
  const std::time_t t = static_cast<std::time_t>(seconds);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char date[40];
  std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%S", &tm);
  char out[64];
  std::snprintf(out, sizeof out, "%s.%06lldZ", date, static_cast<long long>(ns / 1000));
  return out;
}

std::string stampText(Stamp stamp) {
  const bool negative = stamp < 0;
  // Magnitude as unsigned: -INT64_MIN does not fit a signed integer.
  const std::uint64_t m = negative ? 0 - static_cast<std::uint64_t>(stamp) : static_cast<std::uint64_t>(stamp);
  char out[40];
  std::snprintf(out, sizeof out, "%s%llu.%09llu", negative ? "-" : "",
                static_cast<unsigned long long>(m / 1000000000ull),
                static_cast<unsigned long long>(m % 1000000000ull));
  return out;
}

AuditLog::AuditLog(const std::string& path, std::string fingerprint)
    : path_(path), fingerprint_(std::move(fingerprint)) {
  // O_APPEND: every write goes to the end, whatever else appends to the file; never truncated.
  // A plain descriptor, no stdio buffer: each line is one write(2), in the file (the kernel's
  // page cache) when write returns, and nothing half-written waits in a buffer after a failure.
  fd_ = ::open(path.c_str(), O_WRONLY | O_APPEND | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) {
    throw AuditLogError("~audit_log = '" + path + "': cannot open it for appending: " +
                        std::strerror(errno));
  }
  struct stat st {};
  if (::fstat(fd_, &st) != 0) {
    const int e = errno;
    ::close(fd_);
    throw AuditLogError("~audit_log = '" + path + "': " + std::strerror(e));
  }
  if (st.st_size == 0) {
    // A new file: its columns first. A file that cannot take even this line is refused now
    // rather than found to fail at the first stop.
    std::string header = kHeader;
    header += '\n';
    std::string why;
    if (!writeAll(header, &why)) {
      ::close(fd_);
      throw AuditLogError("~audit_log = '" + path + "': cannot write to it: " + why);
    }
  }
}

AuditLog::~AuditLog() { ::close(fd_); }

bool AuditLog::writeAll(const std::string& bytes, std::string* why) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd_, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      *why = n < 0 ? std::strerror(errno) : "nothing written";
      // Cut off inside (or still cut off from before, when nothing went out).
      partial_ = partial_ || done > 0;
      return false;
    }
    done += static_cast<std::size_t>(n);
  }
  partial_ = false;
  return true;
}

bool AuditLog::write(Stamp stamp, const std::string& kind, const std::string& reason) {
  const std::int64_t wall_ns = std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::system_clock::now().time_since_epoch())
                                   .count();
  return writeAt(wall_ns, stamp, kind, reason);
}

bool AuditLog::writeAt(std::int64_t wall_ns, Stamp stamp, const std::string& kind,
                       const std::string& reason) {
  // After a line that was cut off, a line break first: the next line starts a row of its own.
  line_.assign(partial_ ? "\n" : "");
  line_ += isoUtc(wall_ns);
  line_ += ',';
  line_ += stampText(stamp);
  line_ += ',';
  line_ += csvField(kind);
  line_ += ',';
  line_ += csvField(reason);
  line_ += ',';
  line_ += csvField(fingerprint_);
  line_ += '\n';
  std::string why;
  if (writeAll(line_, &why)) return true;
  if (failures_++ == 0) {
    error_ = "audit log " + path_ + ": a line could not be written (" + why +
             "); the audit trail is incomplete";
  }
  return false;
}

}  // namespace workspace_proximity
