#include "workspace_proximity/ros/cloud_tracker.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <stdexcept>

#include <boost/make_shared.hpp>
#include <tf2_eigen/tf2_eigen.h>

#include "workspace_proximity/perception/laser_scan.hpp"
#include "workspace_proximity/ros/conversions.hpp"
#include "workspace_proximity/ros/monitor_bridges.hpp"
#include "workspace_proximity/ros/robot_description.hpp"
#include "workspace_proximity/ros/ros_params.hpp"

namespace workspace_proximity {

namespace pc = perception;

namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
  throw std::runtime_error("~" + name + ": " + what);
}

double number(const XmlRpc::XmlRpcValue& v, const std::string& name) {
  if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble) return static_cast<double>(const_cast<XmlRpc::XmlRpcValue&>(v));
  if (v.getType() == XmlRpc::XmlRpcValue::TypeInt) return static_cast<int>(const_cast<XmlRpc::XmlRpcValue&>(v));
  fail(name, "must be a number");
}

// ~name as a number (default when absent), finite and within [lo, hi].
double readNumber(const ros::NodeHandle& pnh, const std::string& name, double def, double lo, double hi) {
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam(name, v)) return def;
  const double x = number(v, name);
  if (!std::isfinite(x) || x < lo || x > hi) {
    fail(name, "must be within [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  }
  return x;
}

std::vector<double> readNumbers(const ros::NodeHandle& pnh, const std::string& name, std::size_t n) {
  XmlRpc::XmlRpcValue v;
  if (!pnh.getParam(name, v)) return {};
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray || static_cast<std::size_t>(v.size()) != n) {
    fail(name, "must be a list of " + std::to_string(n) + " numbers");
  }
  std::vector<double> out;
  for (int i = 0; i < v.size(); ++i) {
    out.push_back(number(v[i], name));
    if (!std::isfinite(out.back())) fail(name, "must be finite");
  }
  return out;
}

std::vector<std::string> readTopics(const ros::NodeHandle& pnh, const std::string& name) {
  XmlRpc::XmlRpcValue v;
  std::vector<std::string> out;
  if (!pnh.getParam(name, v)) return out;
  if (v.getType() != XmlRpc::XmlRpcValue::TypeArray) fail(name, "must be a list of topics");
  for (int i = 0; i < v.size(); ++i) {
    if (v[i].getType() != XmlRpc::XmlRpcValue::TypeString) fail(name, "must be a list of topics");
    out.push_back(static_cast<std::string>(v[i]));
    if (out.back().empty()) fail(name, "an empty topic name");
  }
  return out;
}

}  // namespace

