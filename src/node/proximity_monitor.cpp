#include "workspace_proximity/ros/proximity_monitor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <unordered_set>

#include <tf2_eigen/tf2_eigen.h>

#include "workspace_proximity/ros/robot_model.hpp"

namespace workspace_proximity {
namespace {

// Grow at once (never smaller than the truth); shrink only when clearly smaller, so a
// tracker's jittering dimensions do not rebuild the geometry every message.
bool needsResize(const Eigen::Vector3d& current, const Eigen::Vector3d& wanted) {
  constexpr double kShrinkSlack = 0.05;  // m
  return (wanted.array() > current.array()).any() ||
         (wanted.array() < current.array() - kShrinkSlack).any();
}

// t1 - t0 in seconds, exact to the nanosecond (ros::Time's operator- normalises through a
// Duration, which is slow in per-track loops).
double secondsBetween(const ros::Time& t0, const ros::Time& t1) {
  return static_cast<double>(static_cast<std::int64_t>(t1.toNSec()) -
                             static_cast<std::int64_t>(t0.toNSec())) *
         1e-9;
}

// Reason category for the diagnostics' "dropped by reason" counters.
std::string category(const std::string& why) {
  static const std::pair<const char*, const char*> kCategories[] = {
      {"empty id", "empty id"},           {"non-finite", "non-finite"},
      {"dimensions", "dimensions"},       {"position", "position"},
      {"orientation", "orientation"},     {"speed", "speed"},
      {"angular speed", "angular speed"}, {"duplicate", "duplicate id"},
      {"cap", "cap"},                     {"rejected by the core", "core limits"}};
  for (const auto& c : kCategories) {
    if (why.compare(0, std::strlen(c.first), c.first) == 0) return c.second;
  }
  return why.substr(0, why.find(' '));
}

std::string format(const char* fmt, double value) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, fmt, value);
  return buffer;
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
  std::vector<std::string> topics = params_.input_topics;
  const bool qualify = !topics.empty();
  if (topics.empty()) topics.push_back("tracked_objects");
  sources_.resize(topics.size());
  for (std::size_t i = 0; i < topics.size(); ++i) {
    sources_[i].topic = nh_.resolveName(topics[i]);
    sources_[i].qualifier = qualify ? sources_[i].topic : std::string();
    // Queue of 1: only the newest array of each source is worth predicting from.
    subscribers_.push_back(nh_.subscribe<TrackedBoxArray>(
        topics[i], 1, [this, i](const TrackedBoxArray::ConstPtr& msg) { onBoxes(msg, i); },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay()));
  }

  diagnostics_.setHardwareID("workspace_proximity");
  diagnostics_.add("proximity monitor", this, &ProximityMonitor::diagnose);
  timer_ = nh_.createTimer(ros::Duration(1.0 / params_.rate),
                           [this](const ros::TimerEvent&) { cycle(ros::Time::now()); });
  // Markers are built half a period after the cycle that predicted them, so that their
  // cost (and their megabyte on the wire) never delays the contacts of the next cycle or
  // coincides with this one's delivery. One-shot, re-armed by the cycle when markers are due.
  marker_timer_ = nh_.createTimer(
      ros::Duration(0.5 / params_.rate), [this](const ros::TimerEvent&) { publishMarkers(); },
      true, false);
  ROS_INFO("proximity_monitor: %zu robot bodies, %zu input topics, fixed frame '%s', %.1f Hz, "
           "horizon %.2f s",
           robot_.size(), sources_.size(), params_.fixed_frame.c_str(), params_.rate,
           params_.horizon);
}

ProximityMonitor::~ProximityMonitor() {
  if (cycles_ > 0) {
    std::printf("proximity_monitor: %llu cycles; stage times over the last %zu: %s\n",
                static_cast<unsigned long long>(cycles_),
                std::min<std::size_t>(cycles_, CycleTiming::kWindow), timing_.summary().c_str());
    std::fflush(stdout);
  }
}

