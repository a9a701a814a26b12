#include "workspace_proximity/tools/load_generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <std_msgs/Float64.h>
#include <visualization_msgs/MarkerArray.h>
#include <workspace_proximity/SafetyStatus.h>

namespace workspace_proximity {
namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
}

double maxOf(const std::vector<double>& v) {
  return v.empty() ? NAN : *std::max_element(v.begin(), v.end());
}

}  // namespace

void LoadGenerator::Stats::print(const char* tag) const {
  std::printf(
      "%s arrays=%zu cycles=%zu events=%zu degraded=%zu total_ms median=%.3f p99=%.3f max=%.3f "
      "work_ms median=%.3f p99=%.3f max=%.3f\n",
      tag, arrays, cycles, events, degraded, percentile(total_ms, 0.5), percentile(total_ms, 0.99),
      maxOf(total_ms), percentile(work_ms, 0.5), percentile(work_ms, 0.99), maxOf(work_ms));
  if (!scale_ms.empty()) {
    std::printf("%s scales=%zu scale_ms median=%.3f p99=%.3f max=%.3f scale_work_ms median=%.3f "
                "p99=%.3f max=%.3f\n",
                tag, scale_ms.size(), percentile(scale_ms, 0.5), percentile(scale_ms, 0.99),
                maxOf(scale_ms), percentile(scale_work_ms, 0.5), percentile(scale_work_ms, 0.99),
                maxOf(scale_work_ms));
  }
  std::fflush(stdout);
}