CloudTrackerParams readCloudTrackerParams(const ros::NodeHandle& pnh) {
  CloudTrackerParams p;
  pnh.param<std::string>("fixed_frame", p.fixed_frame, p.fixed_frame);
  if (p.fixed_frame.empty()) fail("fixed_frame", "must not be empty");
  // tf2 refuses frame ids with a leading '/' in every lookup.
  if (p.fixed_frame[0] == '/') fail("fixed_frame", "must not start with '/' (tf2 refuses it)");
  p.cloud_topics = readTopics(pnh, "cloud_topics");
  p.scan_topics = readTopics(pnh, "scan_topics");
  if (p.cloud_topics.empty() && p.scan_topics.empty()) {
    fail("cloud_topics", "no ~cloud_topics and no ~scan_topics: nothing to see with");
  }
  p.source_timeout = readNumber(pnh, "source_timeout", p.source_timeout, 0.01, 60.0);
  p.tf_wait = readNumber(pnh, "tf_wait", p.tf_wait, 0.0, 1.0);
  p.self_max_speed = readNumber(pnh, "self_max_speed", p.self_max_speed, 0.0, 100.0);
  p.self_max_gap = readNumber(pnh, "self_max_gap", p.self_max_gap, 0.0, 10.0);
  pc::CloudFrameParams& f = p.frame;
  f.voxel_size = readNumber(pnh, "voxel_size", f.voxel_size, 0.005, 1.0);
  f.floor_height = readNumber(pnh, "floor_height", f.floor_height, -1e3, 1e3);
  f.floor_tolerance = readNumber(pnh, "floor_tolerance", f.floor_tolerance, 0.0, 1.0);
  f.self_padding = readNumber(pnh, "self_padding", f.self_padding, 0.0, 1.0);
  f.min_cluster_points = static_cast<int>(readNumber(pnh, "min_cluster_points", f.min_cluster_points, 1, 1e6));
  f.max_points = static_cast<std::int64_t>(readNumber(pnh, "max_points", static_cast<double>(f.max_points), 1, 1e8));
  const std::vector<double> volume = readNumbers(pnh, "volume", 6);
  if (!volume.empty()) {
    f.volume = Aabb{Eigen::Vector3d(volume[0], volume[1], volume[2]),
                    Eigen::Vector3d(volume[3], volume[4], volume[5])};
  } else {
    std::vector<double> base = readNumbers(pnh, "robot_base", 3);
    if (base.empty()) base = {0.0, 0.0, 0.0};
    const double reach = readNumber(pnh, "robot_reach", 1.0, 0.0, 100.0);
    const double ssm_reach = readNumber(pnh, "ssm_reach", 1.5, 0.0, 100.0);
    f.volume = pc::defaultMonitoredVolume(Eigen::Vector3d(base[0], base[1], base[2]), reach,
                                          ssm_reach, f.floor_height);
  }
  const std::string why = pc::checkCloudFrameParams(f);
  if (!why.empty()) fail("volume", why);
  const std::vector<double> band = readNumbers(pnh, "scan_band", 2);
  if (!band.empty()) {
    if (band[1] < band[0] || band[1] - band[0] > 10.0) fail("scan_band", "must be [z_min, z_max] with z_min <= z_max, at most 10 m apart");
    p.scan_band.z_min = static_cast<float>(band[0]);
    p.scan_band.z_max = static_cast<float>(band[1]);
  } else {
    p.scan_band.z_min = -0.1f;
    p.scan_band.z_max = 1.8f;
  }
  p.scan_band.z_step = static_cast<float>(0.5 * f.voxel_size);
  // The robot's bodies, read as the monitor reads them.
  XmlRpc::XmlRpcValue robot;
  robot["use_robot_description"] = true;
  for (const char* key : {"robot_bodies", "use_robot_description", "robot_description_param",
                          "use_joint_states", "trajectory_topic", "tf_timeout",
                          "trajectory_tolerance", "joint_path_tolerance"}) {
    XmlRpc::XmlRpcValue v;
    if (pnh.getParam(key, v)) robot[key] = v;
  }
  p.robot = readParams(robot);
  // Checked as the monitor checks them (the rest of MonitorParams keeps its valid defaults).
  const std::vector<std::string> robot_errors = validate(p.robot);
  if (!robot_errors.empty()) throw std::runtime_error(robot_errors.front());
  p.ssm_reach = readNumber(pnh, "ssm_reach", p.ssm_reach, 0.0, 100.0);
  p.unseen_limit = readNumber(pnh, "unseen_limit", p.unseen_limit, 0.0, 1.0);
  p.unseen_rate = readNumber(pnh, "unseen_rate", p.unseen_rate, 0.1, 100.0);
  p.status_rate = readNumber(pnh, "status_rate", p.status_rate, 0.1, 1000.0);
  const std::string unseen = pnh.param<std::string>("unseen", "ignore");
  if (unseen != "ignore" && unseen != "occupied") fail("unseen", "must be 'ignore' or 'occupied'");
  p.unseen_occupied = unseen == "occupied";
  p.unseen_max_boxes = static_cast<int>(readNumber(pnh, "unseen_max_boxes", p.unseen_max_boxes, 1, 10000));
  XmlRpc::XmlRpcValue views;
  if (pnh.getParam("sensor_fov", views)) {
    if (views.getType() != XmlRpc::XmlRpcValue::TypeStruct) fail("sensor_fov", "must map topics to views");
    // The parameter server splits keys at '/': a topic "cam/points" arrives as {cam: {points:
    // view}}. A struct with "azimuth" is a view; any other is a level of its topic's name.
    // (A key with a leading '/' is put outside the node's namespace by rosparam: write the
    // topic without it; "cam/points" is matched against "/cam/points" too.)
    std::function<void(const XmlRpc::XmlRpcValue&, const std::string&)> collect;
    collect = [&](const XmlRpc::XmlRpcValue& level, const std::string& path) {
      for (auto it = const_cast<XmlRpc::XmlRpcValue&>(level).begin();
           it != const_cast<XmlRpc::XmlRpcValue&>(level).end(); ++it) {
        const std::string name = path.empty() ? it->first : path + "/" + it->first;
        const std::string where = "sensor_fov/" + name;
        const XmlRpc::XmlRpcValue& v = it->second;
        if (v.getType() != XmlRpc::XmlRpcValue::TypeStruct) fail(where, "must be {azimuth, elevation, range, optical}");
        if (!v.hasMember("azimuth") && !v.hasMember("elevation") && !v.hasMember("range")) {
          collect(v, name);
          continue;
        }
        CloudTrackerParams::View view;
        auto pair = [&](const char* key, double* lo, double* hi) {
          if (!v.hasMember(key)) fail(where, std::string("needs ") + key + ": [min, max]");
          const XmlRpc::XmlRpcValue& x = const_cast<XmlRpc::XmlRpcValue&>(v)[key];
          if (x.getType() != XmlRpc::XmlRpcValue::TypeArray || x.size() != 2) fail(where + "/" + key, "must be [min, max]");
          *lo = number(x[0], where + "/" + key);
          *hi = number(x[1], where + "/" + key);
          if (!std::isfinite(*lo) || !std::isfinite(*hi) || *lo > *hi) fail(where + "/" + key, "must be finite, min <= max");
        };
        pair("azimuth", &view.fov.azimuth_min, &view.fov.azimuth_max);
        pair("elevation", &view.fov.elevation_min, &view.fov.elevation_max);
        pair("range", &view.fov.range_min, &view.fov.range_max);
        if (v.hasMember("optical")) {
          const XmlRpc::XmlRpcValue& o = const_cast<XmlRpc::XmlRpcValue&>(v)["optical"];
          if (o.getType() != XmlRpc::XmlRpcValue::TypeBoolean) fail(where + "/optical", "must be true or false");
          view.optical = static_cast<bool>(const_cast<XmlRpc::XmlRpcValue&>(o));
        }
        std::string topic;
        for (const std::vector<std::string>* list : {&p.cloud_topics, &p.scan_topics}) {
          for (const std::string& t : *list) {
            if (t == name || t == "/" + name) topic = t;
          }
        }
        if (topic.empty()) fail(where, "not one of ~cloud_topics or ~scan_topics");
        p.views[topic] = view;
      }
    };
    collect(views, "");
  }
  pc::ClusterTrackParams& t = p.tracks;
  t.max_speed = readNumber(pnh, "track_max_speed", t.max_speed, 0.01, 100.0);
  t.max_accel = readNumber(pnh, "track_max_accel", t.max_accel, 0.0, 1000.0);
  t.sigma = readNumber(pnh, "cluster_sigma", f.voxel_size, 0.001, 1.0);
  t.max_merge_gap = readNumber(pnh, "max_merge_gap", t.max_merge_gap, 0.0, 5.0);
  t.fragment_gap = readNumber(pnh, "fragment_gap", t.fragment_gap, 0.0, 10.0);
  const std::vector<std::string> track_errors = pc::validate(t);
  if (!track_errors.empty()) fail("track_max_speed", track_errors.front());
  return p;
}