void ProximityMonitor::loadRobot() {
  std::vector<RobotBodySpec> specs = params_.robot_bodies;
  if (params_.use_robot_description) {
    std::string urdf;
    if (nh_.getParam(params_.robot_description_param, urdf)) {
      const UrdfBodies from_urdf = bodiesFromUrdf(urdf);
      for (const UnmodelledElement& e : from_urdf.unmodelled) {
        ROS_WARN("proximity_monitor: URDF link '%s': %s; skipped", e.link.c_str(), e.reason.c_str());
      }
      specs.insert(specs.end(), from_urdf.bodies.begin(), from_urdf.bodies.end());
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

void ProximityMonitor::onBoxes(const TrackedBoxArray::ConstPtr& msg, std::size_t index) {
  Source& source = sources_[index];
  const ros::Time now = ros::Time::now();
  if (!source.last_receipt.isZero() && now > source.last_receipt) {
    // Smooth the interval, not its inverse: the mean of 1 / interval overstates the rate
    // (arrays arriving in pairs 5 ms apart at 20 per second read as 100 Hz).
    const double interval = (now - source.last_receipt).toSec();
    source.rate = source.rate == 0.0 ? 1.0 / interval
                                     : 1.0 / (0.9 / source.rate + 0.1 * interval);
  }
  source.last_receipt = now;
  ++source.arrays;
  if (source.pending) rejected_["superseded"] += 1;  // flood: the older array is skipped
  source.pending = msg;

  // Work ahead: turn the array into tracks now, while the cycle waits, so the cycle itself
  // only extrapolates, predicts and publishes. At most one array per source between cycles
  // (a flood supersedes the rest into `pending`, which the cycle takes), and never after
  // the clock went back (the cycle resets the history first).
  if (source.taken_since_cycle || (!last_cycle_.isZero() && now < last_cycle_)) return;
  const auto start = std::chrono::steady_clock::now();
  try {
    if (!processArray(source, *msg, now, true)) return;  // deferred to the cycle
  } catch (const std::exception& e) {
    // Never out of a callback; the cycle reports failures of its own.
    ROS_ERROR_THROTTLE(1.0, "proximity_monitor: array on %s failed: %s", source.topic.c_str(),
                       e.what());
    rejected_["array failure"] += 1;
  }
  source.pending.reset();
  source.taken_since_cycle = true;
  timing_.add(CycleStage::kArrival, std::chrono::duration<double, std::milli>(
                                        std::chrono::steady_clock::now() - start)
                                        .count());
}

void ProximityMonitor::reject(const std::string& source, const std::string& id,
                              const std::string& why) {
  rejected_[category(why)] += 1;
  ROS_WARN_THROTTLE(2.0, "proximity_monitor: %s: track '%s' rejected: %s", source.c_str(),
                    id.c_str(), why.c_str());
}

bool ProximityMonitor::processArray(Source& source, const TrackedBoxArray& msg,
                                    const ros::Time& now, bool on_arrival) {
  const std::string& name = source.topic;
  if (msg.header.frame_id.empty()) {
    rejected_["frame"] += 1;
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: array on %s has an empty frame_id; dropped",
                      name.c_str());
    return true;
  }
  ros::Time stamp = msg.header.stamp;
  if (stamp.isZero()) {
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: array on %s has stamp 0; using the receive time",
                      name.c_str());
    stamp = source.last_receipt;
  }
  if ((stamp - now).toSec() > params_.max_future) {
    rejected_["future"] += 1;
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: array on %s is stamped %.3f s in the future "
                           "(clocks out of sync?); dropped",
                      name.c_str(), (stamp - now).toSec());
    return true;
  }
  if ((now - stamp).toSec() > params_.track_timeout) {
    rejected_["old"] += 1;
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: array on %s is %.3f s old (> ~track_timeout); "
                           "dropped",
                      name.c_str(), (now - stamp).toSec());
    return true;
  }
  if (!source.last_stamp.isZero() && stamp < source.last_stamp) {
    rejected_["out-of-order"] += 1;
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: array on %s is older than the previous one; "
                           "dropped",
                      name.c_str());
    return true;
  }
  Eigen::Isometry3d fixed_from_frame;
  try {
    fixed_from_frame = tf2::transformToEigen(
        tf_buffer_.lookupTransform(params_.fixed_frame, msg.header.frame_id, stamp));
  } catch (const tf2::TransformException& at_stamp) {
    // On arrival tf may simply not have caught up yet: leave the array for the cycle.
    if (on_arrival) return false;
    // The newest transform is the best we have when tf lags the tracker; a frame tf cannot
    // reach at all drops the array.
    try {
      fixed_from_frame = tf2::transformToEigen(
          tf_buffer_.lookupTransform(params_.fixed_frame, msg.header.frame_id, ros::Time(0)));
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: %s: no transform at the array's stamp (%s); "
                             "using the latest",
                        name.c_str(), at_stamp.what());
    } catch (const tf2::TransformException& e) {
      ++tf_failures_;
      rejected_["frame"] += 1;
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: %s: cannot transform '%s' to '%s': %s; dropped",
                        name.c_str(), msg.header.frame_id.c_str(), params_.fixed_frame.c_str(),
                        e.what());
      return true;
    }
  }
  source.last_stamp = stamp;

  // Too many boxes: keep the ones nearest the robot (they matter first) and say so.
  nearest_.clear();
  const Eigen::Vector3d centre = robotCentre();
  for (std::size_t i = 0; i < msg.boxes.size(); ++i) {
    const auto& p = msg.boxes[i].pose.position;
    const double d = (fixed_from_frame * Eigen::Vector3d(p.x, p.y, p.z) - centre).squaredNorm();
    nearest_.emplace_back(std::isfinite(d) ? d : HUGE_VAL, i);
  }
  const std::size_t room = static_cast<std::size_t>(params_.max_tracks);
  if (nearest_.size() > room) {
    std::nth_element(nearest_.begin(), nearest_.begin() + static_cast<long>(room), nearest_.end());
    rejected_["cap"] += nearest_.size() - room;
    ROS_WARN_THROTTLE(5.0, "proximity_monitor: %s: %zu boxes exceed ~max_tracks = %d; the "
                           "%zu farthest from the robot are ignored",
                      name.c_str(), nearest_.size(), params_.max_tracks, nearest_.size() - room);
    nearest_.resize(room);
  }

  // Every track updated from this array is marked with its serial: a second box with the
  // same id finds the mark (duplicate) without a per-array set of ids.
  ++array_serial_;
  for (const auto& entry : nearest_) {
    const TrackedBox& box = msg.boxes[entry.second];
    const std::string why = checkTrackedBox(box);
    if (!why.empty()) {
      reject(name, box.id, why);
      continue;
    }
    // The single default topic uses ids as they are (no copy); several topics qualify them.
    const std::string& key =
        source.qualifier.empty() ? box.id : (scratch_key_ = source.qualifier + "/" + box.id);
    const auto found = track_index_.find(key);
    const std::int32_t index = found == track_index_.end() ? -1 : found->second;
    if (index >= 0 && tracks_[static_cast<std::size_t>(index)].array_serial == array_serial_) {
      reject(name, box.id, "duplicate id in one array; the first is used");
      continue;
    }
    if (index < 0 && static_cast<int>(tracks_.size()) >= params_.max_tracks &&
        !evictFarther(entry.first, centre)) {
      reject(name, box.id, "cap: ~max_tracks reached and every kept track is nearer the robot");
      continue;
    }
    try {
      updateTrack(key, index, box, toMotion(box, fixed_from_frame), stamp);
    } catch (const std::exception& e) {
      // The core's own limits (e.g. a pose that the frame's transform carries past them):
      // drop the box, never the array or the node.
      reject(name, box.id, std::string("rejected by the core: ") + e.what());
    }
  }
  return true;
}

