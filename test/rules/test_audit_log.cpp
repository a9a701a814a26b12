// The audit log's file (audit_log.hpp) and what the cycles write to it (audit_trail.hpp):
// the header and columns, read back with a CSV reader written here from RFC 4180; quoting of
// commas, quotes and line breaks; appending (never truncating) across reopenings; a path that
// cannot be opened refused by name; a write that fails (the file size limit, as a full disk
// would) reported, and the lines after it still whole rows; the transitions of a scripted
// sequence of cycle reports, one line each and none for the cycles between.

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "workspace_proximity/rules/audit_log.hpp"
#include "workspace_proximity/rules/audit_trail.hpp"
#include "workspace_proximity/rules/stop_latch.hpp"

namespace wp = workspace_proximity;
using Rows = std::vector<std::vector<std::string>>;

namespace {

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// RFC 4180: fields separated by commas, records by CRLF or LF; a quoted field may hold commas,
// line breaks and doubled quotes. Fails the test on a malformed record.
Rows parseCsv(const std::string& text) {
  Rows rows;
  std::vector<std::string> row;
  std::string field;
  std::size_t i = 0;
  bool quoted_field = false;
  while (i < text.size()) {
    const char c = text[i];
    if (field.empty() && !quoted_field && c == '"') {
      quoted_field = true;
      ++i;
      for (;;) {
        if (i >= text.size()) {
          ADD_FAILURE() << "unterminated quote";
          return rows;
        }
        if (text[i] == '"') {
          if (i + 1 < text.size() && text[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          ++i;
          break;
        }
        field += text[i++];
      }
      continue;
    }
    if (c == ',') {
      row.push_back(field);
      field.clear();
      quoted_field = false;
      ++i;
    } else if (c == '\n' || (c == '\r' && i + 1 < text.size() && text[i + 1] == '\n')) {
      row.push_back(field);
      rows.push_back(row);
      row.clear();
      field.clear();
      quoted_field = false;
      i += c == '\r' ? 2 : 1;
    } else {
      EXPECT_FALSE(quoted_field) << "text after a closing quote";
      field += c;
      ++i;
    }
  }
  EXPECT_TRUE(field.empty() && row.empty()) << "the last record has no line break";
  return rows;
}

class TempDir {
 public:
  TempDir() {
    char pattern[] = "/tmp/wp_audit_XXXXXX";
    dir_ = ::mkdtemp(pattern);
  }
  ~TempDir() { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  std::string path(const std::string& name) const { return dir_ + "/" + name; }

 private:
  std::string dir_;
};

const std::vector<std::string> kColumns = {"wall_time", "ros_stamp", "kind", "reason",
                                           "config_fingerprint"};

}  // namespace

TEST(AuditLog, TimesAndStampsAsTheyAreWritten) {
  // 1 700 000 000 s after the epoch is 2023-11-14 22:13:20 UTC.
  EXPECT_EQ(wp::isoUtc(1700000000123456789LL), "2023-11-14T22:13:20.123456Z");
  EXPECT_EQ(wp::isoUtc(0), "1970-01-01T00:00:00.000000Z");
  EXPECT_EQ(wp::isoUtc(-1), "1969-12-31T23:59:59.999999Z");
  EXPECT_EQ(wp::stampText(1500000000), "1.500000000");
  EXPECT_EQ(wp::stampText(1700000000000000001LL), "1700000000.000000001");
  EXPECT_EQ(wp::stampText(-500000000), "-0.500000000");
}

TEST(AuditLog, ANewFileGetsTheHeaderAndEachLineItsColumns) {
  TempDir tmp;
  const std::string file = tmp.path("audit.csv");
  {
    wp::AuditLog log(file, "0123456789abcdef");
    EXPECT_TRUE(log.writeAt(1700000000123456789LL, 42500000000LL, "start", "node started"));
    log.setFingerprint("fedcba9876543210");
    EXPECT_TRUE(log.writeAt(1700000001000000000LL, 43000000000LL, "params", "rate: 30 -> 20"));
    EXPECT_FALSE(log.failed());
  }
  const std::string text = readFile(file);
  EXPECT_EQ(text.substr(0, text.find('\n')), wp::AuditLog::kHeader);
  const Rows rows = parseCsv(text);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], kColumns);
  EXPECT_EQ(rows[1], (std::vector<std::string>{"2023-11-14T22:13:20.123456Z", "42.500000000",
                                                "start", "node started", "0123456789abcdef"}));
  EXPECT_EQ(rows[2], (std::vector<std::string>{"2023-11-14T22:13:21.000000Z", "43.000000000",
                                                "params", "rate: 30 -> 20", "fedcba9876543210"}));
}

TEST(AuditLog, WallTimeIsTheMachinesClockInUtc) {
  TempDir tmp;
  const std::string file = tmp.path("audit.csv");
  const std::time_t before = std::time(nullptr);
  {
    wp::AuditLog log(file, "f");
    log.write(1, "start", "x");
  }
  const std::time_t after = std::time(nullptr);
  const Rows rows = parseCsv(readFile(file));
  ASSERT_EQ(rows.size(), 2u);
  std::tm tm{};
  const std::string& wall = rows[1][0];
  ASSERT_NE(strptime(wall.c_str(), "%Y-%m-%dT%H:%M:%S", &tm), nullptr) << wall;
  const std::time_t t = timegm(&tm);
  EXPECT_GE(t, before);
  EXPECT_LE(t, after);
  EXPECT_EQ(wall.size(), 27u) << wall;
  EXPECT_EQ(wall.back(), 'Z');
}

TEST(AuditLog, ReasonsWithCommasQuotesAndLineBreaksReadBackWhole) {
  TempDir tmp;
  const std::string file = tmp.path("audit.csv");
  const std::vector<std::string> reasons = {
      "plain", "a, b", "say \"stop\"", "two\nlines", "cr\r\nlf", "\"", ",", "", "trailing,\"\n"};
  {
    wp::AuditLog log(file, "0000000000000000");
    for (const std::string& r : reasons) ASSERT_TRUE(log.writeAt(0, 0, "kind", r));
  }
  const Rows rows = parseCsv(readFile(file));
  ASSERT_EQ(rows.size(), reasons.size() + 1);
  for (std::size_t i = 0; i < reasons.size(); ++i) {
    ASSERT_EQ(rows[i + 1].size(), 5u) << i;
    EXPECT_EQ(rows[i + 1][3], reasons[i]) << i;
  }
  EXPECT_EQ(wp::csvField("a,b"), "\"a,b\"");
  EXPECT_EQ(wp::csvField("say \"x\""), "\"say \"\"x\"\"\"");
  EXPECT_EQ(wp::csvField("plain"), "plain");
}

TEST(AuditLog, ReopeningAppendsAndNeverTruncates) {
  TempDir tmp;
  const std::string file = tmp.path("audit.csv");
  {
    wp::AuditLog log(file, "1111111111111111");
    log.writeAt(0, 1, "start", "first run");
    log.writeAt(0, 2, "shutdown", "first run ends");
  }
  const std::string first = readFile(file);
  {
    wp::AuditLog log(file, "2222222222222222");  // no second header
    log.writeAt(0, 3, "start", "second run");
  }
  const std::string both = readFile(file);
  EXPECT_EQ(both.substr(0, first.size()), first);
  const Rows rows = parseCsv(both);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[0], kColumns);
  EXPECT_EQ(rows[3][3], "second run");
  EXPECT_EQ(rows[3][4], "2222222222222222");
  // Flushed line by line: another reader sees each line as soon as write returns.
  wp::AuditLog log(file, "3333333333333333");
  log.writeAt(0, 4, "ok", "seen at once");
  EXPECT_EQ(parseCsv(readFile(file)).back()[3], "seen at once");
}

