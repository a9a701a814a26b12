#include "workspace_proximity/ros/ros_params.hpp"

#include <stdexcept>

#include <XmlRpcValue.h>

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

void readDouble(const ros::NodeHandle& nh, const std::string& name, double* out) {
  XmlRpcValue v;
  if (nh.getParam(name, v)) *out = toDouble(v, name);
}

void readBool(const ros::NodeHandle& nh, const std::string& name, bool* out) {
  XmlRpcValue v;
  if (!nh.getParam(name, v)) return;
  if (v.getType() != XmlRpcValue::TypeBoolean) fail(name, "must be true or false");
  *out = static_cast<bool>(v);
}

void readString(const ros::NodeHandle& nh, const std::string& name, std::string* out) {
  XmlRpcValue v;
  if (nh.getParam(name, v)) *out = toString(v, name);
}

void readStringList(const ros::NodeHandle& nh, const std::string& name,
                    std::vector<std::string>* out) {
  XmlRpcValue v;
  if (!nh.getParam(name, v)) return;
  if (v.getType() != XmlRpcValue::TypeArray) fail(name, "must be a list of strings");
  out->clear();
  for (int i = 0; i < v.size(); ++i) out->push_back(toString(v[i], name));
}

void readPairs(const ros::NodeHandle& nh, const std::string& name,
               std::vector<std::pair<std::string, std::string>>* out) {
  XmlRpcValue v;
  if (!nh.getParam(name, v)) return;
  if (v.getType() != XmlRpcValue::TypeArray) fail(name, "must be a list of [selector, selector]");
  for (int i = 0; i < v.size(); ++i) {
    if (v[i].getType() != XmlRpcValue::TypeArray || v[i].size() != 2) {
      fail(name, "entry " + std::to_string(i) + " must be a list of two selectors");
    }
    out->emplace_back(toString(v[i][0], name), toString(v[i][1], name));
  }
}

LabelSettings readLabel(XmlRpcValue& v, const std::string& name, LabelSettings l) {
  if (v.getType() != XmlRpcValue::TypeStruct) fail(name, "must be a dictionary");
  for (auto it = v.begin(); it != v.end(); ++it) {
    const std::string key = it->first;
    const double value = toDouble(it->second, name + "/" + key);
    if (key == "margin") l.margin = value;
    else if (key == "warning_time") l.warning_time = value;
    else if (key == "critical_time") l.critical_time = value;
    else if (key == "warning_distance") l.warning_distance = value;
    else if (key == "critical_distance") l.critical_distance = value;
    else fail(name + "/" + key, "unknown setting (margin, warning_time, critical_time, "
                                "warning_distance, critical_distance)");
  }
  return l;
}

RobotBodySpec readRobotBody(XmlRpcValue& v, const std::string& name) {
  if (v.getType() != XmlRpcValue::TypeStruct) fail(name, "must be a dictionary");
  RobotBodySpec b;
  if (!v.hasMember("name") || !v.hasMember("frame") || !v.hasMember("size")) {
    fail(name, "needs name, frame and size");
  }
  b.name = toString(v["name"], name + "/name");
  b.frame = toString(v["frame"], name + "/frame");
  b.shape = Shape::box(0.5 * toVector3(v["size"], name + "/size"));
  if (v.hasMember("offset")) {
    XmlRpcValue& o = v["offset"];
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

}  // namespace

MonitorParams readParams(const ros::NodeHandle& nh) {
  MonitorParams p;
  readString(nh, "fixed_frame", &p.fixed_frame);
  readDouble(nh, "rate", &p.rate);
  readDouble(nh, "horizon", &p.horizon);
  readDouble(nh, "track_timeout", &p.track_timeout);
  readStringList(nh, "input_topics", &p.input_topics);
  readDouble(nh, "stale_after", &p.stale_after);
  readDouble(nh, "source_timeout", &p.source_timeout);
  readDouble(nh, "max_future", &p.max_future);
  XmlRpcValue max_tracks;
  if (nh.getParam("max_tracks", max_tracks)) {
    if (max_tracks.getType() != XmlRpcValue::TypeInt) fail("max_tracks", "must be an integer");
    p.max_tracks = static_cast<int>(max_tracks);
  }
  readBool(nh, "use_robot_description", &p.use_robot_description);
  readString(nh, "robot_description_param", &p.robot_description_param);
  readDouble(nh, "robot_margin", &p.robot_margin);
  readDouble(nh, "velocity_window", &p.velocity_window);
  readDouble(nh, "tf_timeout", &p.tf_timeout);
  readPairs(nh, "ignore_pairs", &p.ignore_pairs);
  readPairs(nh, "check_pairs", &p.check_pairs);
  readBool(nh, "publish_markers", &p.publish_markers);
  readDouble(nh, "marker_lifetime", &p.marker_lifetime);
  readDouble(nh, "marker_rate", &p.marker_rate);

  XmlRpcValue v;
  if (nh.getParam("robot_bodies", v)) {
    if (v.getType() != XmlRpcValue::TypeArray) fail("robot_bodies", "must be a list");
    for (int i = 0; i < v.size(); ++i) {
      p.robot_bodies.push_back(readRobotBody(v[i], "robot_bodies[" + std::to_string(i) + "]"));
    }
  }
  if (nh.getParam("labels", v)) {
    if (v.getType() != XmlRpcValue::TypeStruct) fail("labels", "must be a dictionary of labels");
    // "default" first, so other labels inherit from it.
    if (v.hasMember("default")) p.labels["default"] = readLabel(v["default"], "labels/default", LabelSettings());
    for (auto it = v.begin(); it != v.end(); ++it) {
      if (it->first == "default") continue;
      p.labels[it->first] = readLabel(it->second, "labels/" + it->first, p.labels["default"]);
    }
  }
  if (nh.getParam("robot_thresholds", v)) {
    p.robot_thresholds = readLabel(v, "robot_thresholds", p.robot_thresholds);
  }
  return p;
}

}  // namespace workspace_proximity