bool ProximityMonitor::evictFarther(double squared_distance, const Eigen::Vector3d& centre) {
  // At the cap, the track farthest from the robot (at its last observed position) gives way
  // to a nearer newcomer, whichever source it came from.
  std::int32_t farthest = -1;
  double worst = squared_distance;
  for (std::size_t i = 0; i < tracks_.size(); ++i) {
    const double d = (tracks_[i].motion.position - centre).squaredNorm();
    if (d > worst) {
      worst = d;
      farthest = static_cast<std::int32_t>(i);
    }
  }
  if (farthest < 0) return false;
  rejected_["cap"] += 1;
  ROS_WARN_THROTTLE(5.0, "proximity_monitor: ~max_tracks = %d reached; dropping track '%s', the "
                         "farthest from the robot, for a nearer one",
                    params_.max_tracks, tracks_[static_cast<std::size_t>(farthest)].key.c_str());
  removeTrack(farthest);
  return true;
}

void ProximityMonitor::removeTrack(std::int32_t index) {
  // Swap-and-pop keeps the tracks dense; the moved track's index entries follow it.
  const auto i = static_cast<std::size_t>(index);
  setTrackOf(tracks_[i].handle, -1);
  world_.removeBody(tracks_[i].handle);
  track_index_.erase(tracks_[i].key);
  if (i + 1 != tracks_.size()) {
    tracks_[i] = std::move(tracks_.back());
    track_index_[tracks_[i].key] = index;
    setTrackOf(tracks_[i].handle, index);
  }
  tracks_.pop_back();
}

