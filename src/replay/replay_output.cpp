#include "workspace_proximity/replay/replay_output.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <sstream>

#include <sys/stat.h>

#include "workspace_proximity/rules/config_fingerprint.hpp"

namespace workspace_proximity {
namespace {

const char* kEventColumns =
    "stamp,t,state,id_a,id_b,label_a,label_b,time_to_contact,time_to_separation,distance,"
    "closing_speed,level,stale\n";
const char* kCycleColumns =
    "stamp,t,status,events,tracks,robot_bodies,robot_unposed,details,speed_scale,raw_scale,"
    "ssm_robot,ssm_object,separation,required_separation,approach_speed\n";

const char* stateName(std::uint8_t state) {
  switch (state) {
    case ContactEvent::BEGIN: return "BEGIN";
    case ContactEvent::ONGOING: return "ONGOING";
    default: return "END";
  }
}

const char* levelName(std::uint8_t level) {
  switch (level) {
    case ContactEvent::NOTICE: return "NOTICE";
    case ContactEvent::WARNING: return "WARNING";
    default: return "CRITICAL";
  }
}

// A CSV field: quoted when it holds a comma, a quote or a line break.
void appendField(std::string* line, const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) {
    *line += s;
    return;
  }
  line->push_back('"');
  for (char c : s) {
    if (c == '"') line->push_back('"');
    line->push_back(c);
  }
  line->push_back('"');
}

void appendNumber(std::string* line, double v, const char* format = "%.6f") {
  if (std::isinf(v)) {
    *line += v > 0 ? "inf" : "-inf";
    return;
  }
  if (std::isnan(v)) {
    *line += "nan";
    return;
  }
  char buf[64];
  std::snprintf(buf, sizeof(buf), format, v);
  *line += buf;
}

// The next field of a row: a comma, then the field.
void nextField(std::string* line, const std::string& s) {
  line->push_back(',');
  appendField(line, s);
}

void nextNumber(std::string* line, double v) {
  line->push_back(',');
  appendNumber(line, v);
}

// "1795429779.220000000": exact, whatever the epoch.
void appendStamp(std::string* line, Stamp s) {
  char buf[48];
  std::snprintf(buf, sizeof(buf), "%lld.%09lld", static_cast<long long>(s / 1000000000),
                static_cast<long long>(s % 1000000000));
  *line += buf;
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof(buf), "\\u%04x", c);
          out += buf;
        } else {
          out.push_back(c);
        }
    }
  }
  return out + "\"";
}

std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

std::string jsonStrings(const std::vector<std::string>& v) {
  std::string out = "[";
  for (std::size_t i = 0; i < v.size(); ++i) out += (i ? ", " : "") + jsonString(v[i]);
  return out + "]";
}

void makeDirs(const std::string& dir) {
  std::string path;
  std::stringstream parts(dir);
  std::string part;
  if (!dir.empty() && dir[0] == '/') path = "/";
  while (std::getline(parts, part, '/')) {
    if (part.empty()) continue;
    path += part + "/";
    if (::mkdir(path.c_str(), 0755) != 0 && errno != EEXIST) {
      throw ReplayError(ReplayError::kOutput,
                        "cannot create the output folder " + path + ": " + std::strerror(errno));
    }
  }
  struct stat st;
  if (::stat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)) {
    throw ReplayError(ReplayError::kOutput, dir + " is not a folder");
  }
}

std::FILE* openCsv(const std::string& path, const char* header) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) {
    throw ReplayError(ReplayError::kOutput, "cannot write " + path + ": " + std::strerror(errno));
  }
  std::fputs(header, f);
  return f;
}

}  // namespace

ReplayWriter::ReplayWriter(const std::string& out_dir, Stamp bag_begin)
    : dir_(out_dir), begin_(bag_begin) {
  makeDirs(dir_);
  events_ = openCsv(dir_ + "/events.csv", kEventColumns);
  cycles_ = openCsv(dir_ + "/cycles.csv", kCycleColumns);
}

ReplayWriter::~ReplayWriter() {
  if (events_ != nullptr) std::fclose(events_);
  if (cycles_ != nullptr) std::fclose(cycles_);
}

