// Cloud stamp -> speed_scale (issue 23, "How fast"): one process that is a nodelet manager
// holding cloud_tracker and proximity_monitor (as proximity_monitor.launch clouds:=... runs
// them), and a depth camera beside them: it publishes ray-cast 640 x 480 organised clouds
// (as depth_image_proc's point_cloud_xyz does: float x, y, z, 16-byte points) as shared
// pointers in the same process, so no cloud is serialised, like a camera driver nodelet in
// that manager. It measures, per cloud, from the cloud's publication (its header.stamp is
// taken just before) to the receipt of:
//   - `perceived_objects` (the front end's TrackedBoxArray), matched by header.stamp;
//   - `speed_scale` of the monitor's cycle that used it (~cycle_trigger: input on the
//     monitor: a cycle per arrival), matched through `safety_status`'s stamp (the cycle's
//     start; speed_scale has none) as load_generator does;
//   - `cloud_tracker/clusters` (markers with the cloud's stamp), with ~markers: true: the
//     front end's output before perceived_objects exists (it builds them only while someone
//     subscribes, so they cost it a little).
// Parameters (private): rate (Hz, 30), duration (s, 20), frames (distinct frames, precomputed,
// 30: a person walking 1 m towards the arm and back at 1 m/s), monitor (load the monitor,
// true), markers (false), topic (bench_points), camera_frame (bench_camera), fake_perceived
// (false: with true this process also publishes, right after each cloud, the person's true box
// on perceived_objects with the cloud's stamp, in place of the front end's: the monitor's part
// alone, and a check of the matching; the front end still processes every cloud, its own
// perceived_objects renamed perceived_objects_front_end).
// The nodelets read their parameters from the server (/cloud_tracker/..., /proximity_monitor/...):
// scripts/bench-perception-latency sets them. Prints one `summary` line per output.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>
#include <random>
#include <string>
#include <vector>

#include <geometry_msgs/TransformStamped.h>
#include <nodelet/loader.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Float64.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <visualization_msgs/MarkerArray.h>
#include <workspace_proximity/SafetyStatus.h>
#include <workspace_proximity/TrackedBoxArray.h>

#include "ray_cast_scene.hpp"

namespace {

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(p * (v.size() - 1) + 0.5))];
}

void printSummary(const char* what, std::size_t clouds, const std::vector<double>& ms) {
  std::printf("summary %s clouds=%zu received=%zu median=%.3f p90=%.3f p99=%.3f max=%.3f\n", what, clouds,
              ms.size(), percentile(ms, 0.5), percentile(ms, 0.9), percentile(ms, 0.99),
              ms.empty() ? NAN : *std::max_element(ms.begin(), ms.end()));
}

// What the subscribers record (wall times, s), under one lock.
struct Receipts {
  std::mutex mutex;
  std::map<std::int64_t, double> published;  // cloud stamp (ns) -> publication (s)
  std::vector<double> published_order;       // publications in order
  std::vector<std::int64_t> stamp_order;     // their stamps (ns)
  std::map<std::int64_t, double> perceived;  // cloud stamp (ns) -> perceived_objects received (s)
  std::vector<double> perceived_ms;
  std::size_t perceived_unmatched = 0;
  std::vector<double> markers_ms;
  std::vector<double> scale_receipts;
  std::vector<double> cycle_starts;
  std::size_t degraded = 0;
  std::string last_reason;
};

double nowS() { return ros::WallTime::now().toSec(); }

}  // namespace