CloudTracker::CloudTracker(const ros::NodeHandle& nh, const ros::NodeHandle& pnh,
                           const CloudTrackerParams& params)
    : nh_(nh), pnh_(pnh), params_(params), tf_listener_(tf_buffer_), diagnostics_(nh_, pnh_) {
  const RobotDescription robot = loadRobotBodies(nh_, params_.robot);
  for (const std::string& line : robot.unmodelled) ROS_WARN("cloud_tracker: %s (not self-filtered)", line.c_str());
  robot_ = robot.bodies;
  links_.resize(robot_.size());
  params_.frame.max_links = static_cast<int>(robot_.size());
  enableJoints();

  std::vector<std::string> names = params_.cloud_topics;
  names.insert(names.end(), params_.scan_topics.begin(), params_.scan_topics.end());
  for (std::size_t i = 0; i < names.size(); ++i) {
    frames_.push_back(std::make_unique<pc::CloudFrame>(params_.frame));
  }
  health_ = std::make_unique<pc::SensorHealth>(names, params_.source_timeout, nowNs());
  const pc::VoxelGrid& geometry = frames_.front()->grid();
  unseen_.configure(geometry);
  unseen_links_.resize(robot_.size());
  posed_links_.resize(robot_.size());
  unseen_out_.made_ns = nowNs();
  if (params_.unseen_occupied) {
    unseen_boxes_ = std::make_unique<pc::UnseenBoxes>(params_.unseen_max_boxes);
    unseen_boxes_->configure(geometry);
    for (int k = 0; k < params_.unseen_max_boxes; ++k) unseen_ids_.push_back("unseen_" + std::to_string(k + 1));
    // Both copies of the boxes sized once: copying a result in or out allocates nothing.
    unseen_out_.boxes.reserve(static_cast<std::size_t>(params_.unseen_max_boxes));
    track_unseen_boxes_.reserve(static_cast<std::size_t>(params_.unseen_max_boxes));
  }
  sights_.resize(names.size());
  sensor_pose_.assign(names.size(), Eigen::Isometry3d::Identity());
  for (const std::string& n : names) {
    const auto it = params_.views.find(n);
    view_.push_back(it == params_.views.end() ? nullptr : &it->second);
    // Only a sensor with a view takes part in the unseen share; its buffer is two grids.
    sight_buffers_.emplace_back();
    if (view_.back() != nullptr) {
      sight_buffers_.back() = std::make_unique<pc::SightBuffer>();
      std::string why;
      if (!sight_buffers_.back()->configure(geometry, &why)) throw std::runtime_error(why);
    }
  }
  markers_ = pnh_.advertise<visualization_msgs::MarkerArray>("clusters", 2);
  // A track is gone when it missed one frame of every sensor in a row (a round of frames):
  // a person who leaves is free within one frame per sensor, and a person only one sensor
  // sees is not deleted at each of the others' frames.
  params_.tracks.tracker.max_misses = static_cast<int>(names.size());
  // Each sensor's latest sight of a track goes into its box (cluster_tracks.hpp).
  params_.tracks.sensors = static_cast<int>(names.size());
  tracks_ = std::make_unique<pc::ClusterTracks>(params_.tracks);
  objects_ = nh_.advertise<TrackedBoxArray>("perceived_objects", 2);
  status_ = nh_.advertise<PerceptionStatus>("perception_status", 2);
  diagnostics_.setHardwareID("workspace_proximity");
  diagnostics_.add("cloud_tracker", this, &CloudTracker::diagnose);

  // Callbacks last: in a nodelet manager they may run as soon as they exist, so everything
  // they touch is built first.
  const int clouds = static_cast<int>(params_.cloud_topics.size());
  for (int i = 0; i < clouds; ++i) {
    subs_.push_back(nh_.subscribe<sensor_msgs::PointCloud2>(
        params_.cloud_topics[static_cast<std::size_t>(i)], 2,
        [this, i](const sensor_msgs::PointCloud2ConstPtr& m) { onCloud(i, m); }));
  }
  for (std::size_t j = 0; j < params_.scan_topics.size(); ++j) {
    const int s = clouds + static_cast<int>(j);
    subs_.push_back(nh_.subscribe<sensor_msgs::LaserScan>(
        params_.scan_topics[j], 2, [this, s](const sensor_msgs::LaserScanConstPtr& m) { onScan(s, m); }));
  }
  diag_timer_ = nh_.createTimer(ros::Duration(0.5), [this](const ros::TimerEvent&) { diagnostics_.update(); });
  status_timer_ = nh_.createTimer(ros::Duration(1.0 / params_.status_rate),
                                  [this](const ros::TimerEvent&) { publishStatus(); });
  // The unseen share on its own thread: its timer's callbacks go to its own queue, so a frame
  // never waits for the share's work (several ms) and the share never for a frame's.
  ros::NodeHandle unseen_nh(nh_);
  unseen_nh.setCallbackQueue(&unseen_queue_);
  unseen_timer_ = unseen_nh.createTimer(ros::Duration(1.0 / params_.unseen_rate),
                                        [this](const ros::TimerEvent&) { updateUnseen(); });
  unseen_thread_ = std::thread([this] {
    while (!unseen_stop_.load() && nh_.ok()) unseen_queue_.callAvailable(ros::WallDuration(0.05));
  });
}

CloudTracker::~CloudTracker() {
  // No new share, then the one running (if any) finishes and the thread ends, before any
  // member it reads is destroyed (node shutdown and nodelet unload alike).
  unseen_timer_.stop();
  {
    const std::lock_guard<std::mutex> lock(handed_mutex_);
    unseen_stop_ = true;
  }
  handed_cv_.notify_one();
  if (unseen_thread_.joinable()) unseen_thread_.join();
  unseen_queue_.disable();
  unseen_queue_.clear();
}

