#include "workspace_proximity/rules/config_fingerprint.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <stdexcept>

#include "workspace_proximity/rules/param_table.hpp"

namespace workspace_proximity {
namespace {

void appendNumber(std::string* out, double v) {
  // The shortest of %.15g, %.16g, %.17g that parses back to the same double: exact (a change
  // in the last bit is seen) and readable (0.1, not 0.10000000000000001).
  char buffer[40];
  for (int digits = 15; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, v);
    if (std::strtod(buffer, nullptr) == v || std::isnan(v)) break;
  }
  *out += buffer;
}

void appendQuoted(std::string* out, const std::string& s) {
  // Quoted and escaped, so that no value can imitate a line break or a list separator.
  *out += '"';
  for (const char c : s) {
    switch (c) {
      case '\\': *out += "\\\\"; break;
      case '"': *out += "\\\""; break;
      case '\n': *out += "\\n"; break;
      case '\r': *out += "\\r"; break;
      case '\t': *out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\x%02x", static_cast<unsigned char>(c));
          *out += buffer;
        } else {
          *out += c;
        }
    }
  }
  *out += '"';
}

// A label's name inside a line's name: as it is, but with '\\', '=', '/' and control
// characters as \xHH, so that no name can end the line's name early or start another line.
void appendNamePart(std::string* out, const std::string& s) {
  for (const char c : s) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\\' || c == '=' || c == '/' || u < 0x20 || u == 0x7f) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\x%02x", u);
      *out += buffer;
    } else {
      *out += c;
    }
  }
}

void appendNames(std::string* out, const std::vector<std::string>& names) {
  *out += '[';
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (i > 0) *out += ',';
    appendQuoted(out, names[i]);
  }
  *out += ']';
}

void appendPairs(std::string* out, const std::vector<std::pair<std::string, std::string>>& pairs) {
  *out += '[';
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (i > 0) *out += ',';
    *out += '[';
    appendQuoted(out, pairs[i].first);
    *out += ',';
    appendQuoted(out, pairs[i].second);
    *out += ']';
  }
  *out += ']';
}

void appendLabel(std::string* out, const std::string& prefix, const LabelSettings& l,
                 bool track_label) {
  for (const LabelRow& row : labelTable()) {
    if (row.track_only && !track_label) continue;  // not a setting of the robot
    *out += prefix;
    *out += row.key;
    *out += '=';
    appendNumber(out, l.*row.member);
    *out += '\n';
  }
}

const char* shapeName(ShapeType type) {
  switch (type) {
    case ShapeType::kBox: return "box";
    case ShapeType::kSphere: return "sphere";
    case ShapeType::kCylinder: return "cylinder";
    case ShapeType::kCapsule: return "capsule";
  }
  return "?";
}

void appendBody(std::string* out, const RobotBodySpec& b) {
  appendQuoted(out, b.name);
  *out += ',';
  appendQuoted(out, b.frame);
  *out += ',';
  *out += shapeName(b.shape.type);
  const double dims[] = {b.shape.half_extents.x(), b.shape.half_extents.y(),
                         b.shape.half_extents.z(), b.shape.radius, b.shape.length};
  for (const double d : dims) {
    *out += ',';
    appendNumber(out, d);
  }
  // The offset as its 3x4 matrix, row by row.
  const Eigen::Matrix<double, 3, 4> m = b.offset.matrix().topRows<3>();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) {
      *out += ',';
      appendNumber(out, m(r, c));
    }
  }
}

