#include "workspace_proximity/ros/proximity_monitor.hpp"

#include <chrono>
#include <cmath>
#include <unordered_set>

#include <ros/package.h>
#include <tf2_eigen/tf2_eigen.h>

#include "workspace_proximity/ros/robot_model.hpp"
#include "workspace_proximity/swept_bounds.hpp"

namespace workspace_proximity {
namespace {

// "package://pkg/path" and "file:///path" to a local path; empty when unresolvable.
std::string resolveMesh(const std::string& url) {
  const std::string package_prefix = "package://";
  const std::string file_prefix = "file://";
  if (url.compare(0, package_prefix.size(), package_prefix) == 0) {
    const std::string rest = url.substr(package_prefix.size());
    const auto slash = rest.find('/');
    if (slash == std::string::npos) return std::string();
    const std::string root = ros::package::getPath(rest.substr(0, slash));
    return root.empty() ? std::string() : root + rest.substr(slash);
  }
  if (url.compare(0, file_prefix.size(), file_prefix) == 0) return url.substr(file_prefix.size());
  return url;
}

// The shape a box should have now: grow at once (never smaller than the truth), shrink only
// when clearly smaller, so a tracker's jittering dimensions do not rebuild geometry each time.
bool needsResize(const Eigen::Vector3d& current, const Eigen::Vector3d& wanted) {
  constexpr double kShrinkSlack = 0.05;  // m
  return (wanted.array() > current.array()).any() ||
         (wanted.array() < current.array() - kShrinkSlack).any();
}

}  // namespace

ProximityMonitor::ProximityMonitor(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh,
                                   const MonitorParams& params)
    : nh_(nh),
      pnh_(private_nh),
      params_(params),
      tf_buffer_(ros::Duration(std::max(10.0, 4.0 * params.velocity_window))),
      tf_listener_(tf_buffer_),
      diagnostics_(nh_, pnh_),
      world_([&] {
        WorldConfig config;
        config.rules = makePairRules(params);
        return config;
      }()),
      markers_(params.fixed_frame, params.marker_lifetime) {
  loadRobot();

  contacts_pub_ = nh_.advertise<ContactEventArray>("contacts", 10);
  if (params_.publish_markers) {
    markers_pub_ = nh_.advertise<visualization_msgs::MarkerArray>("markers", 10);
  }
  // Queue of 1: only the newest array of each source is worth predicting from.
  if (params_.input_topics.empty()) {
    subscribers_.push_back(nh_.subscribe<TrackedBoxArray>(
        "tracked_objects", 1,
        [this](const TrackedBoxArray::ConstPtr& msg) { onBoxes(msg, std::string()); }));
  } else {
    for (const std::string& topic : params_.input_topics) {
      const std::string qualifier = nh_.resolveName(topic);
      subscribers_.push_back(nh_.subscribe<TrackedBoxArray>(
          topic, 1,
          [this, qualifier](const TrackedBoxArray::ConstPtr& msg) { onBoxes(msg, qualifier); }));
    }
  }

  diagnostics_.setHardwareID("workspace_proximity");
  diagnostics_.add("proximity monitor", this, &ProximityMonitor::diagnose);
  timer_ = nh_.createTimer(ros::Duration(1.0 / params_.rate),
                           [this](const ros::TimerEvent&) { cycle(ros::Time::now()); });
  ROS_INFO("proximity_monitor: %zu robot bodies, fixed frame '%s', %.1f Hz, horizon %.2f s",
           robot_.size(), params_.fixed_frame.c_str(), params_.rate, params_.horizon);
}

void ProximityMonitor::loadRobot() {
  std::vector<RobotBodySpec> specs = params_.robot_bodies;
  if (params_.use_robot_description) {
    std::string urdf;
    if (nh_.getParam(params_.robot_description_param, urdf)) {
      std::vector<std::string> warnings;
      const std::vector<RobotBodySpec> from_urdf = bodiesFromUrdf(urdf, resolveMesh, &warnings);
      for (const std::string& w : warnings) ROS_WARN("proximity_monitor: URDF %s", w.c_str());
      specs.insert(specs.end(), from_urdf.begin(), from_urdf.end());
    } else {
      ROS_INFO("proximity_monitor: no '%s' parameter; robot bodies from ~robot_bodies only",
               params_.robot_description_param.c_str());
    }
  }
  std::unordered_set<std::string> names;
  for (const RobotBodySpec& spec : specs) {
    if (!names.insert(spec.name).second) {
      ROS_WARN("proximity_monitor: robot body '%s' declared twice; the first is used",
               spec.name.c_str());
      continue;
    }
    RobotBody body;
    body.spec = spec;
    robot_.push_back(body);
  }
}

void ProximityMonitor::onBoxes(const TrackedBoxArray::ConstPtr& msg, const std::string& qualifier) {
  // Everything here must be non-blocking and must not throw out of the callback.
  const std::string source = qualifier.empty() ? std::string("tracked_objects") : qualifier;
  if (msg->header.frame_id.empty()) {
    ++arrays_dropped_;
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: array on %s has an empty frame_id; dropped",
                      source.c_str());
    return;
  }
  ros::Time stamp = msg->header.stamp;
  const ros::Time now = ros::Time::now();
  if (stamp.isZero()) {
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: array on %s has stamp 0; using the receive time",
                      source.c_str());
    stamp = now;
  }
  Eigen::Isometry3d fixed_from_frame;
  try {
    fixed_from_frame = tf2::transformToEigen(
        tf_buffer_.lookupTransform(params_.fixed_frame, msg->header.frame_id, stamp));
  } catch (const tf2::TransformException& at_stamp) {
    // The newest transform is the best we have when tf lags the tracker; a frame tf cannot
    // reach at all drops the array.
    try {
      fixed_from_frame = tf2::transformToEigen(
          tf_buffer_.lookupTransform(params_.fixed_frame, msg->header.frame_id, ros::Time(0)));
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: %s: no transform at the array's stamp (%s); "
                             "using the latest",
                        source.c_str(), at_stamp.what());
    } catch (const tf2::TransformException& e) {
      ++arrays_dropped_;
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: %s: cannot transform '%s' to '%s': %s; dropped",
                        source.c_str(), msg->header.frame_id.c_str(),
                        params_.fixed_frame.c_str(), e.what());
      return;
    }
  }
  last_input_ = now;

  std::unordered_set<std::string> seen;
  for (const TrackedBox& box : msg->boxes) {
    const std::string why = checkTrackedBox(box);
    if (!why.empty()) {
      ++boxes_rejected_;
      ROS_WARN_THROTTLE(2.0, "proximity_monitor: %s: track '%s' rejected: %s", source.c_str(),
                        box.id.c_str(), why.c_str());
      continue;
    }
    if (!seen.insert(box.id).second) {
      ++boxes_rejected_;
      ROS_WARN_THROTTLE(2.0, "proximity_monitor: %s: track '%s' appears twice in one array; "
                             "the first is used",
                        source.c_str(), box.id.c_str());
      continue;
    }
    const std::string key = qualifier.empty() ? box.id : qualifier + "/" + box.id;
    updateTrack(key, box, toMotion(box, fixed_from_frame), stamp);
  }
}

