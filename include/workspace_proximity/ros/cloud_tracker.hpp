#pragma once
/// The cloud_tracker node (and nodelet): depth clouds and laser scans into clusters, thin
/// wiring around the ROS-free perception rules (src/perception):
///   PointCloud2 (~cloud_topics) | LaserScan (~scan_topics)
///     -> fields and frame checked (rejected by name) -> tf2: sensor -> ~fixed_frame at the stamp
///     -> robot links posed from tf at the stamp (self-filter) -> CloudFrame -> clusters
///     -> ClusterTracks (one MultiObjectTracker for every sensor's frames, cluster_tracks.hpp)
///     -> perceived_objects (TrackedBoxArray: label `unknown`, ids, velocities once known,
///        the filter's 3 sigma errors), ~clusters (markers), /diagnostics (SensorHealth)
/// The unseen share runs on its own thread (its own callback queue and timer, ~unseen_rate):
/// each frame's callback hands its voxel flags, sensor pose and stamp over by a per-sensor
/// double buffer (SightBuffer) and never waits for the share's work.

#include <atomic>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>
#include <trajectory_msgs/JointTrajectory.h>
#include <visualization_msgs/MarkerArray.h>

#include <workspace_proximity/PerceptionStatus.h>
#include <workspace_proximity/TrackedBoxArray.h>

#include "workspace_proximity/perception/cloud_frame.hpp"
#include "workspace_proximity/perception/cluster_tracks.hpp"
#include "workspace_proximity/perception/joint_self_poses.hpp"
#include "workspace_proximity/perception/sensor_health.hpp"
#include "workspace_proximity/perception/sight_buffer.hpp"
#include "workspace_proximity/perception/unseen_boxes.hpp"
#include "workspace_proximity/perception/unseen_share.hpp"
#include "workspace_proximity/rules/monitor_params.hpp"

namespace workspace_proximity {

struct CloudTrackerParams {
  std::string fixed_frame = "world";
  std::vector<std::string> cloud_topics;
  std::vector<std::string> scan_topics;
  double source_timeout = 1.0;   ///< s without a usable frame from a sensor -> DEGRADED
  double tf_wait = 0.05;         ///< s a frame waits for its transforms
  /// m/s, bound on the speed of any point of a link posed from tf (the self-filter's growth per
  /// second of stamp gap); links posed from the joints have their own bound.
  double self_max_speed = 2.0;
  /// s: the largest gap between a cloud's stamp and the robot poses used for it. Beyond it
  /// the growth would hide too much around the robot: the frame goes without the self-filter
  /// (the robot's points stay, conservative) and the sensor is DEGRADED.
  double self_max_gap = 0.1;
  perception::CloudFrameParams frame;  ///< volume, voxel size, floor, padding, ...
  perception::ScanBand scan_band;      ///< scan frame z band of a beam's column
  /// robot_bodies, use_robot_description, robot_description_param, and the joints as the
  /// monitor reads them: use_joint_states, trajectory_topic, tf_timeout, trajectory_tolerance,
  /// joint_path_tolerance.
  MonitorParams robot;
  /// The unseen share: R (m) around the robot, its limit, how often; the sensors' views by
  /// topic (a sensor without one sees nothing there). `optical`: the view is given in a
  /// camera's optical frame (z forward, x right, y down) instead of x forward, z up.
  double ssm_reach = 1.5;
  double unseen_limit = 0.3;     ///< share above which the status is DEGRADED
  double unseen_rate = 5.0;      ///< Hz
  double status_rate = 10.0;     ///< Hz, perception_status (PerceptionStatus) for the monitor
  /// ~unseen: "ignore", or "occupied": the unseen protective voxels go to the monitor as boxes
  /// (label `unseen`, velocity unknown) beside the tracks, at most `unseen_max_boxes`.
  bool unseen_occupied = false;
  int unseen_max_boxes = 64;
  struct View {
    perception::SensorFov fov;   ///< pose unused: the sensor's frame at its frame's stamp
    bool optical = false;
  };
  std::map<std::string, View> views;
  /// The clusters' tracker: label `unknown`, its max_speed and max_accel (the monitor's
  /// `unknown` label: 2.0 m/s, 4.0 m/s^2), a cluster centre's noise (default: one voxel),
  /// the largest stamp gap at which a late sensor's frame is still merged.
  perception::ClusterTrackParams tracks;
};

/// Reads the private parameters; throws std::runtime_error naming a bad one.
CloudTrackerParams readCloudTrackerParams(const ros::NodeHandle& private_nh);

class CloudTracker {
 public:
  CloudTracker(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh,
               const CloudTrackerParams& params);
  /// Stops the unseen share's timer and joins its thread before anything it uses goes.
  ~CloudTracker();
  CloudTracker(const CloudTracker&) = delete;
  CloudTracker& operator=(const CloudTracker&) = delete;