void CloudTracker::updateUnseen() {
  {
    // Start right after the next frame is handed over (at most half a period from now): a
    // camera's frames come at regular intervals, so the share's work then falls in the gap
    // before the following frame instead of competing with it for a core (and it uses that
    // newest frame).
    std::unique_lock<std::mutex> lock(handed_mutex_);
    const std::uint64_t seen = handed_;
    handed_cv_.wait_for(lock, std::chrono::duration<double>(0.5 / params_.unseen_rate),
                        [&] { return handed_ != seen || unseen_stop_.load(); });
  }
  if (unseen_stop_.load()) return;
  // The robot now, into this thread's own links: as the newest frame's self-filter posed it
  // (from the joints where they move it) while that is within the source timeout, else its
  // newest tf poses (tf is thread-safe); without either the protective volume is unknown.
  unseen_why_.clear();
  bool from_frame = false;
  {
    const std::lock_guard<std::mutex> lock(posed_mutex_);
    if (posed_ns_ >= 0 && nowNs() - posed_ns_ <= static_cast<std::int64_t>(params_.source_timeout * 1e9)) {
      std::copy(posed_links_.begin(), posed_links_.end(), unseen_links_.begin());
      from_frame = true;
    }
  }
  for (std::size_t i = 0; i < robot_.size() && unseen_why_.empty() && !from_frame; ++i) {
    try {
      const geometry_msgs::TransformStamped t =
          tf_buffer_.lookupTransform(params_.fixed_frame, robot_[i].frame, ros::Time(0));
      unseen_links_[i].shape = robot_[i].shape;
      unseen_links_[i].pose = tf2::transformToEigen(t) * robot_[i].offset;
    } catch (const tf2::TransformException& e) {
      unseen_why_ = "unseen share unknown: link " + robot_[i].name + " not posed: " + e.what();
    }
  }
  perception::UnseenResult result;
  ros::Time stamp = ros::Time::now();
  const pc::VoxelGrid& geometry = frames_.front()->grid();  // its geometry only (never changes)
  if (unseen_why_.empty()) {
    // Each sensor with a view and a frame within the source timeout sees from where it was:
    // its newest complete sight, held (never written) until released below.
    const std::int64_t now = nowNs();
    const auto timeout = static_cast<std::int64_t>(params_.source_timeout * 1e9);
    int count = 0;
    for (std::size_t s = 0; s < view_.size(); ++s) {
      if (sight_buffers_[s] == nullptr) continue;
      const pc::SightSlot* slot = sight_buffers_[s]->acquire();
      if (slot == nullptr || now - slot->received_ns > timeout) continue;
      perception::SensorSight& sight = sights_[static_cast<std::size_t>(count++)];
      sight.fov = view_[s]->fov;
      sight.fov.pose = slot->pose;
      if (view_[s]->optical) {
        // Body frame (x forward, z up) from the optical frame (z forward, x right, y down).
        Eigen::Matrix3d optical_body;
        optical_body << 0, -1, 0, 0, 0, -1, 1, 0, 0;
        sight.fov.pose.linear() = slot->pose.linear() * optical_body;
      }
      sight.grid = &slot->grid;
      const ros::Time slot_stamp = ros::Time().fromNSec(static_cast<std::uint64_t>(std::max<std::int64_t>(0, slot->stamp_ns)));
      if (count == 1 || slot_stamp < stamp) stamp = slot_stamp;
    }
    result = unseen_.compute(unseen_links_.data(), static_cast<int>(unseen_links_.size()), params_.ssm_reach,
                             params_.frame.self_padding,
                             params_.frame.floor_height + params_.frame.floor_tolerance,
                             sights_.data(), count);
    for (const std::unique_ptr<pc::SightBuffer>& b : sight_buffers_) {
      if (b != nullptr) b->release();
    }
    if (result.refused) unseen_why_ = "unseen share unknown: a robot link's pose or shape refused";
  }
  if (unseen_boxes_ != nullptr) {
    // ~unseen: occupied: what no sensor sees near the robot is taken as an object there. With
    // the share unknown the status is DEGRADED (and the scale at degraded_scale) anyway.
    if (unseen_why_.empty()) {
      unseen_boxes_->build(geometry, unseen_.unseenCells());
    } else {
      unseen_boxes_->build(geometry, {});
    }
  }
  {
    // Published for the status, the diagnostics and perceived_objects (copies, no allocation
    // in steady state: the boxes' capacity is reserved, the reason is "" or unchanged).
    const std::lock_guard<std::mutex> lock(unseen_mutex_);
    unseen_out_.problem = unseen_why_;
    unseen_out_.result = result;
    if (unseen_boxes_ != nullptr) unseen_out_.boxes = unseen_boxes_->boxes();
    unseen_out_.stamp = stamp;
    unseen_out_.made_ns = nowNs();
  }
  if (markers_.getNumSubscribers() == 0 || !unseen_why_.empty()) return;
  // The unseen voxels of the protective volume, grey.
  const perception::VoxelGrid& grid = geometry;
  visualization_msgs::Marker m;
  m.header.frame_id = params_.fixed_frame;
  m.header.stamp = ros::Time::now();
  m.ns = "unseen";
  m.type = visualization_msgs::Marker::CUBE_LIST;
  m.action = visualization_msgs::Marker::ADD;
  m.pose.orientation.w = 1.0;
  m.scale.x = m.scale.y = m.scale.z = 0.8 * grid.voxelSize();
  m.color.r = m.color.g = m.color.b = 0.5f;
  m.color.a = 0.25f;
  m.lifetime = ros::Duration(2.0 / params_.unseen_rate);
  m.points.reserve(unseen_.unseenCells().size());
  for (const std::int64_t cell : unseen_.unseenCells()) {
    const Eigen::Vector3f c = grid.centre(cell);
    geometry_msgs::Point p;
    p.x = c.x();
    p.y = c.y();
    p.z = c.z();
    m.points.push_back(p);
  }
  if (m.points.empty()) m.action = visualization_msgs::Marker::DELETE;  // as for the voxels
  visualization_msgs::MarkerArray out;
  out.markers.push_back(std::move(m));
  markers_.publish(out);
}

