#include "workspace_proximity/ros/ros_params.hpp"

#include <algorithm>
#include <stdexcept>

#include <XmlRpcValue.h>
#include <workspace_proximity/ProximityMonitorConfig.h>

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

// Each reader looks `name` up in `root`; errors name the parameter as `where` + `name` (where:
// the namespace inside the node's, e.g. "ssm/").
void readDouble(const XmlRpcValue& root, const std::string& name, double* out,
                const std::string& where = "") {
  if (const XmlRpcValue* v = member(root, name)) *out = toDouble(*v, where + name);
}

void readBool(const XmlRpcValue& root, const std::string& name, bool* out,
              const std::string& where = "") {
  XmlRpcValue* v = member(root, name);
  if (v == nullptr) return;
  if (v->getType() != XmlRpcValue::TypeBoolean) fail(where + name, "must be true or false");
  *out = static_cast<bool>(*v);
}

void readString(const XmlRpcValue& root, const std::string& name, std::string* out,
                const std::string& where = "") {
  if (const XmlRpcValue* v = member(root, name)) *out = toString(*v, where + name);
}

void readStringList(const XmlRpcValue& root, const std::string& name,
                    std::vector<std::string>* out, const std::string& where = "") {
  const XmlRpcValue* v = member(root, name);
  if (v == nullptr) return;
  if (v->getType() != XmlRpcValue::TypeArray) fail(where + name, "must be a list of strings");
  out->clear();
  for (int i = 0; i < v->size(); ++i) out->push_back(toString((*v)[i], where + name));
}

void readPairs(const XmlRpcValue& root, const std::string& name,
               std::vector<std::pair<std::string, std::string>>* out) {
  const XmlRpcValue* p = member(root, name);
  if (p == nullptr) return;
  const XmlRpcValue& v = *p;
  if (v.getType() != XmlRpcValue::TypeArray) fail(name, "must be a list of [selector, selector]");
  for (int i = 0; i < v.size(); ++i) {
    if (v[i].getType() != XmlRpcValue::TypeArray || v[i].size() != 2) {
      fail(name, "entry " + std::to_string(i) + " must be a list of two selectors");
    }
    out->emplace_back(toString(v[i][0], name), toString(v[i][1], name));
  }
}

