#pragma once
/// The proximity_monitor node: a thin adapter between ROS (topics, tf2, parameters,
/// markers, diagnostics) and the ROS-free ProximityWorld.

#include <map>
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
#include "workspace_proximity/ros/cycle_timing.hpp"
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

  /// Logs the stage timing summary of the last cycles.
  ~ProximityMonitor();

  /// One prediction cycle at `now` (the timer calls this).
  void cycle(const ros::Time& now);

 private:
  struct Track {
    std::string key;        // id, qualified by the topic with several input topics
    BodyHandle handle;
    std::string label;
    ros::Time stamp;        // observation time of `motion`
    BodyMotion motion;      // in the fixed frame, at `stamp`
    Eigen::Vector3d half = Eigen::Vector3d::Zero();  // current shape's half extents
    std::uint64_t array_serial = 0;  // serial of the last array that updated it
  };
  struct RobotBody {
    RobotBodySpec spec;
    BodyHandle handle;
    bool present = false;  // in the world (posed at least once since the last reset)
    bool stale = false;    // not posed this cycle: kept at its last pose, pairs marked stale
    std::string why;       // why it is stale
  };
  // One input topic. The callback processes the first array after a cycle at once and keeps
  // later ones (only the newest) for the cycle, so a flood costs at most two arrays per
  // cycle and nothing queues up.
  struct Source {
    std::string topic;      // resolved name
    std::string qualifier;  // prefix for ids ("" with the single default topic)
    TrackedBoxArray::ConstPtr pending;
    ros::Time last_receipt;
    ros::Time last_stamp;
    double rate = 0.0;      // Hz, smoothed
    std::uint64_t arrays = 0;
    bool taken_since_cycle = false;  // an array was processed on arrival since the last cycle
  };

  // What the node knows of a world body, by BodyHandle::index (slots are reused, so entries
  // are set on add and cleared on removal).
  struct BodyInfo {
    std::int32_t track = -1;  // index into tracks_
    const RobotBody* robot = nullptr;
    const LabelSettings* settings = nullptr;  // into params_ (never modified after start)
    std::uint8_t level = 0;          // worst level this publish, valid when level_serial matches
    std::uint64_t level_serial = 0;
  };

  void runCycle(const ros::Time& now);
  void onBoxes(const TrackedBoxArray::ConstPtr& msg, std::size_t source);
  // Tracks from one array. `on_arrival`: called from the subscription callback, and returns
  // false (nothing done) when tf has no transform at the array's stamp yet, so the cycle
  // retries; otherwise true (used or rejected).
  bool processArray(Source& source, const TrackedBoxArray& msg, const ros::Time& now,
                    bool on_arrival);
  // `index`: the track for `key` in tracks_, or -1 for a new one.
  void updateTrack(const std::string& key, std::int32_t index, const TrackedBox& box,
                   const BodyMotion& motion, const ros::Time& stamp);
  void removeTrack(std::int32_t index);
  BodyInfo& bodyInfo(std::int32_t index);
  void setTrackOf(BodyHandle body, std::int32_t track);
  const LabelSettings& settingsOf(BodyHandle body, const BodyDesc& desc) const;
  void reject(const std::string& source, const std::string& id, const std::string& why);
  bool evictFarther(double squared_distance, const Eigen::Vector3d& centre);
  void expireTracks(const ros::Time& now);
  void updateRobot(const ros::Time& now);
  bool robotMotion(const RobotBody& body, const ros::Time& now, BodyMotion* motion,
                   std::string* why);
  void resetHistory(const std::string& why);
  void collectStatus(const ros::Time& now);
  bool bodyStale(const BodyHandle& body, const ros::Time& now) const;
  Eigen::Vector3d robotCentre() const;
  void publishContacts(const ros::Time& now, const std::vector<PairEvent>& events);
  void scheduleMarkers(const ros::Time& now);  // arms marker_timer_ when markers are due
  void publishMarkers();                        // marker_timer_: half a period after a cycle
  void buildMarkers(const ros::Time& now);
  void loadRobot();
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);

  ros::NodeHandle nh_;
  ros::NodeHandle pnh_;
  MonitorParams params_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  std::vector<Source> sources_;
  std::vector<ros::Subscriber> subscribers_;
  ros::Publisher contacts_pub_;
  ros::Publisher markers_pub_;
  ros::Timer timer_;
  ros::Timer marker_timer_;
  diagnostic_updater::Updater diagnostics_;

  ProximityWorld world_;
  // Tracks in a dense array (the per-cycle loops walk it linearly), found by key through
  // the index; removal swaps the last track into the hole.
  std::vector<Track> tracks_;
  std::unordered_map<std::string, std::int32_t> track_index_;
  std::vector<RobotBody> robot_;  // never resized after loadRobot(): BodyInfo points into it
  std::vector<BodyInfo> by_body_;
  MarkerBuilder markers_;

  // Reused every cycle.
  ContactEventArray contacts_msg_;
  visualization_msgs::MarkerArray markers_msg_;
  std::vector<MarkerBody> marker_bodies_;
  std::vector<std::pair<std::int32_t, std::int32_t>> event_slots_;  // body slots per event
  std::vector<std::pair<double, std::size_t>> nearest_;  // scratch for the track cap
  std::string scratch_key_;                              // qualified track id
  std::uint64_t array_serial_ = 0;                       // arrays processed
  std::uint64_t publish_serial_ = 0;                     // contact arrays built

  // Figures for diagnostics.
  ros::Time last_cycle_;
  ros::Time last_markers_;  // stamp of the last MarkerArray
  double last_cycle_ms_ = 0.0;
  double max_cycle_ms_ = 0.0;
  CycleTiming timing_;
  std::uint64_t cycles_ = 0;
  std::uint64_t resets_ = 0;
  std::map<std::string, std::uint64_t> rejected_;  // reason -> boxes or arrays dropped
  std::uint64_t tf_failures_ = 0;
  int robot_unknown_ = 0;
};

}  // namespace workspace_proximity