bool CloudTracker::place(int s, const std_msgs::Header& header, Eigen::Isometry3f* out) {
  if (header.frame_id.empty()) {
    health_->frameRejected(s, nowNs(), "no_frame_id");
    return false;
  }
  // A frame tf has never heard of fails at once: waiting ~tf_wait for it on every frame
  // would hold up the other sensors' callbacks.
  if (!tf_buffer_._frameExists(header.frame_id)) {
    health_->frameUnplaced(s, nowNs(), "frame '" + header.frame_id + "' unknown to tf (fixed frame '" +
                                           params_.fixed_frame + "')");
    return false;
  }
  try {
    const geometry_msgs::TransformStamped t = tf_buffer_.lookupTransform(
        params_.fixed_frame, header.frame_id, header.stamp, ros::Duration(params_.tf_wait));
    const Eigen::Isometry3d pose = tf2::transformToEigen(t);
    sensor_pose_[static_cast<std::size_t>(s)] = pose;
    *out = pose.cast<float>();
    return true;
  } catch (const tf2::TransformException& e) {
    health_->frameUnplaced(s, nowNs(), "frame '" + header.frame_id + "' not placed in '" +
                                           params_.fixed_frame + "' at the stamp: " + e.what());
    return false;
  }
}

void CloudTracker::enableJoints() {
  // The links the URDF's joints move, posed as the monitor poses them (its kinematic model and
  // joint predictor, the same parameters); the others keep tf.
  std::string urdf;
  if (params_.robot.use_joint_states && params_.robot.use_robot_description) {
    nh_.getParam(params_.robot.robot_description_param, urdf);
  }
  const std::shared_ptr<const KinematicModel> model = MonitorBridges::jointModel(params_.robot, urdf);
  if (!model) return;
  JointPredictorParams predictor;
  predictor.state_timeout = params_.robot.tf_timeout;
  predictor.trajectory_tolerance = params_.robot.trajectory_tolerance;
  predictor.path_tolerance = params_.robot.joint_path_tolerance;
  joints_ = std::make_unique<pc::JointSelfPoses>(model, robot_, predictor);
  if (joints_->claimedCount() == 0) {
    joints_.reset();
    return;
  }
  // Every reading counts (interpolation, finite differences): a queue of a few.
  subs_.push_back(nh_.subscribe<sensor_msgs::JointState>(
      "joint_states", 10,
      [this](const sensor_msgs::JointState::ConstPtr& msg) {
        joints_->onJointState(msg->name, msg->position, msg->velocity, toStamp(msg->header.stamp),
                              toStamp(ros::Time::now()));
      },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay()));
  if (!params_.robot.trajectory_topic.empty()) {
    subs_.push_back(nh_.subscribe<trajectory_msgs::JointTrajectory>(
        params_.robot.trajectory_topic, 5, [this](const trajectory_msgs::JointTrajectory::ConstPtr& msg) {
          PlannedTrajectory plan;
          plan.start = toStamp(msg->header.stamp);
          plan.joint_names = msg->joint_names;
          for (const trajectory_msgs::JointTrajectoryPoint& point : msg->points) {
            plan.times.push_back(point.time_from_start.toSec());
            plan.positions.push_back(point.positions);
          }
          const std::string why = joints_->onTrajectory(plan, toStamp(ros::Time::now()));
          if (!why.empty()) ROS_WARN_THROTTLE(5.0, "cloud_tracker: planned trajectory ignored: %s", why.c_str());
        }));
  }
  ROS_INFO("cloud_tracker: %d robot bodies posed from joint_states for the self-filter (root '%s')",
           joints_->claimedCount(), model->root().c_str());
}

bool CloudTracker::tfPose(const std::string& frame, const ros::Time& stamp, Eigen::Isometry3d* pose,
                          double* gap, std::string* why) {
  geometry_msgs::TransformStamped t;
  *gap = 0.0;
  try {
    t = tf_buffer_.lookupTransform(params_.fixed_frame, frame, stamp);
  } catch (const tf2::TransformException&) {
    try {
      t = tf_buffer_.lookupTransform(params_.fixed_frame, frame, ros::Time(0));
      *gap = std::abs((stamp - t.header.stamp).toSec());
    } catch (const tf2::TransformException& e) {
      *why = e.what();
      return false;
    }
  }
  *pose = tf2::transformToEigen(t);
  return true;
}

