#include "workspace_proximity/ros/ros_params.hpp"

#include <algorithm>
#include <stdexcept>

#include <XmlRpcValue.h>
#include <workspace_proximity/ProximityMonitorConfig.h>

#include "workspace_proximity/rules/param_table.hpp"

namespace workspace_proximity {
namespace {

using XmlRpc::XmlRpcValue;

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw std::runtime_error("~" + name + ": " + what);
}

double toDouble(const XmlRpcValue& v, const std::string& name) {
  if (v.getType() == XmlRpcValue::TypeDouble) return static_cast<double>(const_cast<XmlRpcValue&>(v));
  if (v.getType() == XmlRpcValue::TypeInt) return static_cast<int>(const_cast<XmlRpcValue&>(v));
  fail(name, "must be a number");
}

std::string toString(const XmlRpcValue& v, const std::string& name) {
  if (v.getType() != XmlRpcValue::TypeString) fail(name, "must be a string");
  return static_cast<std::string>(const_cast<XmlRpcValue&>(v));
}

Eigen::Vector3d toVector3(const XmlRpcValue& v, const std::string& name) {
  if (v.getType() != XmlRpcValue::TypeArray || v.size() != 3) fail(name, "must be a list of 3 numbers");
  XmlRpcValue& a = const_cast<XmlRpcValue&>(v);
  return Eigen::Vector3d(toDouble(a[0], name), toDouble(a[1], name), toDouble(a[2], name));
}

// The parameter `name` of the namespace `root` (a struct), or null when it is not set.
XmlRpcValue* member(const XmlRpcValue& root, const std::string& name) {
  if (!root.hasMember(name)) return nullptr;
  return &root[name];  // XmlRpcValue's struct operator[] is const and returns a reference
}

// The value of `name` ("horizon", "ssm/hold_time") under `root`, or null when it is not set. A
// namespace on the way that is not a dictionary is refused ("~ssm: must be a dictionary").
const XmlRpcValue* lookup(const XmlRpcValue& root, const std::string& name) {
  const XmlRpcValue* at = &root;
  std::size_t from = 0;
  for (std::size_t slash = name.find('/'); slash != std::string::npos;
       from = slash + 1, slash = name.find('/', from)) {
    at = member(*at, name.substr(from, slash - from));
    if (at == nullptr) return nullptr;
    if (at->getType() != XmlRpcValue::TypeStruct) fail(name.substr(0, slash), "must be a dictionary");
  }
  return member(*at, name.substr(from));
}

void readPairs(const XmlRpcValue& v, const std::string& name,
               std::vector<std::pair<std::string, std::string>>* out) {
  if (v.getType() != XmlRpcValue::TypeArray) fail(name, "must be a list of [selector, selector]");
  for (int i = 0; i < v.size(); ++i) {
    if (v[i].getType() != XmlRpcValue::TypeArray || v[i].size() != 2) {
      fail(name, "entry " + std::to_string(i) + " must be a list of two selectors");
    }
    out->emplace_back(toString(v[i][0], name), toString(v[i][1], name));
  }
}

// "unknown setting (margin, warning_time, ...)": the settings a label (`track_label`) or the
// robot's thresholds have, as labelTable() lists them.
std::string unknownSetting(bool track_label) {
  std::string keys;
  for (const LabelRow& row : labelTable()) {
    if (row.track_only && !track_label) continue;
    keys += (keys.empty() ? "" : ", ") + std::string(row.key);
  }
  if (!track_label) keys += "; the robot's margin is ~robot_margin";
  return "unknown setting (" + keys + ")";
}

// A label's settings (`track_label`), or the robot's thresholds: the robot has no margin
// here (~robot_margin) and no growth (its motion comes from tf), so those keys are refused.
LabelSettings readLabel(const XmlRpcValue& v, const std::string& name, LabelSettings l,
                        bool track_label = true) {
  if (v.getType() != XmlRpcValue::TypeStruct) fail(name, "must be a dictionary");
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string key = it->first;
    // A dictionary inside a track label is a sub-label ("person/head": the parameter server
    // nests a label whose name has a '/'), read by readLabels.
    if (track_label && it->second.getType() == XmlRpcValue::TypeStruct) continue;
    const double value = toDouble(it->second, name + "/" + key);
    const LabelRow* row = findLabelSetting(key);
    if (row == nullptr || (row->track_only && !track_label)) {
      fail(name + "/" + key, unknownSetting(track_label));
    }
    l.*row->member = value;
  }
  return l;
}