void ProximityMonitor::updateTrack(const std::string& key, const TrackedBox& box,
                                   const BodyMotion& motion, const ros::Time& stamp) {
  const Shape shape = toShape(box);
  auto it = tracks_.find(key);
  if (it != tracks_.end() && it->second.label != box.label) {
    ROS_WARN_THROTTLE(2.0, "proximity_monitor: track '%s' changed label '%s' -> '%s'; "
                           "restarting it",
                      key.c_str(), it->second.label.c_str(), box.label.c_str());
    world_.removeBody(it->second.handle);
    tracks_.erase(it);
    it = tracks_.end();
  }
  if (it == tracks_.end()) {
    Track t;
    t.label = box.label;
    t.stamp = stamp;
    t.motion = motion;
    t.half = shape.half_extents;
    t.handle = world_.addBody(
        BodyDesc{key, box.label, BodyGroup::kObject, shape, params_.label(box.label).margin},
        motion);
    tracks_.emplace(key, t);
    return;
  }
  Track& t = it->second;
  if (stamp < t.stamp) return;  // older than what we have: out-of-order delivery
  t.stamp = stamp;
  t.motion = motion;
  if (needsResize(t.half, shape.half_extents)) {
    t.half = shape.half_extents;
    world_.setShape(t.handle, shape, params_.label(box.label).margin);
  }
}

void ProximityMonitor::expireTracks(const ros::Time& now) {
  for (auto it = tracks_.begin(); it != tracks_.end();) {
    if ((now - it->second.stamp).toSec() > params_.track_timeout) {
      world_.removeBody(it->second.handle);
      it = tracks_.erase(it);
    } else {
      ++it;
    }
  }
}

bool ProximityMonitor::robotMotion(const RobotBody& body, const ros::Time& now, BodyMotion* motion,
                                   std::string* why) {
  geometry_msgs::TransformStamped latest;
  try {
    latest = tf_buffer_.lookupTransform(params_.fixed_frame, body.spec.frame, ros::Time(0));
  } catch (const tf2::TransformException& e) {
    *why = e.what();
    return false;
  }
  const Eigen::Isometry3d pose1 = tf2::transformToEigen(latest) * body.spec.offset;
  motion->position = pose1.translation();
  motion->orientation = Eigen::Quaterniond(pose1.linear()).normalized();
  motion->linear_velocity.setZero();
  motion->angular_velocity.setZero();
  const ros::Time t1 = latest.header.stamp;
  if (t1.isZero()) return true;  // a static chain: no motion, never stale

  const double age = (now - t1).toSec();
  if (age > params_.tf_timeout) {
    *why = "latest transform is " + std::to_string(age) + " s old";
    return false;
  }
  // Velocity by finite difference over the last velocity_window seconds of tf history.
  const ros::Time t0 = t1 - ros::Duration(params_.velocity_window);
  try {
    const Eigen::Isometry3d pose0 =
        tf2::transformToEigen(tf_buffer_.lookupTransform(params_.fixed_frame, body.spec.frame, t0)) *
        body.spec.offset;
    const double dt = (t1 - t0).toSec();
    motion->linear_velocity = (pose1.translation() - pose0.translation()) / dt;
    const Eigen::AngleAxisd turn(pose1.linear() * pose0.linear().transpose());
    motion->angular_velocity = turn.axis() * (turn.angle() / dt);
  } catch (const tf2::TransformException&) {
    // Not enough history yet (just started): treat the link as momentarily still.
  }
  *motion = motion->advanced(age);
  return true;
}