void ProximityMonitor::updateTrack(const std::string& key, std::int32_t index,
                                   const TrackedBox& box, const BodyMotion& motion,
                                   const ros::Time& stamp) {
  const Shape shape = toShape(box);
  if (index >= 0 && tracks_[static_cast<std::size_t>(index)].label != box.label) {
    ROS_WARN_THROTTLE(2.0, "proximity_monitor: track '%s' changed label '%s' -> '%s'; "
                           "restarting it",
                      key.c_str(), tracks_[static_cast<std::size_t>(index)].label.c_str(),
                      box.label.c_str());
    rejected_["relabelled"] += 1;
    removeTrack(index);
    index = -1;
  }
  if (index < 0) {
    Track t;
    t.key = key;
    t.label = box.label;
    t.stamp = stamp;
    t.motion = motion;
    t.half = shape.half_extents;
    t.array_serial = array_serial_;
    t.handle = world_.addBody(
        BodyDesc{key, box.label, BodyGroup::kObject, shape, params_.label(box.label).margin},
        motion);
    const auto added = static_cast<std::int32_t>(tracks_.size());
    tracks_.push_back(std::move(t));
    track_index_.emplace(key, added);
    setTrackOf(tracks_.back().handle, added);
    bodyInfo(tracks_.back().handle.index).settings = &params_.label(box.label);
    return;
  }
  Track& t = tracks_[static_cast<std::size_t>(index)];
  t.array_serial = array_serial_;
  if (stamp < t.stamp) return;  // older than what we have
  t.stamp = stamp;
  t.motion = motion;
  if (needsResize(t.half, shape.half_extents)) {
    t.half = shape.half_extents;
    world_.setShape(t.handle, shape, params_.label(box.label).margin);
  }
}

void ProximityMonitor::expireTracks(const ros::Time& now) {
  // Backwards: removeTrack moves the last track into the hole, which was visited already.
  for (std::size_t i = tracks_.size(); i-- > 0;) {
    if (secondsBetween(tracks_[i].stamp, now) > params_.track_timeout) {
      removeTrack(static_cast<std::int32_t>(i));
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
  if (-age > params_.max_future) {
    // Stamped ahead of the clock: left over from before the clock jumped back (a publisher
    // that saw the jump after our reset). tf2 refuses data older than its newest entry by
    // more than the cache time, so the fresh transforms would never be used: drop it all.
    tf_buffer_.clear();
    *why = format("latest transform is stamped %.3f s ahead of the clock; tf history cleared",
                  -age);
    return false;
  }
  if (age > params_.tf_timeout) {
    *why = format("latest transform is %.3f s old", age);
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
      // Unknown, not absent: a link last seen stays where it was (without extrapolating an
      // old velocity) and its pairs are marked stale; the status says DEGRADED.
      ++robot_unknown_;
      ++tf_failures_;
      body.stale = true;
      body.why = why.empty() ? "invalid pose" : why;
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: robot body '%s' (frame '%s') not posed: %s",
                        body.spec.name.c_str(), body.spec.frame.c_str(), body.why.c_str());
      if (body.present) {
        BodyMotion still = world_.motion(body.handle);
        still.linear_velocity.setZero();
        still.angular_velocity.setZero();
        world_.setMotion(body.handle, still);
      }
      continue;
    }
    if (body.stale && body.present) {
      ROS_INFO("proximity_monitor: robot body '%s' is posed again", body.spec.name.c_str());
    }
    body.stale = false;
    body.why.clear();
    try {
      if (!body.present) {
        body.handle = world_.addBody(BodyDesc{body.spec.name, "robot", BodyGroup::kRobot,
                                              body.spec.shape, params_.robot_margin},
                                     motion);
        body.present = true;
        bodyInfo(body.handle.index).robot = &body;
        bodyInfo(body.handle.index).settings = &params_.robot_thresholds;
      } else {
        world_.setMotion(body.handle, motion);
      }
    } catch (const std::exception& e) {
      ++robot_unknown_;
      body.stale = true;
      body.why = std::string("rejected by the core: ") + e.what();
      ROS_WARN_THROTTLE(5.0, "proximity_monitor: robot body '%s': %s", body.spec.name.c_str(),
                        body.why.c_str());
    }
  }
}