std::string CloudTracker::poseRobot(const ros::Time& stamp, pc::CloudFrame* frame) {
  // Links the joints move: at the cloud's stamp from the joint readings (pc::JointSelfPoses),
  // on the root frame from tf. Every other link, and one the joints cannot pose: from tf at
  // the stamp or, when tf has not got there, at its newest pose grown by ~self_max_speed x
  // the gap. No pose farther than ~self_max_gap from the stamp: the growth would hide too much.
  std::string root_why;
  Eigen::Isometry3d root = Eigen::Isometry3d::Identity();
  double root_gap = 0.0;
  if (joints_ != nullptr) {
    if (tfPose(joints_->model().root(), stamp, &root, &root_gap, &root_why)) {
      joints_->poseAt(toStamp(stamp), root, links_.data());
    } else {
      root_why = "root frame '" + joints_->model().root() + "' not posed by tf: " + root_why;
    }
  }
  char gap_why[200];
  char joint_gap[200];
  for (std::size_t i = 0; i < robot_.size(); ++i) {
    const RobotBodySpec& spec = robot_[i];
    const int body = static_cast<int>(i);
    // Why the joints could not pose it (only put into words when tf cannot either).
    const std::string* joint_why = nullptr;
    bool joint_too_old = false;
    if (joints_ != nullptr && joints_->claims(body)) {
      joint_why = root_why.empty() ? &joints_->why(body) : &root_why;
      pc::SelfLink& link = links_[i];
      const double gap = std::max(link.gap, root_gap);
      if (joint_why->empty() && gap > params_.self_max_gap) {
        std::snprintf(joint_gap, sizeof joint_gap, "joint readings %.3f s from the frame's stamp (self_max_gap %.3f s)",
                      gap, params_.self_max_gap);
        joint_too_old = true;
      }
      if (joint_why->empty() && !joint_too_old) {
        if (root_gap > 0.0) {  // the root from tf's newest: its growth too
          link.speed += params_.self_max_speed;
          link.gap = gap;
        }
        continue;
      }
    }
    const auto from_joints = [&]() -> std::string {
      if (joint_why == nullptr) return std::string();
      return " (from the joints: " + (joint_too_old ? std::string(joint_gap) : *joint_why) + ")";
    };
    Eigen::Isometry3d pose;
    double gap = 0.0;
    std::string why;
    if (!tfPose(spec.frame, stamp, &pose, &gap, &why)) {
      frame->clearRobot();
      return "link " + spec.name + " (frame '" + spec.frame + "'): " + why + from_joints();
    }
    if (gap > params_.self_max_gap) {
      frame->clearRobot();
      std::snprintf(gap_why, sizeof gap_why, "newest robot poses %.3f s from the frame's stamp (self_max_gap %.3f s)",
                    gap, params_.self_max_gap);
      return "link " + spec.name + ": " + gap_why + from_joints();
    }
    links_[i].shape = spec.shape;
    links_[i].pose = pose * spec.offset;
    links_[i].speed = params_.self_max_speed;
    links_[i].gap = gap;
  }
  if (!frame->setRobot(links_.data(), static_cast<int>(links_.size()), 0.0)) {
    frame->clearRobot();
    return "the self-filter refused the robot's links";
  }
  return "";
}

void CloudTracker::onCloud(int s, const sensor_msgs::PointCloud2ConstPtr& msg) {
  pc::CloudView view;
  for (const sensor_msgs::PointField& f : msg->fields) {
    if (f.datatype != sensor_msgs::PointField::FLOAT32 || f.count < 1) continue;
    if (f.name == "x") view.x_offset = static_cast<int>(f.offset);
    if (f.name == "y") view.y_offset = static_cast<int>(f.offset);
    if (f.name == "z") view.z_offset = static_cast<int>(f.offset);
  }
  if (view.x_offset < 0 || view.y_offset < 0 || view.z_offset < 0) {
    health_->frameRejected(s, nowNs(), pc::cloudRejectionName(pc::CloudRejection::kMissingXyz));
    return;
  }
  if (msg->is_bigendian) {  // this node reads native little-endian floats
    health_->frameRejected(s, nowNs(), "big_endian");
    return;
  }
  view.data = msg->data.data();
  view.data_size = static_cast<std::int64_t>(msg->data.size());
  view.width = msg->width;
  view.height = msg->height;
  view.point_step = msg->point_step;
  view.row_step = msg->row_step;
  Eigen::Isometry3f to_fixed;
  if (!place(s, msg->header, &to_fixed)) return;
  pc::CloudFrame& frame = *frames_[static_cast<std::size_t>(s)];
  const std::string robot_problem = poseRobot(msg->header.stamp, &frame);
  const pc::CloudFrameStats& stats = frame.process(view, to_fixed);
  if (stats.rejected != pc::CloudRejection::kNone) {
    health_->frameRejected(s, nowNs(), pc::cloudRejectionName(stats.rejected));
    return;
  }
  finish(s, msg->header, robot_problem);
}

void CloudTracker::onScan(int s, const sensor_msgs::LaserScanConstPtr& msg) {
  pc::ScanView scan;
  scan.ranges = msg->ranges.data();
  scan.count = static_cast<std::int64_t>(msg->ranges.size());
  scan.angle_min = msg->angle_min;
  scan.angle_increment = msg->angle_increment;
  scan.range_min = msg->range_min;
  scan.range_max = msg->range_max;
  Eigen::Isometry3f to_fixed;
  if (!place(s, msg->header, &to_fixed)) return;
  pc::CloudFrame& frame = *frames_[static_cast<std::size_t>(s)];
  const std::string robot_problem = poseRobot(msg->header.stamp, &frame);
  const pc::CloudFrameStats& stats = frame.processScan(scan, params_.scan_band, to_fixed);
  if (stats.rejected != pc::CloudRejection::kNone) {
    health_->frameRejected(s, nowNs(), "bad_scan");
    return;
  }
  if (frame.scanResult().truncated) {
    ROS_WARN_THROTTLE(5.0, "cloud_tracker: %s: scan beyond max_scan_points, beams dropped",
                      health_->name(s).c_str());
  }
  finish(s, msg->header, robot_problem);
}