TEST(AuditLog, APathThatCannotBeOpenedIsRefusedByName) {
  TempDir tmp;
  const std::string missing = tmp.path("no/such/dir/audit.csv");
  try {
    wp::AuditLog log(missing, "f");
    ADD_FAILURE() << "opened " << missing;
  } catch (const wp::AuditLogError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("~audit_log"), std::string::npos) << what;
    EXPECT_NE(what.find(missing), std::string::npos) << what;
    EXPECT_NE(what.find("No such file or directory"), std::string::npos) << what;
  }
  EXPECT_THROW(wp::AuditLog(tmp.path(""), "f"), wp::AuditLogError);  // a directory
  if (::access("/dev/full", W_OK) == 0) {
    // Opens, but takes no byte: refused at once, not at the first stop.
    try {
      wp::AuditLog log("/dev/full", "f");
      ADD_FAILURE() << "/dev/full accepted";
    } catch (const wp::AuditLogError& e) {
      EXPECT_NE(std::string(e.what()).find("cannot write"), std::string::npos) << e.what();
    }
  }
}

TEST(AuditLog, AFailedWriteIsReportedAndTheNextLinesStayWholeRows) {
  TempDir tmp;
  const std::string file = tmp.path("audit.csv");
  wp::AuditLog log(file, "abcdabcdabcdabcd");
  ASSERT_TRUE(log.writeAt(0, 1, "start", "fits"));
  struct stat st {};
  ASSERT_EQ(::stat(file.c_str(), &st), 0);
  // The file may grow 30 more bytes (as a full disk would refuse the rest): the next line is
  // cut off inside.
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  const auto previous = ::signal(SIGXFSZ, SIG_IGN);
  rlimit small = old;
  small.rlim_cur = static_cast<rlim_t>(st.st_size + 30);
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  const bool written = log.writeAt(0, 2, "stop_begin", std::string(200, 'x'));
  const bool again = log.writeAt(0, 3, "stop_end", "also refused");
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &old), 0);
  ::signal(SIGXFSZ, previous);
  EXPECT_FALSE(written);
  EXPECT_FALSE(again);
  EXPECT_TRUE(log.failed());
  EXPECT_EQ(log.failures(), 2u);
  EXPECT_NE(log.error().find(file), std::string::npos) << log.error();
  EXPECT_NE(log.error().find("File too large"), std::string::npos) << log.error();
  EXPECT_NE(log.error().find("incomplete"), std::string::npos) << log.error();
  // Room again: the next line is written, as a row of its own after the cut one.
  ASSERT_TRUE(log.writeAt(0, 4, "ok", "after the gap"));
  EXPECT_TRUE(log.failed()) << "the gap stays";
  const Rows rows = parseCsv(readFile(file));
  ASSERT_GE(rows.size(), 4u) << readFile(file);
  EXPECT_EQ(rows[1][3], "fits");
  EXPECT_EQ(rows.back(), (std::vector<std::string>{"1970-01-01T00:00:00.000000Z", "0.000000004",
                                                    "ok", "after the gap", "abcdabcdabcdabcd"}));
  EXPECT_LT(rows[rows.size() - 2].size(), 5u) << "the cut line is no whole row";
}