// The value of a structure row: labels, robot_thresholds and robot_bodies, each a line per
// entry named below the row's name.
void appendStructure(std::string* out, const ParamRow& row, const MonitorParams& p) {
  const std::string name = row.name;
  if (name == "labels") {
    for (const auto& [label, settings] : p.labels) {  // std::map: sorted by name
      std::string prefix = "labels/";
      appendNamePart(&prefix, label);
      prefix += '/';
      appendLabel(out, prefix, settings, true);
    }
    return;
  }
  if (name == "robot_thresholds") {
    appendLabel(out, "robot_thresholds/", p.robot_thresholds, false);
    return;
  }
  if (name == "robot_bodies") {
    *out += "robot_bodies=";
    *out += std::to_string(p.robot_bodies.size());
    *out += '\n';
    for (std::size_t i = 0; i < p.robot_bodies.size(); ++i) {
      *out += "robot_bodies/" + std::to_string(i) + '=';
      appendBody(out, p.robot_bodies[i]);
      *out += '\n';
    }
    return;
  }
  throw std::logic_error("config fingerprint: the structure row ~" + name +
                         " is not covered (add it to config_fingerprint.cpp)");
}

// Splits canonical text into its lines' names and values (name up to the first '=').
std::map<std::string, std::string> lines(const std::string& text, std::vector<std::string>* order) {
  std::map<std::string, std::string> out;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(begin, end - begin);
    const std::size_t eq = line.find('=');
    const std::string name = line.substr(0, eq);
    out[name] = eq == std::string::npos ? std::string() : line.substr(eq + 1);
    if (order != nullptr) order->push_back(name);
    begin = end + 1;
  }
  return out;
}

}  // namespace

std::uint64_t fnv1a64(const std::string& bytes) {
  std::uint64_t h = 14695981039346656037ull;  // offset basis
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;  // FNV prime
  }
  return h;
}

std::string hex64(std::uint64_t value) {
  char buffer[20];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

std::string canonicalConfig(const MonitorParams& params, const std::string& urdf) {
  MonitorParams& p = const_cast<MonitorParams&>(params);  // the accessors only read here
  std::string out;
  for (const ParamRow& row : paramTable()) {
    if (row.member.type == ParamType::kStructure) {
      appendStructure(&out, row, params);
      continue;
    }
    out += row.name;
    out += '=';
    switch (row.member.type) {
      case ParamType::kNumber: appendNumber(&out, row.member.number(p)); break;
      case ParamType::kInteger: out += std::to_string(row.member.integer(p)); break;
      case ParamType::kBool: out += row.member.flag(p) ? "true" : "false"; break;
      case ParamType::kString: appendQuoted(&out, row.member.text(p)); break;
      case ParamType::kStringList: appendNames(&out, row.member.names(p)); break;
      case ParamType::kPairs: appendPairs(&out, row.member.pairs(p)); break;
      case ParamType::kStructure: break;
    }
    out += '\n';
  }
  // The robot as the URDF describes it is part of the configuration too (only when read).
  out += "robot_description=";
  if (params.use_robot_description && !urdf.empty()) {
    out += hex64(fnv1a64(urdf));
  } else {
    out += "\"\"";
  }
  out += '\n';
  return out;
}

std::string configFingerprint(const MonitorParams& params, const std::string& urdf) {
  return hex64(fnv1a64(canonicalConfig(params, urdf)));
}

std::vector<std::string> configChanges(const MonitorParams& before, const MonitorParams& after,
                                       const std::string& urdf) {
  std::vector<std::string> order_after;
  std::vector<std::string> order_before;
  const std::map<std::string, std::string> a = lines(canonicalConfig(before, urdf), &order_before);
  const std::map<std::string, std::string> b = lines(canonicalConfig(after, urdf), &order_after);
  std::vector<std::string> out;
  for (const std::string& name : order_after) {
    const auto old = a.find(name);
    const std::string& now = b.at(name);
    if (old == a.end()) {
      out.push_back(name + ": (none) -> " + now);
    } else if (old->second != now) {
      out.push_back(name + ": " + old->second + " -> " + now);
    }
  }
  for (const std::string& name : order_before) {
    if (b.count(name) == 0) out.push_back(name + ": " + a.at(name) + " -> (none)");
  }
  return out;
}

}  // namespace workspace_proximity