void CloudTracker::finish(int s, const std_msgs::Header& header, const std::string& robot_problem) {
  const pc::CloudFrame& frame = *frames_[static_cast<std::size_t>(s)];
  const std::int64_t now = nowNs();
  health_->frameUsed(s, now, frame.stats(), robot_problem);
  if (robot_problem.empty()) {
    // Every link posed for this frame's self-filter: the unseen thread's robot (a copy of
    // plain values, no allocation).
    const std::lock_guard<std::mutex> lock(posed_mutex_);
    std::copy(links_.begin(), links_.end(), posed_links_.begin());
    posed_ns_ = now;
  }
  publishTracks(s, header);
  if (markers_.getNumSubscribers() > 0) publishMarkers(s, header);
  // After the tracks are out: the frame's flags, pose and stamp to the unseen thread (a copy of
  // the touched cells into the slot it does not hold; never waits for its work).
  pc::SightBuffer* sight = sight_buffers_[static_cast<std::size_t>(s)].get();
  if (sight != nullptr) {
    sight->write(frame.grid(), sensor_pose_[static_cast<std::size_t>(s)],
                 static_cast<std::int64_t>(header.stamp.toNSec()), now);
    {
      const std::lock_guard<std::mutex> lock(handed_mutex_);
      ++handed_;
    }
    handed_cv_.notify_one();
  }
}

void CloudTracker::publishTracks(int s, const std_msgs::Header& header) {
  const pc::CloudFrame& frame = *frames_[static_cast<std::size_t>(s)];
  // Every sensor's frames go into the one tracker in the order they come, associated by
  // footprint, each track's box the union of every sensor's latest sight (cluster_tracks.hpp;
  // a late frame is merged at the newest stamp with its noise grown, one beyond
  // ~max_merge_gap is dropped and counted).
  if (tracks_->update(toStamp(header.stamp), frame.detections(), s) == pc::ClusterFrameUse::kTooLate) {
    ROS_WARN_THROTTLE(5.0, "cloud_tracker: %s: frame more than max_merge_gap %.3f s older than "
                           "the newest merged frame: not tracked",
                      health_->name(s).c_str(), params_.tracks.max_merge_gap);
    return;
  }
  // An empty array too: the monitor hears that nothing is there, and that the source lives.
  // A new message each frame, published as a shared pointer: a monitor nodelet in the same
  // manager takes it without serialisation (it must not change after publish()).
  const boost::shared_ptr<TrackedBoxArray> msg = boost::make_shared<TrackedBoxArray>();
  TrackedBoxArray& out = *msg;
  out.header.stamp = toTime(tracks_->stamp());
  out.header.frame_id = params_.fixed_frame;
  const std::vector<BoxObservation>& tracks = tracks_->tracks();
  out.boxes.resize(tracks.size());
  for (std::size_t i = 0; i < tracks.size(); ++i) {
    const BoxObservation& t = tracks[i];
    TrackedBox& b = out.boxes[i];
    b.id.assign(t.id.data(), t.id.size());
    b.label.assign(t.label.data(), t.label.size());
    b.pose.position.x = t.position.x();
    b.pose.position.y = t.position.y();
    b.pose.position.z = t.position.z();
    b.pose.orientation.x = t.quaternion.x();
    b.pose.orientation.y = t.quaternion.y();
    b.pose.orientation.z = t.quaternion.z();
    b.pose.orientation.w = t.quaternion.w();
    b.dimensions.x = t.dimensions.x();
    b.dimensions.y = t.dimensions.y();
    b.dimensions.z = t.dimensions.z();
    // Until its velocity is established a track says so, and its twist is 0 (ignored).
    b.velocity_unknown = !t.velocity_known;
    const Eigen::Vector3d v = t.velocity_known ? t.linear_velocity : Eigen::Vector3d::Zero();
    b.twist.linear.x = v.x();
    b.twist.linear.y = v.y();
    b.twist.linear.z = v.z();
    b.position_error = t.position_error;
    b.velocity_error = t.velocity_known ? t.velocity_error : 0.0;
  }
  if (params_.unseen_occupied) {
    // The unseen boxes of the latest unseen share, velocity unknown: the monitor grows them at
    // the `unseen` label's max_speed, so a person in the arm's shadow stops the arm. Copied out
    // of the unseen thread's result under its mutex (a few boxes; capacity reserved).
    ros::Time unseen_stamp;
    {
      const std::lock_guard<std::mutex> lock(unseen_mutex_);
      track_unseen_boxes_ = unseen_out_.boxes;
      unseen_stamp = unseen_out_.stamp;
    }
    const std::vector<pc::CellBox>& boxes = track_unseen_boxes_;
    for (std::size_t k = 0; k < boxes.size(); ++k) {
      TrackedBox& b = out.boxes.emplace_back();
      b.id = unseen_ids_[k];
      b.label = "unseen";
      b.pose.position.x = boxes[k].centre.x();
      b.pose.position.y = boxes[k].centre.y();
      b.pose.position.z = boxes[k].centre.z();
      b.pose.orientation.w = 1.0;
      b.dimensions.x = boxes[k].size.x();
      b.dimensions.y = boxes[k].size.y();
      b.dimensions.z = boxes[k].size.z();
      b.velocity_unknown = true;
      // Seen (not seen) at unseen_stamp, published at the array's later stamp: what was
      // there may have moved in between, at most track_max_speed.
      b.position_error = params_.tracks.max_speed * std::max(0.0, (out.header.stamp - unseen_stamp).toSec());
    }
  }
  objects_.publish(msg);
}