void ReplayWriter::onCycle(const CycleReport& report, const ContactEventArray& contacts,
                           const Monitor& monitor) {
  // Rows are built in reused strings: steady cycles write without allocating.
  std::string& l = line_;
  std::string& stamp_t = stamp_t_;  // the stamp and t columns, shared by all rows of the cycle
  stamp_t.clear();
  appendStamp(&stamp_t, report.stamp);
  stamp_t.push_back(',');
  appendNumber(&stamp_t, secondsBetween(begin_, report.stamp), "%.9f");
  for (const ContactEvent& e : contacts.events) {
    l = stamp_t;
    l.push_back(',');
    l += stateName(e.state);
    nextField(&l, e.id_a);
    nextField(&l, e.id_b);
    nextField(&l, e.label_a);
    nextField(&l, e.label_b);
    nextNumber(&l, e.time_to_contact);
    nextNumber(&l, e.time_to_separation);
    nextNumber(&l, e.distance);
    nextNumber(&l, e.closing_speed);
    l.push_back(',');
    l += levelName(e.level);
    l += e.stale ? ",1\n" : ",0\n";
    std::fwrite(l.data(), 1, l.size(), events_);
  }

  l = stamp_t;
  l += contacts.status == ContactEventArray::OK ? ",OK," : ",DEGRADED,";
  char counts[96];
  std::snprintf(counts, sizeof(counts), "%zu,%d,%d,%d,", contacts.events.size(),
                monitor.tracks().size(), monitor.robot().size(), monitor.robot().unknownCount());
  l += counts;
  std::string& details = details_;
  details.clear();
  for (const std::string& d : contacts.status_details) {
    if (!details.empty()) details += " | ";
    details += d;
  }
  appendField(&l, details);
  // Speed and separation monitoring: the scale, the rule's raw scale and the limiting pair
  // (empty fields when it is off, or for the pair when nothing is within reach).
  const SsmVerdict& v = report.ssm;
  if (v.enabled) {
    nextNumber(&l, v.speed_scale);
    nextNumber(&l, v.raw_scale);
    const ProximityWorld& world = monitor.world();
    if (v.limited && world.contains(v.robot) && world.contains(v.object)) {
      nextField(&l, world.desc(v.robot).id);
      nextField(&l, world.desc(v.object).id);
      nextNumber(&l, v.separation);
      nextNumber(&l, v.required_separation);
      nextNumber(&l, v.approach_speed);
    } else {
      l += ",,,,,";
    }
  } else {
    l += ",,,,,,,";
  }
  l.push_back('\n');
  std::fwrite(l.data(), 1, l.size(), cycles_);
}

void ReplayWriter::finish(const ReplayStats& stats, const ReplayInfo& info) {
  const bool ok = std::ferror(events_) == 0 && std::ferror(cycles_) == 0;
  const bool closed = std::fclose(events_) == 0 && std::fclose(cycles_) == 0;
  events_ = cycles_ = nullptr;
  if (!ok || !closed) throw ReplayError(ReplayError::kOutput, "writing the CSV files in " + dir_ + " failed");
  const std::string path = dir_ + "/summary.json";
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) {
    throw ReplayError(ReplayError::kOutput, "cannot write " + path + ": " + std::strerror(errno));
  }
  const std::string json = summaryJson(stats, info);
  const bool written = std::fwrite(json.data(), 1, json.size(), f) == json.size();
  if (std::fclose(f) != 0 || !written) throw ReplayError(ReplayError::kOutput, "writing " + path + " failed");
}