int main(int argc, char** argv) {
  ros::init(argc, argv, "cloud_latency_bench");
  ros::NodeHandle nh, pnh("~");
  const double rate = pnh.param("rate", 30.0), duration = pnh.param("duration", 20.0);
  const int frames = std::max(1, pnh.param("frames", 30));
  const bool with_monitor = pnh.param("monitor", true), with_markers = pnh.param("markers", false);
  const std::string topic = pnh.param<std::string>("topic", "bench_points");
  const std::string camera_frame = pnh.param<std::string>("camera_frame", "bench_camera");
  const bool fake_perceived = pnh.param("fake_perceived", false);

  // The cell: the monitor's and the front end's robot (three boxes in `world`, set by the
  // script) and a person walking from 3 m to 2 m in front of it and back, seen by a camera at
  // (3.0, 1.8, 2.0) looking at the arm.
  using bench_scene::boxAt;
  const std::vector<bench_scene::Box> robot = {boxAt({0, 0, 0.3}, {0.2, 0.2, 0.3}, 0, 0),
                                               boxAt({0.3, 0, 0.8}, {0.4, 0.08, 0.08}, 0, 0),
                                               boxAt({0.75, 0, 0.8}, {0.06, 0.06, 0.06}, 0, 0)};
  const bench_scene::DepthCamera camera({3.0, 1.8, 2.0}, {0.5, 0.0, 0.8});
  const int width = camera.width, height = camera.height, point_step = 16;
  std::vector<std::vector<std::uint8_t>> data(static_cast<std::size_t>(frames));
  std::mt19937 rng(7);
  for (int f = 0; f < frames; ++f) {
    const double s = frames > 1 ? static_cast<double>(f) / (frames - 1) : 0.0;
    std::vector<bench_scene::Box> scene = robot;
    scene.push_back(boxAt({3.0 - 1.0 * s, -0.6, 0.9}, {0.25, 0.2, 0.9}, 0, 0));
    std::vector<float> xyz(static_cast<std::size_t>(4 * width * height), 0.0f);
    camera.render(scene, rng, xyz.data(), 4);
    auto& d = data[static_cast<std::size_t>(f)];
    d.resize(xyz.size() * sizeof(float));
    std::memcpy(d.data(), xyz.data(), d.size());
  }
  sensor_msgs::PointCloud2 proto;
  proto.header.frame_id = camera_frame;
  proto.width = static_cast<std::uint32_t>(width);
  proto.height = static_cast<std::uint32_t>(height);
  proto.is_bigendian = false;
  proto.is_dense = false;
  proto.point_step = point_step;
  proto.row_step = static_cast<std::uint32_t>(point_step * width);
  for (int k = 0; k < 3; ++k) {
    sensor_msgs::PointField f;
    f.name = std::string(1, static_cast<char>('x' + k));
    f.offset = static_cast<std::uint32_t>(4 * k);
    f.datatype = sensor_msgs::PointField::FLOAT32;
    f.count = 1;
    proto.fields.push_back(f);
  }

  // The camera's pose, as its driver's static transform.
  tf2_ros::StaticTransformBroadcaster tf_static;
  {
    geometry_msgs::TransformStamped t;
    t.header.stamp = ros::Time::now();
    t.header.frame_id = "world";
    t.child_frame_id = camera_frame;
    const Eigen::Quaterniond q(camera.rot);
    t.transform.translation.x = camera.eye.x();
    t.transform.translation.y = camera.eye.y();
    t.transform.translation.z = camera.eye.z();
    t.transform.rotation.x = q.x();
    t.transform.rotation.y = q.y();
    t.transform.rotation.z = q.z();
    t.transform.rotation.w = q.w();
    tf_static.sendTransform(t);
  }

  Receipts rx;
  const auto tcp = ros::TransportHints().tcpNoDelay();
  ros::Subscriber perceived_sub = nh.subscribe<workspace_proximity::TrackedBoxArray>(
      "perceived_objects", 100,
      [&rx](const workspace_proximity::TrackedBoxArray::ConstPtr& m) {
        const double now = nowS();
        std::lock_guard<std::mutex> lock(rx.mutex);
        const auto it = rx.published.find(m->header.stamp.toNSec());
        if (it == rx.published.end()) {
          ++rx.perceived_unmatched;
        } else {
          rx.perceived_ms.push_back((now - it->second) * 1e3);
          rx.perceived[it->first] = now;
        }
      },
      ros::VoidConstPtr(), tcp);
  ros::Subscriber scale_sub = nh.subscribe<std_msgs::Float64>(
      "speed_scale", 100,
      [&rx](const std_msgs::Float64::ConstPtr&) {
        const double now = nowS();
        std::lock_guard<std::mutex> lock(rx.mutex);
        rx.scale_receipts.push_back(now);
      },
      ros::VoidConstPtr(), tcp);
  ros::Subscriber status_sub = nh.subscribe<workspace_proximity::SafetyStatus>(
      "safety_status", 100,
      [&rx](const workspace_proximity::SafetyStatus::ConstPtr& m) {
        std::lock_guard<std::mutex> lock(rx.mutex);
        rx.cycle_starts.push_back(m->header.stamp.toSec());
        if (m->status != workspace_proximity::SafetyStatus::OK) {
          ++rx.degraded;
          rx.last_reason = m->reason;
        }
      },
      ros::VoidConstPtr(), tcp);
  ros::Subscriber markers_sub;
  if (with_markers) {
    markers_sub = nh.subscribe<visualization_msgs::MarkerArray>(
        "cloud_tracker/clusters", 100, [&rx](const visualization_msgs::MarkerArray::ConstPtr& m) {
          const double now = nowS();
          std::lock_guard<std::mutex> lock(rx.mutex);
          for (const auto& marker : m->markers) {
            if (marker.ns.rfind("clusters", 0) != 0 && marker.ns.rfind("voxels", 0) != 0) continue;
            const auto it = rx.published.find(marker.header.stamp.toNSec());
            if (it != rx.published.end()) rx.markers_ms.push_back((now - it->second) * 1e3);
            break;  // one receipt per array
          }
        });
  }
  ros::AsyncSpinner spinner(1);  // this process's own subscriptions (the nodelets have their own threads)
  spinner.start();

  // The manager: the front end and the monitor as nodelets, reading their parameters from the
  // server; the camera's clouds reach the front end as shared pointers.
  nodelet::Loader manager(false);
  const nodelet::M_string remap;
  const nodelet::V_string args;
  // With fake_perceived the front end still runs on every cloud, its own output renamed.
  nodelet::M_string tracker_remap;
  if (fake_perceived) tracker_remap["/perceived_objects"] = "/perceived_objects_front_end";
  if (!manager.load("/cloud_tracker", "workspace_proximity/CloudTrackerNodelet", tracker_remap, args)) {
    std::fprintf(stderr, "cloud_latency_bench: could not load the cloud_tracker nodelet\n");
    return 1;
  }
  if (with_monitor && !manager.load("/proximity_monitor", "workspace_proximity/ProximityMonitorNodelet", remap, args)) {
    std::fprintf(stderr, "cloud_latency_bench: could not load the proximity_monitor nodelet\n");
    return 1;
  }
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>(topic, 2);
  ros::Publisher fake_pub;
  if (fake_perceived) fake_pub = nh.advertise<workspace_proximity::TrackedBoxArray>("perceived_objects", 2);
  // The front end needs the camera's transform first; 1 s of frames before the timed ones.
  ros::WallDuration(1.0).sleep();

  ros::WallRate loop(rate);
  const double start = nowS(), warm_up = 1.0;
  std::size_t clouds = 0;
  int f = 0, step = 1;
  while (ros::ok() && nowS() - start < duration + warm_up) {
    sensor_msgs::PointCloud2::Ptr msg(new sensor_msgs::PointCloud2(proto));
    msg->data = data[static_cast<std::size_t>(f)];
    const int shown = f, shown_step = step;
    if (frames > 1 && (f + step < 0 || f + step >= frames)) step = -step;  // walk back and forth
    f += step;
    msg->header.stamp = ros::Time::now();
    const bool timed = nowS() - start >= warm_up;
    {
      std::lock_guard<std::mutex> lock(rx.mutex);
      const double now = nowS();
      if (timed) {
        rx.published[msg->header.stamp.toNSec()] = now;
        rx.published_order.push_back(now);
        rx.stamp_order.push_back(static_cast<std::int64_t>(msg->header.stamp.toNSec()));
        ++clouds;
      }
    }
    pub.publish(sensor_msgs::PointCloud2::ConstPtr(msg));
    if (fake_perceived) {
      workspace_proximity::TrackedBoxArray::Ptr boxes(new workspace_proximity::TrackedBoxArray);
      boxes->header = msg->header;
      boxes->header.frame_id = "world";
      workspace_proximity::TrackedBox b;
      b.id = "person";
      b.label = "person";
      const double s = frames > 1 ? static_cast<double>(shown) / (frames - 1) : 0.0;
      b.pose.position.x = 3.0 - 1.0 * s;
      b.pose.position.y = -0.6;
      b.pose.position.z = 0.9;
      b.pose.orientation.w = 1.0;
      b.dimensions.x = 0.5;
      b.dimensions.y = 0.4;
      b.dimensions.z = 1.8;
      b.twist.linear.x = -shown_step * rate / std::max(frames - 1, 1);  // m/s: 1 m over frames - 1
      boxes->boxes.push_back(b);
      fake_pub.publish(workspace_proximity::TrackedBoxArray::ConstPtr(boxes));
    }
    loop.sleep();
  }
  ros::WallDuration(0.5).sleep();

  std::lock_guard<std::mutex> lock(rx.mutex);
  // speed_scale: each cycle's scale is the first received after the cycle started. The cycle
  // used the newest cloud published before it started whose perceived_objects had reached this
  // process by the time the scale did (this process takes its messages in order on one thread,
  // and the monitor publishes a cycle's scale only after the array it used arrived), and that no
  // earlier cycle used. A floor cycle (no new array for 1 / rate) that started before an array
  // arrived but whose scale came after it would claim that cloud a little early: at most one
  // cycle's work too little. Without perceived_objects nothing is measured.
  std::vector<double> scale_ms;
  std::sort(rx.scale_receipts.begin(), rx.scale_receipts.end());
  std::sort(rx.cycle_starts.begin(), rx.cycle_starts.end());
  std::size_t next_scale = 0, next_cloud = 0;
  for (const double cycle_start : rx.cycle_starts) {
    while (next_scale < rx.scale_receipts.size() && rx.scale_receipts[next_scale] < cycle_start) ++next_scale;
    if (next_scale == rx.scale_receipts.size()) break;
    const double received = rx.scale_receipts[next_scale++];
    std::size_t used = rx.published_order.size();
    for (std::size_t c = next_cloud; c < rx.published_order.size() && rx.published_order[c] <= cycle_start; ++c) {
      const auto it = rx.perceived.find(rx.stamp_order[c]);
      if (it != rx.perceived.end() && it->second <= received) used = c;
    }
    if (used == rx.published_order.size()) continue;
    scale_ms.push_back((received - rx.published_order[used]) * 1e3);
    next_cloud = used + 1;
  }
  printSummary("cloud_to_perceived_objects", clouds, rx.perceived_ms);
  // Where the slow ones fall: clouds more than 3 ms over the median to perceived_objects, by
  // their index modulo 6 (a 5 Hz timer on the front end's queue keeps one phase against 30 Hz
  // clouds: its collisions land on one residue).
  if (!rx.perceived.empty()) {
    const double median = percentile(rx.perceived_ms, 0.5);
    int by_phase[6] = {0, 0, 0, 0, 0, 0};
    int slow = 0;
    for (std::size_t c = 0; c < rx.stamp_order.size(); ++c) {
      const auto it = rx.perceived.find(rx.stamp_order[c]);
      if (it == rx.perceived.end()) continue;
      if ((it->second - rx.published_order[c]) * 1e3 > median + 3.0) {
        ++slow;
        ++by_phase[c % 6];
      }
    }
    std::printf("note slow_perceived=%d (over median + 3 ms) by cloud index mod 6: %d %d %d %d %d %d\n", slow,
                by_phase[0], by_phase[1], by_phase[2], by_phase[3], by_phase[4], by_phase[5]);
  }
  if (rx.perceived_unmatched > 0) {
    std::printf("note perceived_objects unmatched=%zu (the warm-up clouds', or not a cloud's stamp)\n", rx.perceived_unmatched);
  }
  if (with_monitor) {
    printSummary("cloud_to_speed_scale", clouds, scale_ms);
    std::printf("note cycles=%zu degraded=%zu last_reason=\"%s\"\n", rx.cycle_starts.size(), rx.degraded,
                rx.last_reason.c_str());
  }
  if (with_markers) printSummary("cloud_to_clusters_markers", clouds, rx.markers_ms);
  std::fflush(stdout);
  manager.clear();
  return 0;
}
