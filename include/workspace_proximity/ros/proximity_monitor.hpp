#pragma once
/// The proximity_monitor node: a thin adapter between ROS (topics, tf2, parameters,
/// markers, diagnostics) and the ROS-free ProximityWorld.

#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/ros.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <visualization_msgs/MarkerArray.h>
#include <workspace_proximity/ContactEventArray.h>
#include <workspace_proximity/TrackedBoxArray.h>

#include "workspace_proximity/proximity_world.hpp"
#include "workspace_proximity/ros/conversions.hpp"
#include "workspace_proximity/ros/marker_builder.hpp"
#include "workspace_proximity/ros/monitor_params.hpp"

namespace workspace_proximity {

class ProximityMonitor {
 public:
  /// Builds the world, robot bodies, subscriptions, publishers and the cycle timer.
  /// `params` must have passed validate(). Throws std::runtime_error on a URDF that does
  /// not parse.
  ProximityMonitor(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh,
                   const MonitorParams& params);

  /// One prediction cycle at `now` (the timer calls this).
  void cycle(const ros::Time& now);

 private:
  struct Track {
    BodyHandle handle;
    std::string label;
    ros::Time stamp;        // observation time of `motion`
    BodyMotion motion;      // in the fixed frame, at `stamp`
    Eigen::Vector3d half = Eigen::Vector3d::Zero();  // current shape's half extents
  };
  struct RobotBody {
    RobotBodySpec spec;
    BodyHandle handle;
    bool present = false;  // in the world this cycle
  };

  void onBoxes(const TrackedBoxArray::ConstPtr& msg, const std::string& qualifier);
  void updateTrack(const std::string& key, const TrackedBox& box, const BodyMotion& motion,
                   const ros::Time& stamp);
  void expireTracks(const ros::Time& now);
  void updateRobot(const ros::Time& now);
  bool robotMotion(const RobotBody& body, const ros::Time& now, BodyMotion* motion,
                   std::string* why);
  void publish(const ros::Time& now, const std::vector<PairEvent>& events);
  void loadRobot();
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  MonitorParams params_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  std::vector<ros::Subscriber> subscribers_;
  ros::Publisher contacts_pub_;
  ros::Publisher markers_pub_;
  ros::Timer timer_;
  diagnostic_updater::Updater diagnostics_;

  ProximityWorld world_;
  std::unordered_map<std::string, Track> tracks_;
  std::vector<RobotBody> robot_;
  MarkerBuilder markers_;

  // Reused every cycle.
  ContactEventArray contacts_msg_;
  visualization_msgs::MarkerArray markers_msg_;
  std::vector<MarkerBody> marker_bodies_;
  std::unordered_map<std::int32_t, int> worst_level_;  // body index -> worst level

  // Figures for diagnostics.
  double last_cycle_ms_ = 0.0;
  ros::Time last_input_;
  std::uint64_t cycles_ = 0;
  std::uint64_t boxes_rejected_ = 0;
  std::uint64_t arrays_dropped_ = 0;
  int robot_unknown_ = 0;
};

}  // namespace workspace_proximity