RobotBodySpec readRobotBody(const XmlRpcValue& v, const std::string& name) {
  if (v.getType() != XmlRpcValue::TypeStruct) fail(name, "must be a dictionary");
  RobotBodySpec b;
  if (!v.hasMember("name") || !v.hasMember("frame") || !v.hasMember("size")) {
    fail(name, "needs name, frame and size");
  }
  b.name = toString(v["name"], name + "/name");
  b.frame = toString(v["frame"], name + "/frame");
  b.shape = Shape::box(0.5 * toVector3(v["size"], name + "/size"));
  if (v.hasMember("offset")) {
    const XmlRpcValue& o = v["offset"];
    if (o.getType() != XmlRpcValue::TypeStruct) fail(name + "/offset", "must be {xyz: [..], rpy: [..]}");
    Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
    if (o.hasMember("xyz")) xyz = toVector3(o["xyz"], name + "/offset/xyz");
    if (o.hasMember("rpy")) rpy = toVector3(o["rpy"], name + "/offset/rpy");
    b.offset = Eigen::Isometry3d::Identity();
    b.offset.translation() = xyz;
    // URDF convention: fixed-axis roll, pitch, yaw = R_z(yaw) R_y(pitch) R_x(roll).
    b.offset.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                         Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                         Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                            .toRotationMatrix();
  }
  return b;
}

// Sub-labels of `name` (the dictionaries among its keys): "person/head" arrives as the key
// "head" of "person", since the parameter server makes every '/' a namespace. Each inherits
// its parent's settings.
void readSubLabels(const XmlRpcValue& v, const std::string& name, MonitorParams* p) {
  for (auto it = v.begin(); it != v.end(); ++it) {
    if (it->second.getType() != XmlRpcValue::TypeStruct) continue;
    const std::string sub = name + "/" + it->first;
    p->labels[sub] = readLabel(it->second, "labels/" + sub, p->labels[name]);
    readSubLabels(it->second, sub, p);
  }
}

// ~labels: "default" first, so that the other labels inherit from it.
void readLabels(const XmlRpcValue& v, MonitorParams* p) {
  if (v.getType() != XmlRpcValue::TypeStruct) fail("labels", "must be a dictionary of labels");
  if (v.hasMember("default")) {
    p->labels["default"] = readLabel(v["default"], "labels/default", LabelSettings());
  }
  for (auto it = v.begin(); it != v.end(); ++it) {
    if (it->first == "default") continue;
    // "person/head" as one key (a YAML file read without the parameter server: the replay)
    // inherits from "person" too, read before it (a prefix sorts first).
    const std::string& name = it->first;
    const auto slash = name.rfind('/');
    const auto parent = slash == std::string::npos ? p->labels.end()
                                                   : p->labels.find(name.substr(0, slash));
    const LabelSettings& base = parent != p->labels.end() ? parent->second : p->labels["default"];
    p->labels[name] = readLabel(it->second, "labels/" + name, base);
    readSubLabels(it->second, name, p);
  }
}

void readRobotBodies(const XmlRpcValue& v, MonitorParams* p) {
  if (v.getType() != XmlRpcValue::TypeArray) fail("robot_bodies", "must be a list");
  for (int i = 0; i < v.size(); ++i) {
    p->robot_bodies.push_back(readRobotBody(v[i], "robot_bodies[" + std::to_string(i) + "]"));
  }
}

// One row's value `v` into `p`, by the row's type.
void readRow(const ParamRow& row, const XmlRpcValue& v, MonitorParams* p) {
  const std::string name = row.name;
  switch (row.member.type) {
    case ParamType::kNumber:
      row.member.number(*p) = toDouble(v, name);
      return;
    case ParamType::kInteger:
      if (v.getType() != XmlRpcValue::TypeInt) fail(name, "must be an integer");
      row.member.integer(*p) = static_cast<int>(const_cast<XmlRpcValue&>(v));
      return;
    case ParamType::kBool:
      if (v.getType() != XmlRpcValue::TypeBoolean) fail(name, "must be true or false");
      row.member.flag(*p) = static_cast<bool>(const_cast<XmlRpcValue&>(v));
      return;
    case ParamType::kString:
      row.member.text(*p) = toString(v, name);
      return;
    case ParamType::kStringList: {
      if (v.getType() != XmlRpcValue::TypeArray) fail(name, "must be a list of strings");
      std::vector<std::string>& out = row.member.names(*p);
      out.clear();
      for (int i = 0; i < v.size(); ++i) out.push_back(toString(v[i], name));
      return;
    }
    case ParamType::kPairs:
      readPairs(v, name, &row.member.pairs(*p));
      return;
    case ParamType::kStructure:
      if (name == "labels") {
        readLabels(v, p);
      } else if (name == "robot_bodies") {
        readRobotBodies(v, p);
      } else if (name == "robot_thresholds") {
        p->robot_thresholds = readLabel(v, name, p->robot_thresholds, false);
      } else {
        throw std::logic_error("~" + name + ": a structure without a reader");
      }
      return;
  }
}