Eigen::Vector3d ProximityMonitor::robotCentre() const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (const RobotBody& body : robot_) {
    if (!body.present) continue;
    sum += world_.motion(body.handle).position;
    ++n;
  }
  return n > 0 ? Eigen::Vector3d(sum / n) : Eigen::Vector3d::Zero();
}

void ProximityMonitor::resetHistory(const std::string& why) {
  // A clock that jumps back (bag loop, simulation reset) invalidates every stamp we hold:
  // drop the tracks (their pairs END), the robot's poses and the tf history.
  ROS_WARN("proximity_monitor: %s; resetting tracks, robot poses and the tf buffer", why.c_str());
  ++resets_;
  for (const Track& t : tracks_) world_.removeBody(t.handle);
  tracks_.clear();
  track_index_.clear();
  for (RobotBody& body : robot_) {
    if (body.present) world_.removeBody(body.handle);
    body.present = false;
    body.stale = false;
  }
  by_body_.clear();
  for (Source& s : sources_) {
    s.pending.reset();
    s.last_receipt = ros::Time();
    s.last_stamp = ros::Time();
    s.rate = 0.0;
  }
  tf_buffer_.clear();
  // diagnostic_updater publishes once its next time (set from the old clock) is reached:
  // publish now, which also restarts its period from the new clock.
  diagnostics_.force_update();
}

void ProximityMonitor::cycle(const ros::Time& now) {
  try {
    runCycle(now);
  } catch (const std::exception& e) {
    // Nothing may stop the cycle: report it loudly and keep publishing next time.
    ROS_ERROR_THROTTLE(1.0, "proximity_monitor: cycle failed: %s", e.what());
    rejected_["cycle failure"] += 1;
    // Still publish, and say the prediction is missing: silence must not read as clear.
    contacts_msg_.header.stamp = now;
    contacts_msg_.header.frame_id = params_.fixed_frame;
    contacts_msg_.events.clear();
    contacts_msg_.status = ContactEventArray::DEGRADED;
    contacts_msg_.status_details.assign(1, std::string("cycle failed: ") + e.what());
    contacts_pub_.publish(contacts_msg_);
  }
}

void ProximityMonitor::runCycle(const ros::Time& now) {
  const auto start = std::chrono::steady_clock::now();
  if (!last_cycle_.isZero() && now < last_cycle_) {
    resetHistory(format("clock jumped back by %.3f s", (last_cycle_ - now).toSec()));
  }
  last_cycle_ = now;

  for (Source& source : sources_) {
    source.taken_since_cycle = false;
    if (!source.pending) continue;
    const TrackedBoxArray::ConstPtr msg = source.pending;
    source.pending.reset();
    processArray(source, *msg, now, false);
  }
  expireTracks(now);
  for (const Track& t : tracks_) {
    // Latency compensation: every track is moved from its own stamp to the cycle instant.
    world_.setMotion(t.handle, t.motion.advanced(secondsBetween(t.stamp, now)));
  }
  updateRobot(now);
  auto mark = start;
  auto lap = [&](CycleStage stage) {
    const auto t = std::chrono::steady_clock::now();
    timing_.add(stage, std::chrono::duration<double, std::milli>(t - mark).count());
    mark = t;
  };
  lap(CycleStage::kInput);
  const std::vector<PairEvent>& events = world_.predict(params_.horizon);
  lap(CycleStage::kPredict);
  collectStatus(now);
  publishContacts(now, events);
  lap(CycleStage::kContacts);
  scheduleMarkers(now);
  ++cycles_;
  last_cycle_ms_ =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  max_cycle_ms_ = std::max(max_cycle_ms_, last_cycle_ms_);
  diagnostics_.update();
}