namespace {

// A report with the given status and speed scale.
wp::CycleReport report(double t, bool degraded, std::vector<std::string> lines, double scale) {
  wp::CycleReport r;
  r.stamp = wp::nanoseconds(t);
  r.degraded = degraded;
  r.status_lines = std::move(lines);
  r.ssm.enabled = true;
  r.ssm.speed_scale = scale;
  r.ssm.reason = scale <= 0.0 ? "person_1 within 0.40 m" : "clear";
  return r;
}

}  // namespace

TEST(AuditTrail, WritesEachTransitionOnceAndNothingBetween) {
  TempDir tmp;
  const std::string file = tmp.path("audit.csv");
  {
    wp::AuditLog log(file, "abcdabcdabcdabcd");
    wp::AuditTrail trail(&log);
    // Scripted: starts DEGRADED and stopped (no data yet), becomes OK and rises, a stop, the
    // end of the stop, a silent source (DEGRADED with two reasons, the reasons changing while
    // DEGRADED), OK again.
    trail.cycle(report(0.00, true, {"source /a: no data yet"}, 0.0));      // degraded, stop_begin
    trail.cycle(report(0.05, true, {"source /a: no data yet"}, 0.0));
    trail.cycle(report(0.10, false, {}, 0.0));                            // ok
    trail.cycle(report(0.15, false, {}, 0.2));                            // stop_end
    for (double t = 0.2; t < 1.0; t += 0.05) trail.cycle(report(t, false, {}, 0.5));
    trail.cycle(report(1.00, false, {}, 0.0));                            // stop_begin
    trail.cycle(report(1.05, false, {}, 0.0));
    trail.cycle(report(1.10, false, {}, 0.1));                            // stop_end
    trail.cycle(report(1.15, true, {"source /a: no data for 1.00 s", "robot body b stale: x"},
                       0.1));                                              // degraded
    trail.cycle(report(1.20, true, {"source /a: no data for 1.05 s"}, 0.1));
    trail.cycle(report(1.25, false, {}, 0.1));                            // ok
    wp::CycleReport off = report(1.30, false, {}, 0.0);
    off.ssm.enabled = false;                                               // no SSM: no stop
    trail.cycle(off);
  }
  const Rows rows = parseCsv(readFile(file));
  std::vector<std::string> kinds;
  for (std::size_t i = 1; i < rows.size(); ++i) kinds.push_back(rows[i][2]);
  EXPECT_EQ(kinds, (std::vector<std::string>{"degraded", "stop_begin", "ok", "stop_end",
                                             "stop_begin", "stop_end", "degraded", "ok"}));
  ASSERT_EQ(rows.size(), 9u);
  EXPECT_EQ(rows[1][1], "0.000000000");
  EXPECT_EQ(rows[1][3], "source /a: no data yet");
  EXPECT_EQ(rows[2][3], "person_1 within 0.40 m");
  EXPECT_EQ(rows[4][1], "0.150000000");
  EXPECT_EQ(rows[4][3], "speed scale 0.200: clear");
  EXPECT_EQ(rows[5][1], "1.000000000");
  EXPECT_EQ(rows[7][3], "source /a: no data for 1.00 s | robot body b stale: x");
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(rows[i][4], "abcdabcdabcdabcd");
}