// Keys read by libraries the node uses (diagnostic_updater's period), beside the table's.
const char* const kForeignKeys[] = {"diagnostic_period"};
const char* const kRobotBodyKeys[] = {"name", "frame", "size", "offset"};
const char* const kOffsetKeys[] = {"xyz", "rpy"};

// Levenshtein distance, for "did you mean" (short strings, off the hot path).
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

// Appends "~<where><key>: unknown ..." for every key of `dict` not in `known`.
void reportUnknown(const XmlRpcValue& dict, const std::string& where,
                   const std::vector<std::string>& known, std::vector<std::string>* out) {
  if (dict.getType() != XmlRpcValue::TypeStruct) return;
  for (auto it = dict.begin(); it != dict.end(); ++it) {
    if (std::find(known.begin(), known.end(), it->first) != known.end()) continue;
    std::string line = "~" + where + it->first + ": unknown parameter, not used";
    std::size_t best = 3;  // suggest only close matches
    std::string suggestion;
    for (const std::string& k : known) {
      const std::size_t d = editDistance(it->first, k);
      if (d < best) {
        best = d;
        suggestion = k;
      }
    }
    if (!suggestion.empty()) line += " (did you mean ~" + where + suggestion + "?)";
    out->push_back(line);
  }
}

}  // namespace

std::vector<std::string> unknownParams(const XmlRpcValue& root) {
  std::vector<std::string> out;
  // The table's names: "horizon" at the top, "ssm/hold_time" as "ssm" at the top and
  // "hold_time" in the namespace "ssm".
  std::vector<std::string> known;
  std::vector<std::pair<std::string, std::vector<std::string>>> namespaces;
  for (const ParamRow& row : paramTable()) {
    const std::string name = row.name;
    const std::size_t slash = name.find('/');
    const std::string top = name.substr(0, slash);
    if (std::find(known.begin(), known.end(), top) == known.end()) known.push_back(top);
    if (slash == std::string::npos) continue;
    auto ns = std::find_if(namespaces.begin(), namespaces.end(),
                           [&](const auto& n) { return n.first == top; });
    if (ns == namespaces.end()) {
      namespaces.emplace_back(top, std::vector<std::string>());
      ns = namespaces.end() - 1;
    }
    ns->second.push_back(name.substr(slash + 1));
  }
  known.insert(known.end(), std::begin(kForeignKeys), std::end(kForeignKeys));
  // dynamic_reconfigure keeps its values beside the node's, under their own flat names.
  for (const auto& d : ProximityMonitorConfig::__getParamDescriptions__()) known.push_back(d->name);
  reportUnknown(root, "", known, &out);
  for (const auto& ns : namespaces) {
    if (const XmlRpcValue* dict = member(root, ns.first)) {
      reportUnknown(*dict, ns.first + "/", ns.second, &out);
    }
  }
  if (const XmlRpcValue* bodies = member(root, "robot_bodies")) {
    if (bodies->getType() == XmlRpcValue::TypeArray) {
      const std::vector<std::string> body_keys(std::begin(kRobotBodyKeys), std::end(kRobotBodyKeys));
      const std::vector<std::string> offset_keys(std::begin(kOffsetKeys), std::end(kOffsetKeys));
      for (int i = 0; i < bodies->size(); ++i) {
        const std::string where = "robot_bodies[" + std::to_string(i) + "]/";
        reportUnknown((*bodies)[i], where, body_keys, &out);
        if ((*bodies)[i].getType() == XmlRpcValue::TypeStruct && (*bodies)[i].hasMember("offset")) {
          reportUnknown((*bodies)[i]["offset"], where + "offset/", offset_keys, &out);
        }
      }
    }
  }
  return out;
}

std::vector<std::string> unknownParams(const ros::NodeHandle& nh) {
  XmlRpcValue root;
  if (!nh.getParam(nh.getNamespace(), root)) return {};
  return unknownParams(root);
}

MonitorParams readParams(const XmlRpcValue& root) {
  MonitorParams p;
  if (root.getType() != XmlRpcValue::TypeStruct && root.getType() != XmlRpcValue::TypeInvalid) {
    throw std::runtime_error("~: the node's parameters must be a dictionary");
  }
  for (const ParamRow& row : paramTable()) {
    if (const XmlRpcValue* v = lookup(root, row.name)) readRow(row, *v, &p);
  }
  return p;
}

MonitorParams readParams(const ros::NodeHandle& nh) {
  // The whole private namespace in one call: a dictionary of every parameter set under it.
  XmlRpcValue root;
  if (!nh.getParam(nh.getNamespace(), root)) return readParams(XmlRpcValue());
  return readParams(root);
}

}  // namespace workspace_proximity