void ProximityMonitor::collectStatus(const ros::Time& now) {
  contacts_msg_.status_details.clear();
  // A source is silent after ~source_timeout, and never later than ~track_timeout: by then
  // its tracks are gone, and an empty scene from a silent source must not read as clear.
  const double silent_after = std::min(params_.source_timeout, params_.track_timeout);
  for (const Source& s : sources_) {
    if (s.last_receipt.isZero()) {
      contacts_msg_.status_details.push_back("source " + s.topic + ": no data yet");
    } else if (secondsBetween(s.last_receipt, now) > silent_after) {
      contacts_msg_.status_details.push_back(
          "source " + s.topic + format(": no data for %.2f s", (now - s.last_receipt).toSec()));
    }
  }
  for (const RobotBody& body : robot_) {
    if (body.stale || !body.present) {
      contacts_msg_.status_details.push_back(
          "robot body " + body.spec.name + (body.present ? " stale: " : " unknown: ") + body.why);
    }
  }
  contacts_msg_.status = contacts_msg_.status_details.empty() ? ContactEventArray::OK
                                                              : ContactEventArray::DEGRADED;
}

ProximityMonitor::BodyInfo& ProximityMonitor::bodyInfo(std::int32_t index) {
  const auto i = static_cast<std::size_t>(index);
  if (i >= by_body_.size()) by_body_.resize(i + 1);  // grows with the world's slots only
  return by_body_[i];
}

const LabelSettings& ProximityMonitor::settingsOf(BodyHandle body, const BodyDesc& desc) const {
  // Cached when the body was added: no string-keyed look-up per event and cycle.
  const auto i = static_cast<std::size_t>(body.index);
  if (i < by_body_.size() && by_body_[i].settings != nullptr) return *by_body_[i].settings;
  return desc.group == BodyGroup::kRobot ? params_.robot_thresholds : params_.label(desc.label);
}

void ProximityMonitor::setTrackOf(BodyHandle body, std::int32_t track) {
  bodyInfo(body.index).track = track;
}

bool ProximityMonitor::bodyStale(const BodyHandle& body, const ros::Time& now) const {
  const auto i = static_cast<std::size_t>(body.index);
  if (i >= by_body_.size()) return false;
  const BodyInfo& info = by_body_[i];
  if (info.track >= 0) {
    return secondsBetween(tracks_[static_cast<std::size_t>(info.track)].stamp, now) >
           params_.stale_after;
  }
  return info.robot != nullptr && info.robot->stale;
}

void ProximityMonitor::publishContacts(const ros::Time& now,
                                       const std::vector<PairEvent>& events) {
  contacts_msg_.header.stamp = now;
  contacts_msg_.header.frame_id = params_.fixed_frame;
  // Resized, not cleared: kept elements keep their strings' capacity, so steady cycles
  // rewrite the message in place.
  contacts_msg_.events.resize(events.size());
  event_slots_.resize(events.size());
  ++publish_serial_;
  for (std::size_t i = 0; i < events.size(); ++i) {
    const PairEvent& e = events[i];
    ContactEvent& msg = contacts_msg_.events[i];
    event_slots_[i] = {e.body_a.index, e.body_b.index};
    const BodyDesc& a = world_.desc(e.body_a);
    const BodyDesc& b = world_.desc(e.body_b);
    const LabelSettings& la = settingsOf(e.body_a, a);
    const LabelSettings& lb = settingsOf(e.body_b, b);
    const std::uint8_t level = contactLevel(e, la, lb);
    toMsg(e, a, b, level, &msg);
    if (e.state == ContactState::kEnd) continue;
    msg.stale = bodyStale(e.body_a, now) || bodyStale(e.body_b, now);
    for (const BodyHandle& h : {e.body_a, e.body_b}) {
      BodyInfo& info = bodyInfo(h.index);
      if (info.level_serial != publish_serial_ || info.level < level) info.level = level;
      info.level_serial = publish_serial_;
    }
  }
  contacts_pub_.publish(contacts_msg_);
}