TEST(AuditTrail, WritesTheStopLatchsTransitionsUnderTheirNames) {
  TempDir tmp;
  const std::string file = tmp.path("audit.csv");
  {
    wp::AuditLog log(file, "abcdabcdabcdabcd");
    wp::AuditTrail trail(&log);
    wp::LatchEvents events;
    wp::CycleReport r = report(0.00, false, {}, 0.0);
    r.ssm.latch_events = &events;
    events.add(wp::LatchEventKind::kStop, "person_1 within 0.40 m");  // is stop_begin
    trail.cycle(r);
    events.clear();
    events.add(wp::LatchEventKind::kResetRefused, "person_1 within S_p");
    events.add(wp::LatchEventKind::kMuteRefused, "the scale is 0");
    r.stamp = wp::nanoseconds(0.05);
    trail.cycle(r);
    events.clear();
    r.stamp = wp::nanoseconds(0.10);
    trail.cycle(r);  // no events, no transition: nothing
    events.add(wp::LatchEventKind::kHaltRequested, "stood still 0.5 s");
    events.add(wp::LatchEventKind::kResetAccepted, "clear");
    events.add(wp::LatchEventKind::kReleased, "reset accepted");
    r.stamp = wp::nanoseconds(0.15);
    trail.cycle(r);
  }
  const Rows rows = parseCsv(readFile(file));
  std::vector<std::string> kinds;
  for (std::size_t i = 1; i < rows.size(); ++i) kinds.push_back(rows[i][2]);
  EXPECT_EQ(kinds, (std::vector<std::string>{"stop_begin", "reset_refused", "mute_refused",
                                             "halt_requested", "reset_accepted", "released"}));
  ASSERT_EQ(rows.size(), 7u);
  EXPECT_EQ(rows[2][3], "person_1 within S_p");
  EXPECT_EQ(rows[4][1], "0.150000000");
  for (std::size_t i = 1; i < rows.size(); ++i) EXPECT_EQ(rows[i][4], "abcdabcdabcdabcd");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
