#include "workspace_proximity/ros/twist_filter.hpp"

#include <cmath>

namespace workspace_proximity {
namespace {

// A consumer treats silence longer than 3 periods as 0 (docs/ssm.md, Outputs): the filter too.
constexpr double kStalePeriods = 3.0;

}  // namespace

geometry_msgs::Twist scaledTwist(const geometry_msgs::Twist& in, double scale, bool stale) {
  geometry_msgs::Twist out;  // zero
  if (stale) return out;
  out.linear.x = in.linear.x * scale;
  out.linear.y = in.linear.y * scale;
  out.linear.z = in.linear.z * scale;
  out.angular.x = in.angular.x * scale;
  out.angular.y = in.angular.y * scale;
  out.angular.z = in.angular.z * scale;
  return out;
}

TwistFilter::TwistFilter(const ros::NodeHandle& nh, const std::string& in, const std::string& out,
                         double rate)
    : nh_(nh), spinner_(1, &queue_), stale_after_(kStalePeriods / rate) {
  nh_.setCallbackQueue(&queue_);
  pub_ = nh_.advertise<geometry_msgs::Twist>(out, 10);
  sub_ = nh_.subscribe<geometry_msgs::Twist>(
      in, 10, [this](const geometry_msgs::Twist::ConstPtr& msg) { onTwist(msg); },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  spinner_.start();
}

TwistFilter::~TwistFilter() {
  spinner_.stop();
  sub_.shutdown();
}

void TwistFilter::update(double scale, const ros::Time& stamp) {
  std::lock_guard<std::mutex> lock(mutex_);
  scale_ = scale;
  stamp_ = stamp;
}

void TwistFilter::setRate(double rate) {
  std::lock_guard<std::mutex> lock(mutex_);
  stale_after_ = kStalePeriods / rate;
}

void TwistFilter::onTwist(const geometry_msgs::Twist::ConstPtr& msg) {
  double scale;
  bool stale;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    scale = scale_;
    // A clock that went back (bag loop, simulation reset) leaves a stamp in the future: stale too.
    stale = stamp_.isZero() || std::abs((ros::Time::now() - stamp_).toSec()) > stale_after_;
  }
  pub_.publish(scaledTwist(*msg, scale, stale));
}

}  // namespace workspace_proximity