std::string summaryJson(const ReplayStats& s, const ReplayInfo& info) {
  std::ostringstream j;
  j << "{\n";
  j << "  \"bag\": " << jsonString(info.bag) << ",\n";
  std::string begin, end;
  appendStamp(&begin, s.begin);
  appendStamp(&end, s.end);
  j << "  \"bag_begin\": " << begin << ",\n";
  j << "  \"bag_end\": " << end << ",\n";
  j << "  \"bag_seconds\": " << jsonNumber(s.bagSeconds()) << ",\n";
  j << "  \"config_files\": " << jsonStrings(info.config_files) << ",\n";
  j << "  \"urdf\": " << jsonString(info.urdf) << ",\n";
  if (info.setup != nullptr) {
    const MonitorParams& p = info.setup->params;
    // The node's fingerprint of the same configuration and URDF (config_fingerprint.hpp).
    j << "  \"config_fingerprint\": " << jsonString(configFingerprint(p, info.setup->urdf_xml))
      << ",\n";
    j << "  \"fixed_frame\": " << jsonString(p.fixed_frame) << ",\n";
    j << "  \"rate\": " << jsonNumber(p.rate) << ",\n";
    j << "  \"horizon\": " << jsonNumber(p.horizon) << ",\n";
    j << "  \"input_topics\": " << jsonStrings(info.setup->topics) << ",\n";
    std::vector<std::string> bodies;
    for (const RobotBodySpec& b : info.setup->robot) bodies.push_back(b.name);
    j << "  \"robot_bodies\": " << jsonStrings(bodies) << ",\n";
  }
  if (info.input != nullptr) {
    j << "  \"topics\": [";
    const auto& topics = info.input->topics();
    for (std::size_t i = 0; i < topics.size(); ++i) {
      const BagTopic& t = topics[i];
      const bool replayed = t.kind == BagTopicKind::kTf || t.kind == BagTopicKind::kTfStatic ||
                            t.kind == BagTopicKind::kArray || t.kind == BagTopicKind::kForeign;
      j << (i ? ",\n    " : "\n    ") << "{\"name\": " << jsonString(t.name)
        << ", \"type\": " << jsonString(t.type) << ", \"messages\": " << t.messages
        << ", \"replayed\": " << (replayed ? "true" : "false") << "}";
    }
    j << "\n  ],\n";
  }
  j << "  \"cycles\": " << s.cycles << ",\n";
  j << "  \"degraded_cycles\": " << s.degraded_cycles << ",\n";
  j << "  \"tf_messages\": " << s.tf_messages << ",\n";
  j << "  \"tf_static_messages\": " << s.tf_static_messages << ",\n";
  j << "  \"arrays\": " << s.arrays << ",\n";
  j << "  \"events\": {\"BEGIN\": " << s.events_begin << ", \"ONGOING\": " << s.events_ongoing
    << ", \"END\": " << s.events_end << "},\n";
  j << "  \"distinct_tracks\": " << s.distinct_tracks << ",\n";
  j << "  \"max_tracks\": " << s.max_tracks << ",\n";
  j << "  \"resets\": " << s.resets << ",\n";
  j << "  \"drops\": {";
  bool first = true;
  for (int r = 0; r < static_cast<int>(Drop::kCount); ++r) {
    const Drop reason = static_cast<Drop>(r);
    j << (first ? "" : ", ") << jsonString(dropName(reason)) << ": " << s.drops.count(reason);
    first = false;
  }
  j << "},\n";
  j << "  \"wall_seconds\": " << jsonNumber(s.wall_seconds) << ",\n";
  j << "  \"speed_factor\": "
    << jsonNumber(s.wall_seconds > 0.0 ? s.bagSeconds() / s.wall_seconds : 0.0) << ",\n";
  j << "  \"missing_frames\": " << jsonStrings(s.missing_frames) << ",\n";
  j << "  \"skipped_gaps\": [";
  for (std::size_t i = 0; i < s.gaps.size(); ++i) {
    j << (i ? ", " : "") << "{\"from\": " << jsonNumber(secondsBetween(s.begin, s.gaps[i].from))
      << ", \"to\": " << jsonNumber(secondsBetween(s.begin, s.gaps[i].to))
      << ", \"cycles\": " << s.gaps[i].cycles << "}";
  }
  j << "],\n";
  j << "  \"warnings\": " << jsonStrings(info.warnings) << "\n";
  j << "}\n";
  return j.str();
}

std::string summaryText(const ReplayStats& s, const ReplayInfo& info) {
  std::ostringstream t;
  t.setf(std::ios::fixed);
  t.precision(2);
  t << "replay: " << info.bag << ": " << s.bagSeconds() << " s of bag in " << s.wall_seconds
    << " s";
  if (s.wall_seconds > 0.0) {
    t.precision(0);
    t << " (" << s.bagSeconds() / s.wall_seconds << "x real time)";
    t.precision(2);
  }
  t << "\n";
  if (info.setup != nullptr) {
    t << "  config: fingerprint "
      << configFingerprint(info.setup->params, info.setup->urdf_xml) << "\n";
  }
  t << "  input:  " << s.arrays << " arrays, " << s.tf_messages << " tf + " << s.tf_static_messages
    << " tf_static messages\n";
  t << "  cycles: " << s.cycles << ", " << s.degraded_cycles << " DEGRADED";
  if (s.resets > 0) t << ", clock went back " << s.resets << " times";
  t << "\n";
  t << "  tracks: " << s.distinct_tracks << " distinct, at most " << s.max_tracks << " at once\n";
  t << "  events: " << s.events_begin << " BEGIN, " << s.events_ongoing << " ONGOING, "
    << s.events_end << " END\n";
  std::string drops;
  for (int r = 0; r < static_cast<int>(Drop::kCount); ++r) {
    const Drop reason = static_cast<Drop>(r);
    if (s.drops.count(reason) == 0) continue;
    drops += (drops.empty() ? "" : ", ") + std::string(dropName(reason)) + " " +
             std::to_string(s.drops.count(reason));
  }
  t << "  dropped: " << (drops.empty() ? "nothing" : drops) << "\n";
  for (const SkippedGap& g : s.gaps) {
    t << "  gap:    no input from " << secondsBetween(s.begin, g.from) << " s to "
      << secondsBetween(s.begin, g.to) << " s: " << g.cycles << " cycles skipped\n";
  }
  for (const std::string& w : info.warnings) t << "  warning: " << w << "\n";
  for (const std::string& m : s.missing_frames) t << "  MISSING: " << m << "\n";
  return t.str();
}

}  // namespace workspace_proximity