void CloudTracker::publishMarkers(int s, const std_msgs::Header& header) {
  const pc::CloudFrame& frame = *frames_[static_cast<std::size_t>(s)];
  marker_msg_.markers.clear();
  const std::string& name = health_->name(s);
  // The clusters as boxes; each lives a little over the sensor's silence limit, so a
  // cluster's box goes when its sensor stops reporting it.
  int id = 0;
  for (const pc::Detection& d : frame.detections()) {
    visualization_msgs::Marker m;
    m.header.frame_id = params_.fixed_frame;
    m.header.stamp = header.stamp;
    m.ns = "clusters " + name;
    m.id = id++;
    m.type = visualization_msgs::Marker::CUBE;
    m.action = visualization_msgs::Marker::ADD;
    m.pose.position.x = d.centre.x();
    m.pose.position.y = d.centre.y();
    m.pose.position.z = d.centre.z();
    m.pose.orientation.w = 1.0;
    m.scale.x = d.size.x();
    m.scale.y = d.size.y();
    m.scale.z = d.size.z();
    m.color.r = 1.0f;
    m.color.g = 0.6f;
    m.color.a = 0.5f;
    m.lifetime = ros::Duration(0.25);
    marker_msg_.markers.push_back(m);
  }
  // The occupied voxels (object points after the self-filter), one cube list.
  visualization_msgs::Marker v;
  v.header.frame_id = params_.fixed_frame;
  v.header.stamp = header.stamp;
  v.ns = "voxels " + name;
  v.id = 0;
  v.type = visualization_msgs::Marker::CUBE_LIST;
  v.action = visualization_msgs::Marker::ADD;
  v.pose.orientation.w = 1.0;
  v.scale.x = v.scale.y = v.scale.z = frame.grid().voxelSize();
  v.color.b = 1.0f;
  v.color.a = 0.6f;
  v.lifetime = ros::Duration(0.25);
  for (const std::int64_t cell : frame.grid().touched()) {
    if (frame.grid().count(cell) == 0) continue;
    const Eigen::Vector3f c = frame.grid().centre(cell);
    geometry_msgs::Point p;
    p.x = c.x();
    p.y = c.y();
    p.z = c.z();
    v.points.push_back(p);
  }
  // rviz marks a list marker without points as an error: an empty frame deletes the last one.
  if (v.points.empty()) v.action = visualization_msgs::Marker::DELETE;
  marker_msg_.markers.push_back(v);
  markers_.publish(marker_msg_);
}

std::string CloudTracker::unseenNow(pc::UnseenResult* result) {
  std::string problem;
  std::int64_t made_ns = 0;
  {
    const std::lock_guard<std::mutex> lock(unseen_mutex_);
    problem = unseen_out_.problem;
    *result = unseen_out_.result;
    made_ns = unseen_out_.made_ns;
  }
  if (!problem.empty()) return problem;
  // A share the unseen thread has not renewed within its period and the source timeout is
  // stale: unknown, not the last figure.
  const double age = 1e-9 * static_cast<double>(nowNs() - made_ns);
  const double limit = 1.0 / params_.unseen_rate + params_.source_timeout;
  if (age > limit) {
    char why[200];
    std::snprintf(why, sizeof why, "unseen share stale: last computed %.3f s ago (1 / unseen_rate + "
                  "source_timeout %.3f s)", age, limit);
    return why;
  }
  return problem;
}

void CloudTracker::degradedReasons(std::vector<std::string>* reasons) {
  health_->degradedReasons(nowNs(), reasons);
  pc::UnseenResult unseen;
  const std::string problem = unseenNow(&unseen);
  char share[160];
  if (!problem.empty()) {
    reasons->push_back(problem);
  } else if (unseen.share > params_.unseen_limit) {
    std::snprintf(share, sizeof share, "unseen share %.3f of the protective volume above unseen_limit %.3f",
                  unseen.share, params_.unseen_limit);
    reasons->push_back(share);
  }
}

void CloudTracker::publishStatus() {
  const boost::shared_ptr<PerceptionStatus> msg = boost::make_shared<PerceptionStatus>();
  msg->header.stamp = ros::Time::now();
  msg->header.frame_id = params_.fixed_frame;
  degradedReasons(&msg->reasons);
  msg->degraded = !msg->reasons.empty();
  pc::UnseenResult unseen;
  msg->unseen_share = unseenNow(&unseen).empty() ? unseen.share : std::numeric_limits<double>::quiet_NaN();
  status_.publish(msg);
}

void CloudTracker::diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
  std::vector<std::string> reasons;
  degradedReasons(&reasons);
  if (reasons.empty()) {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "seeing");
  } else {
    std::string all = "DEGRADED: " + reasons.front();
    for (std::size_t i = 1; i < reasons.size(); ++i) all += "; " + reasons[i];
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, all);
  }
  pc::UnseenResult unseen;
  if (unseenNow(&unseen).empty()) {
    status.add("unseen share", unseen.share);
    status.add("protective voxels", unseen.protective);
    status.add("unseen voxels", unseen.unseen);
    status.add("unseen: outside every view", unseen.outside_fov);
    status.add("unseen: shadowed", unseen.shadowed);
  }
  for (int s = 0; s < health_->size(); ++s) {
    const std::string n = health_->name(s) + ": ";
    const pc::CloudFrameStats& st = health_->lastStats(s);
    status.add(n + "frames used", health_->framesUsed(s));
    status.add(n + "frames rejected", health_->framesRejected(s));
    if (health_->framesRejected(s) > 0) status.add(n + "last rejection", health_->lastRejection(s));
    status.add(n + "frames not placed by tf", health_->framesUnplaced(s));
    status.add(n + "points", st.points_in);
    status.add(n + "NaN points", st.non_finite);
    status.add(n + "outside the volume", st.outside_volume);
    status.add(n + "floor points", st.floor);
    status.add(n + "robot points", st.self);
    status.add(n + "points within 5 cm of the padded robot", st.near_robot);
    status.add(n + "occupied voxels", st.voxels);
    status.add(n + "clusters", st.clusters);
    status.add(n + "clusters over capacity", st.clusters_overflow);
  }
  const MultiObjectTracker& tracker = tracks_->tracker();
  status.add("tracks", static_cast<int>(tracks_->tracks().size()));
  status.add("tracks: live (tentative included)", tracker.stats().live);
  status.add("frames merged late", tracks_->late());
  status.add("frames too late to merge", tracks_->tooLate());
  status.add("clusters beyond the tracker's capacity", tracks_->overflow());
}

}  // namespace workspace_proximity