LoadGenerator::LoadGenerator(ros::NodeHandle nh, const ros::NodeHandle& pnh, bool shared)
    : nh_(nh), shared_(shared) {
  pnh.param("subscribe_markers", subscribe_markers_, subscribe_markers_);
  pnh.param("count", count_, count_);
  pnh.param("rate", rate_, rate_);
  pnh.param("duration", duration_, duration_);
  pnh.param("report", report_, report_);
  pnh.param("cell", cell_, cell_);
  pnh.param("seed", seed_, seed_);
  pnh.param("subscribe_ssm", subscribe_ssm_, subscribe_ssm_);

  std::mt19937 rng(static_cast<unsigned>(seed_));
  std::uniform_real_distribution<double> pos(-cell_ / 2, cell_ / 2), dir(0, 2 * M_PI),
      speed(0.3, 1.5);
  walkers_.resize(static_cast<std::size_t>(count_));
  for (Walker& w : walkers_) {
    const double a = dir(rng), s = speed(rng);
    w = Walker{pos(rng), pos(rng), s * std::cos(a), s * std::sin(a)};
  }
  array_.header.frame_id = "world";
  array_.boxes.resize(walkers_.size());
  for (std::size_t i = 0; i < walkers_.size(); ++i) {
    auto& b = array_.boxes[i];
    b.id = "walker_" + std::to_string(i);
    b.label = (i % 10 == 0) ? "forklift" : "person";
    b.dimensions.x = (i % 10 == 0) ? 2.4 : 0.5;
    b.dimensions.y = (i % 10 == 0) ? 1.2 : 0.5;
    b.dimensions.z = (i % 10 == 0) ? 2.0 : 1.8;
    b.pose.orientation.w = 1.0;
  }

  contacts_sub_ = nh_.subscribe<ContactEventArray>(
      "contacts", 100, [this](const ContactEventArray::ConstPtr& msg) { onContacts(msg); },
      ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  pub_ = nh_.advertise<TrackedBoxArray>("tracked_objects", 1);
  if (subscribe_ssm_) {
    scale_sub_ = nh_.subscribe<std_msgs::Float64>(
        "speed_scale", 100,
        [this](const std_msgs::Float64::ConstPtr&) {
          const ros::WallTime now = ros::WallTime::now();
          std::lock_guard<std::mutex> lock(mutex_);
          scale_receipts_.push_back(now);
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
    status_sub_ = nh_.subscribe<SafetyStatus>(
        "safety_status", 100,
        [this](const SafetyStatus::ConstPtr& msg) {
          std::lock_guard<std::mutex> lock(mutex_);
          cycle_starts_.push_back(msg->header.stamp.toSec());
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  }
  if (subscribe_markers_) {
    markers_sub_ = nh_.subscribe<visualization_msgs::MarkerArray>(
        "markers", 10, [this](const visualization_msgs::MarkerArray::ConstPtr&) {
          std::lock_guard<std::mutex> lock(mutex_);
          ++marker_arrays_;
        });
  }
}

void LoadGenerator::onContacts(const ContactEventArray::ConstPtr& msg) {
  const ros::WallTime now = ros::WallTime::now();
  std::lock_guard<std::mutex> lock(mutex_);
  for (Stats* s : {&stats_, &window_}) {
    ++s->cycles;
    s->events += msg->events.size();
    s->degraded += msg->status != ContactEventArray::OK;
  }
  const double work = (ros::Time::now() - msg->header.stamp).toSec() * 1e3;
  // Every array published before this cycle started has been used by it.
  const ros::WallTime cycle_start(msg->header.stamp.toSec());
  std::size_t used = 0;
  while (used < published_.size() && published_[used] <= cycle_start) ++used;
  if (used > 0) {
    // The newest of them is the one the cycle used (older ones were superseded).
    const double total = (now - published_[used - 1]).toSec() * 1e3;
    for (Stats* s : {&stats_, &window_}) {
      s->total_ms.push_back(total);
      s->work_ms.push_back(work);
    }
    published_.erase(published_.begin(), published_.begin() + static_cast<long>(used));
  }
}

void LoadGenerator::step(double dt) {
  for (std::size_t i = 0; i < walkers_.size(); ++i) {
    Walker& w = walkers_[i];
    w.x += w.vx * dt;
    w.y += w.vy * dt;
    if (std::abs(w.x) > cell_ / 2) w.vx = -w.vx;
    if (std::abs(w.y) > cell_ / 2) w.vy = -w.vy;
    auto& b = array_.boxes[i];
    b.pose.position.x = w.x;
    b.pose.position.y = w.y;
    b.pose.position.z = 0.5 * b.dimensions.z;
    b.twist.linear.x = w.vx;
    b.twist.linear.y = w.vy;
  }
}

void LoadGenerator::run() {
  // Wait for the monitor to connect, at most 10 s.
  const ros::WallTime wait_until = ros::WallTime::now() + ros::WallDuration(10.0);
  while (ros::ok() && pub_.getNumSubscribers() == 0 && ros::WallTime::now() < wait_until) {
    ros::WallDuration(0.05).sleep();
  }
  ros::Rate loop(rate_);
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime next_report = start + ros::WallDuration(report_);
  const double dt = 1.0 / rate_;
  while (ros::ok() && (ros::WallTime::now() - start).toSec() < duration_) {
    step(dt);
    // A shared message must not change after it is published: a new one every time.
    TrackedBoxArray::Ptr shared = shared_ ? TrackedBoxArray::Ptr(new TrackedBoxArray(array_))
                                          : TrackedBoxArray::Ptr();
    TrackedBoxArray& out = shared_ ? *shared : array_;
    out.header.stamp = ros::Time::now();
    {
      std::lock_guard<std::mutex> lock(mutex_);
      published_.push_back(ros::WallTime::now());
      if (subscribe_ssm_) all_published_.push_back(published_.back());
      ++stats_.arrays;
      ++window_.arrays;
    }
    if (shared_) {
      pub_.publish(TrackedBoxArray::ConstPtr(shared));
    } else {
      pub_.publish(array_);
    }
    if (ros::WallTime::now() >= next_report) {
      std::lock_guard<std::mutex> lock(mutex_);
      window_.print("window");
      window_ = Stats();
      next_report += ros::WallDuration(report_);
    }
    loop.sleep();
  }
  ros::WallDuration(0.3).sleep();
  std::lock_guard<std::mutex> lock(mutex_);
  if (subscribe_markers_) std::printf("markers arrays=%zu\n", marker_arrays_);
  if (subscribe_ssm_) matchScales();
  stats_.print("summary");
}

void LoadGenerator::matchScales() {
  // Two subscriber threads: receipts may be appended slightly out of order.
  std::sort(scale_receipts_.begin(), scale_receipts_.end());
  std::sort(cycle_starts_.begin(), cycle_starts_.end());
  std::size_t next_scale = 0, next_array = 0;
  for (const double start_s : cycle_starts_) {
    const ros::WallTime start(start_s);
    // The cycle's speed_scale: the first received after it started (one per cycle, in order).
    while (next_scale < scale_receipts_.size() && scale_receipts_[next_scale] < start) ++next_scale;
    if (next_scale == scale_receipts_.size()) break;
    const ros::WallTime received = scale_receipts_[next_scale++];
    // As for the contacts: the newest array published before the cycle started, if no earlier
    // cycle used it (a floor cycle without a new array measures nothing).
    std::size_t used = next_array;
    while (used < all_published_.size() && all_published_[used] <= start) ++used;
    if (used == next_array) continue;
    stats_.scale_ms.push_back((received - all_published_[used - 1]).toSec() * 1e3);
    stats_.scale_work_ms.push_back((received - start).toSec() * 1e3);
    next_array = used;
  }
}

}  // namespace workspace_proximity
