#pragma once
/// load_generator: publishes N moving tracked boxes at a fixed rate and measures how the
/// proximity monitor keeps up. Used by scripts/soak (reliability) and scripts/bench-node
/// (latency), as a node or, next to the monitor's nodelet, as a nodelet in the same manager
/// (arrays then reach the monitor as shared pointers, without serialisation). Prints one
/// summary line at the end (and every ~report seconds): latency from an array's publication
/// to the first contacts array that used it, the part of it spent after the cycle started
/// (the node's own work plus transport), cycles seen.
///
/// With ~subscribe_ssm it also receives `speed_scale` and `safety_status` and, in the summary,
/// times publication -> speed_scale received (`scale_ms`) and cycle start -> speed_scale
/// received (`scale_work_ms`). speed_scale (std_msgs/Float64) has no stamp: each cycle's
/// safety_status (published with it, stamped with the cycle's start) says when a cycle started,
/// and the cycle's speed_scale is the first one received after that start.
///
/// Private parameters: ~count (boxes, 1000), ~rate (Hz, 30), ~duration (s, 60), ~report (s,
/// 10), ~cell (side of the square cell, m, 20), ~seed, ~subscribe_markers (false: like RViz,
/// also receive the monitor's markers, which it only builds when someone listens),
/// ~subscribe_ssm (false).

#include <cstddef>
#include <mutex>
#include <vector>

#include <ros/ros.h>
#include <workspace_proximity/ContactEventArray.h>
#include <workspace_proximity/TrackedBoxArray.h>

namespace workspace_proximity {

class LoadGenerator {
 public:
  /// `nh`: where tracked_objects, contacts and markers are. With `shared`, every array is a
  /// new message published as a shared pointer (zero copy to a nodelet in the same manager).
  LoadGenerator(ros::NodeHandle nh, const ros::NodeHandle& pnh, bool shared);
  /// Publishes for ~duration seconds (or until ROS shuts down), then prints the summary.
  void run();

 private:
  struct Walker {
    double x, y, vx, vy;
  };
  struct Stats {
    std::vector<double> total_ms;   // publication -> contacts received
    std::vector<double> work_ms;    // cycle start (header.stamp) -> contacts received
    std::size_t arrays = 0;    // TrackedBoxArrays published
    std::size_t cycles = 0;    // ContactEventArrays received
    std::size_t events = 0;
    std::size_t degraded = 0;
    std::vector<double> scale_ms;       // publication -> speed_scale received (summary only)
    std::vector<double> scale_work_ms;  // cycle start -> speed_scale received (summary only)
    void print(const char* tag) const;
  };
  void onContacts(const ContactEventArray::ConstPtr& msg);
  // The speed_scale latencies from the receipts (matched as the header says), into stats_.
  void matchScales();
  void step(double dt);

  ros::NodeHandle nh_;
  bool shared_;
  int count_ = 1000;
  double rate_ = 30.0, duration_ = 60.0, report_ = 10.0, cell_ = 20.0;
  int seed_ = 1;
  bool subscribe_markers_ = false;
  bool subscribe_ssm_ = false;
  ros::Subscriber scale_sub_, status_sub_;
  std::vector<ros::WallTime> all_published_;  // every publication time, for matchScales
  std::vector<ros::WallTime> scale_receipts_;  // speed_scale receipt times
  std::vector<double> cycle_starts_;           // safety_status header stamps, s
  std::vector<Walker> walkers_;
  TrackedBoxArray array_;
  ros::Publisher pub_;
  ros::Subscriber contacts_sub_, markers_sub_;

  std::mutex mutex_;  // receipts arrive on other threads while run() publishes
  std::vector<ros::WallTime> published_;  // publication times not yet seen in contacts
  Stats stats_, window_;
  std::size_t marker_arrays_ = 0;
};

}  // namespace workspace_proximity