void ProximityMonitor::scheduleMarkers(const ros::Time& now) {
  // Nobody watching (no RViz): building thousands of markers would be wasted work.
  if (!params_.publish_markers || markers_pub_.getNumSubscribers() == 0) return;
  // At most ~marker_rate: due when a marker period has passed, less half a cycle so that
  // 10 Hz on 30 Hz cycles is every third cycle; a clock that went back publishes at once.
  if (!last_markers_.isZero() && now >= last_markers_ &&
      secondsBetween(last_markers_, now) < 1.0 / params_.marker_rate - 0.5 / params_.rate) {
    return;
  }
  last_markers_ = now;
  marker_timer_.stop();
  marker_timer_.setPeriod(ros::Duration(0.5 / params_.rate));  // re-arms the one-shot
  marker_timer_.start();
}

void ProximityMonitor::publishMarkers() {
  const auto start = std::chrono::steady_clock::now();
  const ros::Time now = last_markers_;  // the prediction instant they show
  try {
    buildMarkers(now);
  } catch (const std::exception& e) {
    ROS_ERROR_THROTTLE(1.0, "proximity_monitor: markers failed: %s", e.what());
    return;
  }
  timing_.add(CycleStage::kMarkers,
              std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                  .count());
}

void ProximityMonitor::buildMarkers(const ros::Time& now) {
  marker_bodies_.clear();
  auto addMarkerBody = [&](BodyHandle h, bool robot) {
    MarkerBody m;
    const BodyDesc& d = world_.desc(h);
    const BodyMotion& motion = world_.motion(h);
    m.slot = h.index;
    m.robot = robot;
    m.shape = d.shape;
    m.pose = motion.poseAt(0.0);
    m.velocity = motion.linear_velocity;
    m.swept = world_.sweptBounds(h);
    const BodyInfo& info = bodyInfo(h.index);
    m.level = info.level_serial == publish_serial_ ? info.level : -1;
    marker_bodies_.push_back(m);
  };
  for (const Track& t : tracks_) addMarkerBody(t.handle, false);
  for (const RobotBody& body : robot_) {
    if (body.present) addMarkerBody(body.handle, true);
  }
  markers_.build(marker_bodies_, contacts_msg_, event_slots_, now, &markers_msg_);
  markers_pub_.publish(markers_msg_);
}

void ProximityMonitor::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const WorldStats& s = world_.stats();
  const double period_ms = 1000.0 / params_.rate;
  if (last_cycle_ms_ > period_ms) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR,
                    "cycle takes %.1f ms, longer than the %.1f ms period", last_cycle_ms_,
                    period_ms);
  } else if (contacts_msg_.status != ContactEventArray::OK) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN,
                   "degraded: " + contacts_msg_.status_details.front());
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "predicting");
  }
  status.add("cycles", cycles_);
  status.add("cycle time (ms)", last_cycle_ms_);
  status.add("max cycle time (ms)", max_cycle_ms_);
  for (int i = 0; i < CycleTiming::kStages; ++i) {
    const auto stage = static_cast<CycleStage>(i);
    status.addf(std::string("stage ") + CycleTiming::name(stage) + " (ms, last/p99)", "%.3f/%.3f",
                timing_.last(stage), timing_.percentile(stage, 0.99));
  }
  status.add("tracks", tracks_.size());
  status.add("robot bodies", robot_.size());
  status.add("robot bodies not posed", robot_unknown_);
  status.add("tf failures", tf_failures_);
  status.add("broad-phase pairs", s.broad_pairs);
  status.add("predicted contacts", s.contacts);
  status.add("history resets (clock jumps)", resets_);
  const ros::Time now = ros::Time::now();
  for (const Source& src : sources_) {
    status.add("source " + src.topic + " rate (Hz)", src.rate);
    status.add("source " + src.topic + " age (s)",
               src.last_receipt.isZero() ? -1.0 : (now - src.last_receipt).toSec());
  }
  for (const auto& kv : rejected_) status.add("dropped: " + kv.first, kv.second);
  for (const std::string& d : contacts_msg_.status_details) status.add("degraded", d);
}

}  // namespace workspace_proximity