// A label's settings (`track_label`), or the robot's thresholds: the robot has no margin
// here (~robot_margin) and no growth (its motion comes from tf), so those keys are refused.
LabelSettings readLabel(const XmlRpcValue& v, const std::string& name, LabelSettings l,
                        bool track_label = true) {
  if (v.getType() != XmlRpcValue::TypeStruct) fail(name, "must be a dictionary");
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string key = it->first;
    const double value = toDouble(it->second, name + "/" + key);
    if (key == "warning_time") l.warning_time = value;
    else if (key == "critical_time") l.critical_time = value;
    else if (key == "warning_distance") l.warning_distance = value;
    else if (key == "critical_distance") l.critical_distance = value;
    else if (track_label && key == "margin") l.margin = value;
    else if (track_label && key == "position_error") l.position_error = value;
    else if (track_label && key == "velocity_error") l.velocity_error = value;
    else if (track_label && key == "max_accel") l.max_accel = value;
    else if (track_label && key == "max_speed") l.max_speed = value;
    else if (track_label && key == "ssm_min_speed") l.ssm_min_speed = value;
    else if (track_label) {
      fail(name + "/" + key, "unknown setting (margin, warning_time, critical_time, "
                             "warning_distance, critical_distance, position_error, "
                             "velocity_error, max_accel, max_speed, ssm_min_speed)");
    } else {
      fail(name + "/" + key, "unknown setting (warning_time, critical_time, warning_distance, "
                             "critical_distance; the robot's margin is ~robot_margin)");
    }
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

// ~ssm/: speed and separation monitoring.
SsmParams readSsm(const XmlRpcValue& v) {
  SsmParams s;
  if (v.getType() != XmlRpcValue::TypeStruct) fail("ssm", "must be a dictionary");
  readBool(v, "enabled", &s.enabled, "ssm/");
  readStringList(v, "labels", &s.labels, "ssm/");
  readDouble(v, "reaction_time", &s.reaction_time, "ssm/");
  readDouble(v, "stopping_time", &s.stopping_time, "ssm/");
  readDouble(v, "intrusion_distance", &s.intrusion_distance, "ssm/");
  readDouble(v, "sensor_uncertainty", &s.sensor_uncertainty, "ssm/");
  readDouble(v, "robot_uncertainty", &s.robot_uncertainty, "ssm/");
  readDouble(v, "robot_max_speed", &s.robot_max_speed, "ssm/");
  readDouble(v, "max_increase_rate", &s.max_increase_rate, "ssm/");
  readDouble(v, "hold_time", &s.hold_time, "ssm/");
  readDouble(v, "degraded_scale", &s.degraded_scale, "ssm/");
  readStringList(v, "stop_trajectory_topics", &s.stop_trajectory_topics, "ssm/");
  readStringList(v, "stop_event_topics", &s.stop_event_topics, "ssm/");
  readString(v, "cmd_vel_in", &s.cmd_vel_in, "ssm/");
  readString(v, "cmd_vel_out", &s.cmd_vel_out, "ssm/");
  return s;
}

// Every key the node reads at the top of its namespace.
const char* const kNodeKeys[] = {
    "fixed_frame", "rate", "horizon", "track_timeout", "input_topics", "stale_after",
    "cycle_trigger", "trigger_source", "ssm",
    "source_timeout", "max_future", "max_tracks", "use_robot_description",
    "robot_description_param", "require_all_links", "robot_margin", "velocity_window", "tf_timeout",
    "use_joint_states", "trajectory_topic", "trajectory_tolerance", "joint_path_tolerance", "ignore_pairs",
    "check_pairs", "publish_markers", "marker_lifetime", "marker_rate", "robot_bodies", "labels",
    "robot_thresholds",
    // Read by libraries the node uses: diagnostic_updater's period.
    "diagnostic_period"};
const char* const kRobotBodyKeys[] = {"name", "frame", "size", "offset"};
const char* const kSsmKeys[] = {
    "enabled", "labels", "reaction_time", "stopping_time", "intrusion_distance",
    "sensor_uncertainty", "robot_uncertainty", "robot_max_speed", "max_increase_rate",
    "hold_time", "degraded_scale", "stop_trajectory_topics", "stop_event_topics", "cmd_vel_in",
    "cmd_vel_out"};
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
  std::vector<std::string> known(std::begin(kNodeKeys), std::end(kNodeKeys));
  // dynamic_reconfigure keeps its values beside the node's, under their own flat names.
  for (const auto& d : ProximityMonitorConfig::__getParamDescriptions__()) known.push_back(d->name);
  reportUnknown(root, "", known, &out);
  if (const XmlRpcValue* ssm = member(root, "ssm")) {
    reportUnknown(*ssm, "ssm/", std::vector<std::string>(std::begin(kSsmKeys), std::end(kSsmKeys)),
                  &out);
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
  readString(root, "fixed_frame", &p.fixed_frame);
  readDouble(root, "rate", &p.rate);
  readDouble(root, "horizon", &p.horizon);
  readDouble(root, "track_timeout", &p.track_timeout);
  readStringList(root, "input_topics", &p.input_topics);
  readDouble(root, "stale_after", &p.stale_after);
  readDouble(root, "source_timeout", &p.source_timeout);
  readDouble(root, "max_future", &p.max_future);
  readString(root, "cycle_trigger", &p.cycle_trigger);
  readString(root, "trigger_source", &p.trigger_source);
  if (const XmlRpcValue* v = member(root, "ssm")) p.ssm = readSsm(*v);
  if (const XmlRpcValue* max_tracks = member(root, "max_tracks")) {
    if (max_tracks->getType() != XmlRpcValue::TypeInt) fail("max_tracks", "must be an integer");
    p.max_tracks = static_cast<int>(const_cast<XmlRpcValue&>(*max_tracks));
  }
  readBool(root, "use_robot_description", &p.use_robot_description);
  readString(root, "robot_description_param", &p.robot_description_param);
  readBool(root, "require_all_links", &p.require_all_links);
  readDouble(root, "robot_margin", &p.robot_margin);
  readDouble(root, "velocity_window", &p.velocity_window);
  readDouble(root, "tf_timeout", &p.tf_timeout);
  readBool(root, "use_joint_states", &p.use_joint_states);
  readString(root, "trajectory_topic", &p.trajectory_topic);
  readDouble(root, "trajectory_tolerance", &p.trajectory_tolerance);
  readDouble(root, "joint_path_tolerance", &p.joint_path_tolerance);
  readPairs(root, "ignore_pairs", &p.ignore_pairs);
  readPairs(root, "check_pairs", &p.check_pairs);
  readBool(root, "publish_markers", &p.publish_markers);
  readDouble(root, "marker_lifetime", &p.marker_lifetime);
  readDouble(root, "marker_rate", &p.marker_rate);

  if (const XmlRpcValue* v = member(root, "robot_bodies")) {
    if (v->getType() != XmlRpcValue::TypeArray) fail("robot_bodies", "must be a list");
    for (int i = 0; i < v->size(); ++i) {
      p.robot_bodies.push_back(readRobotBody((*v)[i], "robot_bodies[" + std::to_string(i) + "]"));
    }
  }
  if (const XmlRpcValue* v = member(root, "labels")) {
    if (v->getType() != XmlRpcValue::TypeStruct) fail("labels", "must be a dictionary of labels");
    // "default" first, so other labels inherit from it.
    if (v->hasMember("default")) {
      p.labels["default"] = readLabel((*v)["default"], "labels/default", LabelSettings());
    }
    for (auto it = v->begin(); it != v->end(); ++it) {
      if (it->first == "default") continue;
      p.labels[it->first] = readLabel(it->second, "labels/" + it->first, p.labels["default"]);
    }
  }
  if (const XmlRpcValue* v = member(root, "robot_thresholds")) {
    p.robot_thresholds = readLabel(*v, "robot_thresholds", p.robot_thresholds, false);
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