 private:
  void onCloud(int sensor, const sensor_msgs::PointCloud2ConstPtr& msg);
  void onScan(int sensor, const sensor_msgs::LaserScanConstPtr& msg);
  // The sensor -> fixed transform at the frame's stamp, or false (the sensor told why).
  bool place(int sensor, const std_msgs::Header& header, Eigen::Isometry3f* sensor_to_fixed);
  // Poses the robot's links at `stamp` for the self-filter; "" or why it could not.
  std::string poseRobot(const ros::Time& stamp, perception::CloudFrame* frame);
  // `frame` in ~fixed_frame from tf at `stamp`, or at its newest pose and `gap` s from it; or
  // false with why.
  bool tfPose(const std::string& frame, const ros::Time& stamp, Eigen::Isometry3d* pose, double* gap,
              std::string* why);
  // The joints (with a URDF and ~use_joint_states): links they move posed at a frame's stamp.
  void enableJoints();
  void finish(int sensor, const std_msgs::Header& header, const std::string& robot_problem);
  void publishMarkers(int sensor, const std_msgs::Header& header);
  // The frame's clusters into the tracker, its tracks on perceived_objects.
  void publishTracks(int sensor, const std_msgs::Header& header);
  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status);
  // Every reason the front end is DEGRADED now (each naming its sensor or the unseen share).
  void degradedReasons(std::vector<std::string>* reasons);
  // perception_status: the reasons and the unseen share, for the monitor.
  void publishStatus();
  // The unseen share of the protective volume from every sensor's latest frame (on the
  // unseen thread: reads only the sight buffers, tf and what the constructor set).
  void updateUnseen();
  // The newest unseen result as the status sees it now: "" or why it is unknown or stale.
  std::string unseenNow(perception::UnseenResult* result);
  std::int64_t nowNs() const { return static_cast<std::int64_t>(ros::Time::now().toNSec()); }

  ros::NodeHandle nh_, pnh_;
  CloudTrackerParams params_;
  tf2_ros::Buffer tf_buffer_;
  tf2_ros::TransformListener tf_listener_;
  std::vector<RobotBodySpec> robot_;
  std::vector<perception::SelfLink> links_;
  std::unique_ptr<perception::JointSelfPoses> joints_;  // null: every link from tf
  std::vector<std::unique_ptr<perception::CloudFrame>> frames_;  // one per sensor
  std::unique_ptr<perception::SensorHealth> health_;
  std::vector<ros::Subscriber> subs_;
  ros::Publisher markers_;
  ros::Publisher objects_;  // perceived_objects
  std::unique_ptr<perception::ClusterTracks> tracks_;
  diagnostic_updater::Updater diagnostics_;
  ros::Timer diag_timer_;
  ros::Timer unseen_timer_;
  ros::Timer status_timer_;
  ros::Publisher status_;  // perception_status
  std::vector<Eigen::Isometry3d> sensor_pose_;      // per sensor: its frame at its last frame
  std::vector<const CloudTrackerParams::View*> view_;  // per sensor, or null
  std::vector<std::string> unseen_ids_;                // "unseen_<k>", made once
  std::vector<perception::CellBox> track_unseen_boxes_;  // publishTracks' copy (reserved)
  visualization_msgs::MarkerArray marker_msg_;

  // Handed from the frames' callbacks to the unseen thread: per sensor with a view, its
  // latest frame's flags, pose and stamps (null for a sensor without a view).
  std::vector<std::unique_ptr<perception::SightBuffer>> sight_buffers_;

  // The unseen thread's own state (only it touches these).
  perception::UnseenShare unseen_{64};  // sensors beyond 64 see nothing there (counted unseen)
  std::vector<perception::SensorSight> sights_;
  std::vector<perception::SelfLink> unseen_links_;          // the robot now, its own copy
  // The links as the newest frame's self-filter posed them (joints or tf, at its stamp), for
  // the unseen thread: a robot posed from joint_states alone has no tf for its moving links.
  std::mutex posed_mutex_;
  std::vector<perception::SelfLink> posed_links_;  // guarded by posed_mutex_
  std::int64_t posed_ns_ = -1;                     // ns, receipt of that frame; -1: none yet
  std::unique_ptr<perception::UnseenBoxes> unseen_boxes_;  // ~unseen: occupied
  std::string unseen_why_;

  // The unseen thread's newest result, copied in and out under unseen_mutex_ (small: the
  // counts, the reason, at most ~unseen_max_boxes boxes).
  struct UnseenOut {
    std::string problem = "not computed yet";  // "" when `result` is known
    perception::UnseenResult result;
    std::vector<perception::CellBox> boxes;   // ~unseen: occupied
    ros::Time stamp;           // the oldest frame stamp the share was made from
    std::int64_t made_ns = 0;  // ROS time it was made (the constructor's before the first)
  };
  std::mutex unseen_mutex_;
  UnseenOut unseen_out_;

  // Frames handed over so far: the unseen thread waits for the next (at most half a period)
  // so that its work falls in the gap after a frame, not across the next one.
  std::mutex handed_mutex_;
  std::condition_variable handed_cv_;
  std::uint64_t handed_ = 0;

  // The unseen thread: its callback queue (the timer's only), served until stop.
  ros::CallbackQueue unseen_queue_;
  std::atomic<bool> unseen_stop_{false};
  std::thread unseen_thread_;
};

}  // namespace workspace_proximity
