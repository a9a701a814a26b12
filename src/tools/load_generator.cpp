// load_generator: publishes N moving tracked boxes at a fixed rate and measures how the
// proximity monitor keeps up. Used by scripts/soak (reliability) and scripts/bench-node
// (latency). Prints one summary line at the end (and every ~report seconds):
//   latency from an array's publication to the first contacts array that used it, the part
//   of it spent after the cycle started (the node's own work plus transport), cycles seen.
//
// Private parameters: ~count (boxes, 1000), ~rate (Hz, 30), ~duration (s, 60), ~report (s,
// 10), ~cell (side of the square cell, m, 20), ~seed, ~subscribe_markers (false: like RViz,
// also receive the monitor's markers, which it only builds when someone listens).

#include <algorithm>
#include <cmath>
#include <mutex>
#include <cstdio>
#include <random>
#include <vector>

#include <ros/ros.h>
#include <workspace_proximity/ContactEventArray.h>
#include <visualization_msgs/MarkerArray.h>
#include <workspace_proximity/TrackedBoxArray.h>

namespace {

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

  static double percentile(std::vector<double> v, double p) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
  }
  void print(const char* tag) const {
    std::printf(
        "%s arrays=%zu cycles=%zu events=%zu degraded=%zu total_ms median=%.3f p99=%.3f max=%.3f "
        "work_ms median=%.3f p99=%.3f max=%.3f\n",
        tag, arrays, cycles, events, degraded, percentile(total_ms, 0.5), percentile(total_ms, 0.99),
        total_ms.empty() ? NAN : *std::max_element(total_ms.begin(), total_ms.end()),
        percentile(work_ms, 0.5), percentile(work_ms, 0.99),
        work_ms.empty() ? NAN : *std::max_element(work_ms.begin(), work_ms.end()));
    std::fflush(stdout);
  }
};

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "load_generator");
  ros::NodeHandle nh, pnh("~");
  int count = 1000;
  double rate = 30.0, duration = 60.0, report = 10.0, cell = 20.0;
  int seed = 1;
  bool subscribe_markers = false;
  pnh.param("subscribe_markers", subscribe_markers, subscribe_markers);
  pnh.param("count", count, count);
  pnh.param("rate", rate, rate);
  pnh.param("duration", duration, duration);
  pnh.param("report", report, report);
  pnh.param("cell", cell, cell);
  pnh.param("seed", seed, seed);

  std::mt19937 rng(static_cast<unsigned>(seed));
  std::uniform_real_distribution<double> pos(-cell / 2, cell / 2), dir(0, 2 * M_PI), speed(0.3, 1.5);
  std::vector<Walker> walkers(static_cast<std::size_t>(count));
  for (Walker& w : walkers) {
    const double a = dir(rng), s = speed(rng);
    w = Walker{pos(rng), pos(rng), s * std::cos(a), s * std::sin(a)};
  }

  // Publication times of the arrays not yet seen in a contacts array, oldest first.
  std::vector<ros::WallTime> published;
  Stats stats, window;
  ros::Time last_seen_stamp;
  std::mutex mutex;  // the spinner thread receives while the main thread publishes
  auto on_contacts = [&](const workspace_proximity::ContactEventArray::ConstPtr& msg) {
    const ros::WallTime now = ros::WallTime::now();
    std::lock_guard<std::mutex> lock(mutex);
    for (Stats* s : {&stats, &window}) {
      ++s->cycles;
      s->events += msg->events.size();
      s->degraded += msg->status != workspace_proximity::ContactEventArray::OK;
    }
    const double work = (ros::Time::now() - msg->header.stamp).toSec() * 1e3;
    // Every array published before this cycle started has been used by it.
    const ros::WallTime cycle_start(msg->header.stamp.toSec());
    std::size_t used = 0;
    while (used < published.size() && published[used] <= cycle_start) ++used;
    if (used > 0) {
      // The newest of them is the one the cycle used (older ones were superseded).
      const double total = (now - published[used - 1]).toSec() * 1e3;
      for (Stats* s : {&stats, &window}) {
        s->total_ms.push_back(total);
        s->work_ms.push_back(work);
      }
      published.erase(published.begin(), published.begin() + static_cast<long>(used));
    }
  };
  ros::Subscriber sub = nh.subscribe<workspace_proximity::ContactEventArray>(
      "contacts", 100, on_contacts, ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay());
  ros::Publisher pub = nh.advertise<workspace_proximity::TrackedBoxArray>("tracked_objects", 1);
  std::size_t marker_arrays = 0;
  ros::Subscriber markers_sub;
  if (subscribe_markers) {
    markers_sub = nh.subscribe<visualization_msgs::MarkerArray>(
        "markers", 10, [&](const visualization_msgs::MarkerArray::ConstPtr&) {
          std::lock_guard<std::mutex> lock(mutex);
          ++marker_arrays;
        });
  }

  // Contacts are received on their own thread, so receipt times are not held back by the
  // publishing loop.
  ros::AsyncSpinner spinner(subscribe_markers ? 2 : 1);
  spinner.start();
  // Wait for the monitor to connect, at most 10 s.
  const ros::WallTime wait_until = ros::WallTime::now() + ros::WallDuration(10.0);
  while (ros::ok() && pub.getNumSubscribers() == 0 && ros::WallTime::now() < wait_until) {
    ros::WallDuration(0.05).sleep();
  }

  workspace_proximity::TrackedBoxArray array;
  array.header.frame_id = "world";
  array.boxes.resize(walkers.size());
  for (std::size_t i = 0; i < walkers.size(); ++i) {
    auto& b = array.boxes[i];
    b.id = "walker_" + std::to_string(i);
    b.label = (i % 10 == 0) ? "forklift" : "person";
    b.dimensions.x = (i % 10 == 0) ? 2.4 : 0.5;
    b.dimensions.y = (i % 10 == 0) ? 1.2 : 0.5;
    b.dimensions.z = (i % 10 == 0) ? 2.0 : 1.8;
    b.pose.orientation.w = 1.0;
  }

  ros::Rate loop(rate);
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime next_report = start + ros::WallDuration(report);
  const double dt = 1.0 / rate;
  while (ros::ok() && (ros::WallTime::now() - start).toSec() < duration) {
    for (std::size_t i = 0; i < walkers.size(); ++i) {
      Walker& w = walkers[i];
      w.x += w.vx * dt;
      w.y += w.vy * dt;
      if (std::abs(w.x) > cell / 2) w.vx = -w.vx;
      if (std::abs(w.y) > cell / 2) w.vy = -w.vy;
      auto& b = array.boxes[i];
      b.pose.position.x = w.x;
      b.pose.position.y = w.y;
      b.pose.position.z = 0.5 * b.dimensions.z;
      b.twist.linear.x = w.vx;
      b.twist.linear.y = w.vy;
    }
    array.header.stamp = ros::Time::now();
    {
      std::lock_guard<std::mutex> lock(mutex);
      published.push_back(ros::WallTime::now());
      ++stats.arrays;
      ++window.arrays;
    }
    pub.publish(array);
    if (ros::WallTime::now() >= next_report) {
      std::lock_guard<std::mutex> lock(mutex);
      window.print("window");
      window = Stats();
      next_report += ros::WallDuration(report);
    }
    loop.sleep();
  }
  ros::WallDuration(0.3).sleep();
  std::lock_guard<std::mutex> lock(mutex);
  if (subscribe_markers) std::printf("markers arrays=%zu\n", marker_arrays);
  stats.print("summary");
  return 0;
}