void ProximityMonitor::updateRobot(const ros::Time& now) {
  robot_unknown_ = 0;
  for (RobotBody& body : robot_) {
    BodyMotion motion;
    std::string why;
    if (!robotMotion(body, now, &motion, &why) || !motion.valid()) {
      ++robot_unknown_;
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: robot body '%s' (frame '%s') not posed: %s",
                        body.spec.name.c_str(), body.spec.frame.c_str(), why.c_str());
      if (body.present) {
        world_.removeBody(body.handle);
        body.present = false;
      }
      continue;
    }
    if (!body.present) {
      body.handle = world_.addBody(BodyDesc{body.spec.name, "robot", BodyGroup::kRobot,
                                            body.spec.shape, params_.robot_margin},
                                   motion);
      body.present = true;
    } else {
      world_.setMotion(body.handle, motion);
    }
  }
}

void ProximityMonitor::cycle(const ros::Time& now) {
  const auto start = std::chrono::steady_clock::now();
  expireTracks(now);
  for (auto& kv : tracks_) {
    // Latency compensation: every track is moved from its own stamp to the cycle instant.
    world_.setMotion(kv.second.handle, kv.second.motion.advanced((now - kv.second.stamp).toSec()));
  }
  updateRobot(now);
  const std::vector<PairEvent>& events = world_.predict(params_.horizon);
  publish(now, events);
  ++cycles_;
  last_cycle_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  diagnostics_.update();
}

void ProximityMonitor::publish(const ros::Time& now, const std::vector<PairEvent>& events) {
  contacts_msg_.header.stamp = now;
  contacts_msg_.header.frame_id = params_.fixed_frame;
  contacts_msg_.events.clear();
  worst_level_.clear();
  for (const PairEvent& e : events) {
    const BodyDesc& a = world_.desc(e.body_a);
    const BodyDesc& b = world_.desc(e.body_b);
    const LabelSettings& la = a.group == BodyGroup::kRobot ? params_.robot_thresholds : params_.label(a.label);
    const LabelSettings& lb = b.group == BodyGroup::kRobot ? params_.robot_thresholds : params_.label(b.label);
    const std::uint8_t level = contactLevel(e, la, lb);
    contacts_msg_.events.push_back(toMsg(e, a, b, level));
    if (e.state != ContactState::kEnd) {
      for (const BodyHandle& h : {e.body_a, e.body_b}) {
        auto it = worst_level_.find(h.index);
        if (it == worst_level_.end() || it->second < level) worst_level_[h.index] = level;
      }
    }
  }
  contacts_pub_.publish(contacts_msg_);

  if (!params_.publish_markers) return;
  marker_bodies_.clear();
  auto addMarkerBody = [&](BodyHandle h, bool robot) {
    MarkerBody m;
    const BodyDesc& d = world_.desc(h);
    const BodyMotion& motion = world_.motion(h);
    m.id = d.id;
    m.robot = robot;
    m.shape = d.shape;
    m.pose = motion.poseAt(0.0);
    m.velocity = motion.linear_velocity;
    m.swept = world_.sweptBounds(h);
    auto it = worst_level_.find(h.index);
    m.level = it == worst_level_.end() ? -1 : it->second;
    marker_bodies_.push_back(m);
  };
  for (const auto& kv : tracks_) addMarkerBody(kv.second.handle, false);
  for (const RobotBody& body : robot_) {
    if (body.present) addMarkerBody(body.handle, true);
  }
  markers_.build(marker_bodies_, contacts_msg_, now, &markers_msg_);
  markers_pub_.publish(markers_msg_);
}

void ProximityMonitor::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const WorldStats& s = world_.stats();
  if (robot_unknown_ > 0) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN, "%d robot bodies cannot be posed",
                    robot_unknown_);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "predicting");
  }
  status.add("cycles", cycles_);
  status.add("cycle time (ms)", last_cycle_ms_);
  status.add("tracks", tracks_.size());
  status.add("robot bodies", robot_.size());
  status.add("robot bodies not posed", robot_unknown_);
  status.add("broad-phase pairs", s.broad_pairs);
  status.add("predicted contacts", s.contacts);
  status.add("boxes rejected", boxes_rejected_);
  status.add("arrays dropped", arrays_dropped_);
  status.add("seconds since last input", last_input_.isZero() ? -1.0 : (ros::Time::now() - last_input_).toSec());
}

}  // namespace workspace_proximity
