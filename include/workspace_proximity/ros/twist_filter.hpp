#pragma once
/// For robots driven by velocity commands (mobile bases, arms under velocity control): every
/// geometry_msgs/Twist on ~ssm/cmd_vel_in is republished on ~ssm/cmd_vel_out multiplied by the
/// current speed scale, and as zero when the scale is stale (no cycle for more than 3 periods
/// of ROS time, or none yet).
///
/// The commands are handled on a thread of their own (a callback queue and a one-thread
/// spinner), not the cycle's: a cycle that hangs or falls behind then zeroes the commands,
/// instead of holding them back until it is done and letting them through with an old scale.

#include <mutex>
#include <string>

#include <geometry_msgs/Twist.h>
#include <ros/callback_queue.h>
#include <ros/node_handle.h>
#include <ros/publisher.h>
#include <ros/spinner.h>
#include <ros/subscriber.h>
#include <ros/time.h>

namespace workspace_proximity {

/// `in` times `scale` (every component), or zero when `stale`.
geometry_msgs::Twist scaledTwist(const geometry_msgs::Twist& in, double scale, bool stale);

class TwistFilter {
 public:
  /// Subscribes to `in` and advertises `out` (resolved in `nh`'s namespace). `rate`: the
  /// monitor's cycles per second (3 / rate s without a cycle: stale).
  TwistFilter(const ros::NodeHandle& nh, const std::string& in, const std::string& out, double rate);
  ~TwistFilter();
  TwistFilter(const TwistFilter&) = delete;
  TwistFilter& operator=(const TwistFilter&) = delete;

  /// A cycle at `stamp` (its prediction instant) gave `scale`.
  void update(double scale, const ros::Time& stamp);
  /// New cycle rate (live tuning).
  void setRate(double rate);

 private:
  void onTwist(const geometry_msgs::Twist::ConstPtr& msg);

  ros::CallbackQueue queue_;
  ros::NodeHandle nh_;  // on queue_
  ros::Publisher pub_;
  ros::Subscriber sub_;
  ros::AsyncSpinner spinner_;
  std::mutex mutex_;      // scale_, stamp_, stale_after_: written by the cycle, read by onTwist
  double scale_ = 0.0;
  ros::Time stamp_;       // zero: no cycle yet
  double stale_after_;    // s
};

}  // namespace workspace_proximity
