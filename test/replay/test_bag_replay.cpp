// The replay engine on bags written by the test, against analytic answers: a box walking
// straight at a post at 1 m/s, seen by a tracker in a frame that tf places 1 m from the fixed
// frame, the post on a static transform. Checks the cycle instants (every period of bag time
// from the first message, the last one included), delivery order (a message at a cycle's instant
// is used by that cycle), /tf_static inserted as static, arrays transformed at their stamp and
// extrapolated to the cycle (latency compensation), the times to contact, distances, levels and
// events against the closed form, the CSV files, pacing not changing a result, and frames the
// bag has no tf for being named, and ~cycle_trigger: input (cycles on the arrays, at most ~rate
// a second, at least one a period).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <rosbag/bag.h>
#include <tf2_msgs/TFMessage.h>

#include "workspace_proximity/replay/bag_input.hpp"
#include "workspace_proximity/replay/bag_replay.hpp"
#include "workspace_proximity/replay/replay_output.hpp"
#include "workspace_proximity/ros/conversions.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr std::int64_t kSecond = 1000000000;
constexpr std::int64_t kT0 = 1000 * kSecond;  // bag time of the first message
constexpr double kSpeed = 1.0;                // m/s towards the post, along -x
constexpr double kStart = 5.0;                // m, the box's x in the fixed frame at t0
constexpr double kSensorX = 1.0;              // m, the tracker frame's x in the fixed frame
constexpr double kLatency = 0.02;             // s, array stamp before its receipt
// Contact of the margin-inflated shapes: box half 0.25 + margin 0.1 (default label), post half
// 0.2 + robot margin 0.02, so at x = 0.57, i.e. 4.43 s after t0.
constexpr double kContactAfter = (kStart - (0.25 + 0.1 + 0.2 + 0.02)) / kSpeed;

std::string tempDir() {
  char pattern[] = "/tmp/wp_replay_test.XXXXXX";
  const char* dir = ::mkdtemp(pattern);
  return dir != nullptr ? dir : "/tmp";
}

geometry_msgs::TransformStamped transform(const std::string& parent, const std::string& child,
                                          double x, double z, std::int64_t stamp) {
  geometry_msgs::TransformStamped t;
  t.header.frame_id = parent;
  t.child_frame_id = child;
  t.header.stamp = wp::toTime(stamp);
  t.transform.translation.x = x;
  t.transform.translation.z = z;
  t.transform.rotation.w = 1.0;
  return t;
}

wp::TrackedBox box(const std::string& id, double x_fixed, std::int64_t stamp) {
  (void)stamp;
  wp::TrackedBox b;
  b.id = id;
  b.label = "thing";
  b.pose.position.x = x_fixed - kSensorX;  // in the tracker's frame
  b.pose.position.z = 0.5;
  b.pose.orientation.w = 1.0;
  b.dimensions.x = b.dimensions.y = b.dimensions.z = 0.5;
  b.twist.linear.x = -kSpeed;
  return b;
}

double walkerX(std::int64_t stamp) { return kStart - kSpeed * wp::secondsBetween(kT0, stamp); }

struct SceneOptions {
  double seconds = 6.0;
  bool marker_on_cycle = true;       // an extra array exactly at t0 + 3 s with a "marker" box
  std::string array_frame = "sensor";
};

// The analytic scene: /tf_static once (world -> post), /tf world -> sensor at 20 Hz from t0,
// arrays at 20 Hz from t0 + 25 ms stamped kLatency before their receipt; everything `shift` ns
// later (the walker too).
void writeSceneInto(rosbag::Bag& bag, const SceneOptions& o, std::int64_t shift) {
  tf2_msgs::TFMessage statics;
  statics.transforms.push_back(transform("world", "post", 0.0, 0.5, kT0 + shift));
  bag.write("/tf_static", wp::toTime(kT0 + shift), statics);
  const std::int64_t step = kSecond / 20;
  const std::int64_t end = kT0 + shift + static_cast<std::int64_t>(o.seconds * kSecond);
  for (std::int64_t t = kT0 + shift; t <= end; t += step) {
    tf2_msgs::TFMessage tf;
    tf.transforms.push_back(transform("world", "sensor", kSensorX, 0.0, t));
    bag.write("/tf", wp::toTime(t), tf);
    const std::int64_t received = t + step / 2;
    if (received < end) {
      wp::TrackedBoxArray a;
      const std::int64_t stamp = received - static_cast<std::int64_t>(kLatency * kSecond);
      a.header.stamp = wp::toTime(stamp);
      a.header.frame_id = o.array_frame;
      a.boxes.push_back(box("walker", walkerX(stamp - shift), stamp));
      bag.write("/tracked_objects", wp::toTime(received), a);
    }
    if (o.marker_on_cycle && t == kT0 + 3 * kSecond) {
      // Received exactly at a cycle's instant: that cycle must see it.
      wp::TrackedBoxArray a;
      a.header.stamp = wp::toTime(t);
      a.header.frame_id = o.array_frame;
      a.boxes.push_back(box("walker", walkerX(t), t));
      a.boxes.push_back(box("marker", 60.0, t));
      bag.write("/tracked_objects", wp::toTime(t), a);
    }
  }
}

void writeScene(const std::string& path, const SceneOptions& o) {
  rosbag::Bag bag;
  bag.open(path, rosbag::bagmode::Write);
  writeSceneInto(bag, o, 0);
  bag.close();
}

wp::ReplaySetup setup(double rate = 10.0) {
  wp::ReplaySetup s;
  s.params.rate = rate;
  s.params.horizon = 2.0;
  s.params.use_robot_description = false;
  wp::RobotBodySpec post;
  post.name = "post";
  post.frame = "post";
  post.shape = wp::Shape::box({0.2, 0.2, 0.2});
  s.params.robot_bodies.push_back(post);
  s.robot = s.params.robot_bodies;
  s.topics = {"/tracked_objects"};
  return s;
}

struct SeenEvent {
  std::uint8_t state;
  std::string a, b;
  double ttc, distance, closing;
  std::uint8_t level;
  bool stale;
};

struct SeenCycle {
  wp::Stamp stamp;
  bool ok;
  bool marker;
  std::vector<SeenEvent> events;
};

class Recorder : public wp::ReplaySink {
 public:
  void onCycle(const wp::CycleReport& report, const wp::ContactEventArray& contacts,
               const wp::Monitor& monitor) override {
    SeenCycle c;
    c.stamp = report.stamp;
    c.ok = contacts.status == wp::ContactEventArray::OK;
    c.marker = monitor.tracks().find("marker") >= 0;
    for (const wp::ContactEvent& e : contacts.events) {
      c.events.push_back({e.state, e.id_a, e.id_b, e.time_to_contact, e.distance, e.closing_speed,
                          e.level, e.stale != 0});
    }
    cycles.push_back(c);
  }
  std::vector<SeenCycle> cycles;
};

class BagReplayTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = tempDir(); }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }
  // Writes the default scene, `seconds` long, to scene.bag in the test's folder; its path.
  std::string sceneBag(double seconds) {
    SceneOptions o;
    o.seconds = seconds;
    const std::string path = dir_ + "/scene.bag";
    writeScene(path, o);
    return path;
  }
  std::string dir_;
};

}  // namespace

TEST_F(BagReplayTest, CyclesEventsAndLevelsMatchTheClosedForm) {
  const std::string path = sceneBag(SceneOptions().seconds);
  wp::ReplaySetup s = setup();
  wp::BagInput bag(path, s.topics);
  EXPECT_EQ(bag.begin(), kT0);
  EXPECT_EQ(bag.end(), kT0 + 6 * kSecond);
  Recorder rec;
  wp::BagReplay replay(s);
  const wp::ReplayStats stats = replay.run(&bag, &rec, 0.0);

  // Cycles every 0.1 s of bag time from t0 + 0.1 s to the last message (t0 + 6 s) inclusive.
  ASSERT_EQ(rec.cycles.size(), 60u);
  for (std::size_t k = 0; k < rec.cycles.size(); ++k) {
    EXPECT_EQ(rec.cycles[k].stamp, kT0 + static_cast<std::int64_t>(k + 1) * (kSecond / 10)) << k;
  }
  EXPECT_EQ(stats.cycles, 60u);
  EXPECT_EQ(stats.tf_static_messages, 1u);
  EXPECT_EQ(stats.tf_messages, 121u);
  EXPECT_TRUE(stats.missing_frames.empty());

  int begins = 0;
  for (const SeenCycle& c : rec.cycles) {
    const double since = wp::secondsBetween(kT0, c.stamp);
    const std::string when = "cycle at t0 + " + std::to_string(since) + " s";
    // The post rests on /tf_static only: posed every cycle, so never DEGRADED. A dynamic
    // insertion would be older than ~tf_timeout after half a second.
    EXPECT_TRUE(c.ok) << when;
    // The array received exactly at t0 + 3 s is that cycle's (it is used by it, not the next).
    if (c.stamp == kT0 + 3 * kSecond) {
      EXPECT_TRUE(c.marker) << when;
    } else if (c.stamp < kT0 + 3 * kSecond) {
      EXPECT_FALSE(c.marker) << when;
    }
    const double ttc = kContactAfter - since;
    if (ttc > 2.0 + 1e-9) {
      EXPECT_TRUE(c.events.empty()) << when;
      continue;
    }
    if (ttc <= 0.0) break;  // touching: the approach is what has a closed form here
    ASSERT_EQ(c.events.size(), 1u) << when;
    const SeenEvent& e = c.events[0];
    EXPECT_EQ(e.a, "post");
    EXPECT_EQ(e.b, "walker");
    EXPECT_EQ(e.state, begins == 0 ? wp::ContactEvent::BEGIN : wp::ContactEvent::ONGOING) << when;
    ++begins;
    EXPECT_NEAR(e.ttc, ttc, 1e-3) << when;
    EXPECT_NEAR(e.distance, ttc * kSpeed, 1e-3) << when;
    EXPECT_NEAR(e.closing, kSpeed, 1e-3) << when;
    EXPECT_FALSE(e.stale) << when;
    // Thresholds (default label and robot_thresholds, the stricter counts): WARNING at
    // time to contact <= 1 s, CRITICAL at <= 0.4 s (the distance thresholds come later).
    const std::uint8_t level = ttc <= 0.4 ? wp::ContactEvent::CRITICAL
                               : ttc <= 1.0 ? wp::ContactEvent::WARNING
                                            : wp::ContactEvent::NOTICE;
    EXPECT_EQ(e.level, level) << when;
  }
  // BEGIN at the first cycle with contact within the horizon: t0 + 2.5 s (2.43 s rounded up
  // to the grid); then every cycle up to the contact at t0 + 4.43 s.
  EXPECT_EQ(begins, 20);
}

TEST_F(BagReplayTest, PacingDoesNotChangeTheResult) {
  const std::string path = sceneBag(3.0);
  std::vector<std::vector<SeenCycle>> runs;
  for (double factor : {0.0, 40.0}) {
    wp::ReplaySetup s = setup(30.0);
    wp::BagInput bag(path, s.topics);
    Recorder rec;
    wp::BagReplay(s).run(&bag, &rec, factor);
    runs.push_back(rec.cycles);
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  for (std::size_t i = 0; i < runs[0].size(); ++i) {
    EXPECT_EQ(runs[0][i].stamp, runs[1][i].stamp);
    ASSERT_EQ(runs[0][i].events.size(), runs[1][i].events.size());
    for (std::size_t j = 0; j < runs[0][i].events.size(); ++j) {
      EXPECT_EQ(runs[0][i].events[j].ttc, runs[1][i].events[j].ttc);
      EXPECT_EQ(runs[0][i].events[j].distance, runs[1][i].events[j].distance);
    }
  }
}

TEST_F(BagReplayTest, WritesOneRowPerEventAndPerCycle) {
  const std::string path = sceneBag(SceneOptions().seconds);
  wp::ReplaySetup s = setup();
  wp::BagInput bag(path, s.topics);
  Recorder rec;
  wp::ReplayStats stats;
  {
    wp::ReplayWriter writer(dir_ + "/out/nested", bag.begin());
    struct Both : wp::ReplaySink {
      std::vector<wp::ReplaySink*> sinks;
      void onCycle(const wp::CycleReport& r, const wp::ContactEventArray& c, const wp::Monitor& m) override {
        for (wp::ReplaySink* s : sinks) s->onCycle(r, c, m);
      }
    } both;
    both.sinks = {&writer, &rec};
    stats = wp::BagReplay(s).run(&bag, &both, 0.0);
    wp::ReplayInfo info;
    info.bag = path;
    info.input = &bag;
    info.setup = &s;
    writer.finish(stats, info);
  }
  std::ifstream events(dir_ + "/out/nested/events.csv"), cycles(dir_ + "/out/nested/cycles.csv");
  std::string line;
  std::getline(events, line);
  EXPECT_EQ(line, "stamp,t,state,id_a,id_b,label_a,label_b,time_to_contact,time_to_separation,"
                  "distance,closing_speed,level,stale");
  std::size_t n_events = 0, n_rows = 0;
  for (const SeenCycle& c : rec.cycles) n_events += c.events.size();
  std::vector<std::string> rows;
  while (std::getline(events, line)) rows.push_back(line);
  EXPECT_EQ(rows.size(), n_events);
  // The BEGIN row, to the digit: stamp t0 + 2.5 s exactly, t = 2.5, the analytic numbers.
  ASSERT_FALSE(rows.empty());
  const std::string prefix = "1002.500000000,2.500000000,BEGIN,post,walker,robot,thing,";
  ASSERT_EQ(rows[0].rfind(prefix, 0), 0u) << rows[0];
  std::stringstream fields(rows[0].substr(prefix.size()));
  double ttc = 0, tts = 0, distance = 0;
  char comma = 0;
  fields >> ttc >> comma >> tts >> comma >> distance;
  EXPECT_NEAR(ttc, kContactAfter - 2.5, 1e-3) << rows[0];
  EXPECT_NEAR(distance, kContactAfter - 2.5, 1e-3) << rows[0];
  EXPECT_NE(rows[0].find(",NOTICE,0"), std::string::npos) << rows[0];
  std::getline(cycles, line);
  EXPECT_EQ(line, "stamp,t,status,events,tracks,robot_bodies,robot_unposed,details,speed_scale,"
                  "raw_scale,ssm_robot,ssm_object,separation,required_separation,approach_speed");
  // Speed and separation monitoring per cycle, against the formula: the walker's bare gap to
  // the post is d = x - 0.25 - 0.2, approaching at 1 m/s, so S_p(v_r) = 0.4 + 0.25 v_r + 0.22
  // with the defaults and the raw scale is clamp((d - 0.62) / 0.25, 0, 1).
  int limited = 0, partial = 0;
  while (std::getline(cycles, line)) {
    ++n_rows;
    std::vector<std::string> f;
    std::stringstream row(line);
    for (std::string field; std::getline(row, field, ',');) f.push_back(field);
    if (line.back() == ',') f.push_back("");
    ASSERT_EQ(f.size(), 15u) << line;  // no details (the scene stays OK): no quoted commas
    const std::int64_t stamp = static_cast<std::int64_t>(std::llround(std::stod(f[0]) * 1e9));
    const double d = walkerX(stamp) - 0.25 - 0.2;
    if (d <= 0.0) continue;  // touching: the approach is what has a closed form here
    const double speed_scale = std::stod(f[8]), raw = std::stod(f[9]);
    EXPECT_NEAR(raw, std::clamp((d - 0.62) / 0.25, 0.0, 1.0), 1e-6) << line;
    EXPECT_LE(speed_scale, raw) << line;
    if (d <= 0.87) {  // S_p(v_max): the pair is within reach
      EXPECT_EQ(f[10], "post") << line;
      EXPECT_EQ(f[11], "walker") << line;
      EXPECT_NEAR(std::stod(f[12]), d, 1e-6) << line;
      EXPECT_NEAR(std::stod(f[13]), 0.87, 1e-9) << line;
      EXPECT_NEAR(std::stod(f[14]), 1.0, 1e-9) << line;
      ++limited;
      partial += raw > 0.0 && raw < 1.0;
    }
  }
  EXPECT_EQ(n_rows, rec.cycles.size());
  EXPECT_GE(limited, 4);
  EXPECT_GE(partial, 2);
  std::ifstream summary(dir_ + "/out/nested/summary.json");
  std::stringstream json;
  json << summary.rdbuf();
  EXPECT_NE(json.str().find("\"cycles\": 60"), std::string::npos) << json.str();
  EXPECT_NE(json.str().find("\"BEGIN\": 1"), std::string::npos) << json.str();
}

TEST_F(BagReplayTest, ALongStretchWithoutInputIsSkippedAndReported) {
  // The scene twice, the second 500 s after the first: the cycles run until every input has
  // timed out, skip, and resume on the same grid a cycle or two before the second part.
  const std::string path = dir_ + "/gap.bag";
  SceneOptions o;
  o.seconds = 3.0;
  o.marker_on_cycle = false;
  const std::int64_t shift = 500 * kSecond;
  {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Write);
    writeSceneInto(bag, o, 0);
    writeSceneInto(bag, o, shift);
    bag.close();
  }
  wp::ReplaySetup s = setup();
  wp::BagInput bag(path, s.topics);
  Recorder rec;
  const wp::ReplayStats stats = wp::BagReplay(s).run(&bag, &rec, 0.0);
  ASSERT_EQ(stats.gaps.size(), 1u);
  const wp::SkippedGap& gap = stats.gaps[0];
  const std::int64_t period = kSecond / 10;
  const std::int64_t last_input = kT0 + 3 * kSecond;  // the first part's last tf message
  // Settled: every timeout (here ~source_timeout, 1 s) plus a second after the last input.
  EXPECT_GT(gap.from, last_input + 2 * kSecond);
  EXPECT_LE(gap.from, last_input + 2 * kSecond + period);
  EXPECT_GE(gap.to, kT0 + shift - 2 * period);
  EXPECT_LT(gap.to, kT0 + shift);
  EXPECT_EQ(gap.cycles, static_cast<std::uint64_t>((gap.to - gap.from) / period));
  // Every cycle on the grid, none inside the gap, every grid point outside it run once.
  std::int64_t expected = kT0 + period;
  for (const SeenCycle& c : rec.cycles) {
    if (expected == gap.from) expected = gap.to;
    ASSERT_EQ(c.stamp, expected);
    expected += period;
  }
  EXPECT_EQ(rec.cycles.size(), stats.cycles);
  EXPECT_EQ(stats.cycles + gap.cycles, static_cast<std::uint64_t>((kT0 + shift + 3 * kSecond - kT0) / period));
  // Before the gap the scene has settled: DEGRADED (the tracker and tf are silent), no event.
  const SeenCycle& before = rec.cycles[static_cast<std::size_t>((gap.from - kT0) / period) - 2];
  EXPECT_FALSE(before.ok);
  EXPECT_TRUE(before.events.empty());
  // The second part predicts like the first: BEGIN 2.5 s after its start.
  int begins = 0;
  for (const SeenCycle& c : rec.cycles) {
    for (const SeenEvent& e : c.events) {
      if (e.state != wp::ContactEvent::BEGIN) continue;
      ++begins;
      EXPECT_TRUE(c.stamp == kT0 + 25 * period || c.stamp == kT0 + shift + 25 * period) << c.stamp;
    }
  }
  EXPECT_EQ(begins, 2);
}

TEST_F(BagReplayTest, InputTriggeredCyclesRunOnArraysAtMostRateASecondAndAtLeastEveryPeriod) {
  // ~cycle_trigger: input at 10 Hz. /tf every 50 ms for 5 s; arrays (stamped kLatency before
  // their receipt) at 40 Hz from 112.5 ms to 1987.5 ms (a flood), none until 3 s (silence),
  // then at 4 Hz until 4.75 s (a slow tracker).
  const std::string path = dir_ + "/trigger.bag";
  const std::int64_t ms = kSecond / 1000;
  std::vector<std::int64_t> receipts;
  for (int k = 0; k <= 75; ++k) receipts.push_back(kT0 + 1125 * ms / 10 + 25 * ms * k);
  for (int k = 0; k <= 7; ++k) receipts.push_back(kT0 + 3000 * ms + 250 * ms * k);
  {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Write);
    tf2_msgs::TFMessage statics;
    statics.transforms.push_back(transform("world", "post", 0.0, 0.5, kT0));
    bag.write("/tf_static", wp::toTime(kT0), statics);
    std::size_t next = 0;
    for (std::int64_t t = kT0; t <= kT0 + 5 * kSecond; t += 50 * ms) {
      for (; next < receipts.size() && receipts[next] < t; ++next) {
        wp::TrackedBoxArray a;
        const std::int64_t stamp = receipts[next] - static_cast<std::int64_t>(kLatency * kSecond);
        a.header.stamp = wp::toTime(stamp);
        a.header.frame_id = "sensor";
        a.boxes.push_back(box("walker", walkerX(stamp), stamp));
        bag.write("/tracked_objects", wp::toTime(receipts[next]), a);
      }
      tf2_msgs::TFMessage tf;
      tf.transforms.push_back(transform("world", "sensor", kSensorX, 0.0, t));
      bag.write("/tf", wp::toTime(t), tf);
    }
    bag.close();
  }
  struct Cycles : wp::ReplaySink {
    std::vector<std::int64_t> stamps, used;  // each cycle's instant and its newest array's stamp
    void onCycle(const wp::CycleReport& r, const wp::ContactEventArray&, const wp::Monitor& m) override {
      stamps.push_back(r.stamp);
      used.push_back(m.sources().source(0).last_stamp);
    }
  } rec;
  wp::ReplaySetup s = setup();
  s.params.cycle_trigger = "input";
  wp::BagInput bag(path, s.topics);
  const wp::ReplayStats stats = wp::BagReplay(s).run(&bag, &rec, 0.0);
  ASSERT_EQ(stats.arrays, receipts.size());
  ASSERT_FALSE(rec.stamps.empty());
  const std::int64_t period = kSecond / 10;
  const std::int64_t latency = static_cast<std::int64_t>(kLatency * kSecond);
  // The floor a period after the bag's first message (nothing heard yet); then the first
  // array runs a cycle at its receipt, using it (a full bucket).
  ASSERT_GE(rec.stamps.size(), 2u);
  EXPECT_EQ(rec.stamps[0], kT0 + period);
  EXPECT_EQ(rec.stamps[1], receipts[0]);
  EXPECT_EQ(rec.used[1], receipts[0] - latency);
  int at_arrays = 0;
  for (std::size_t i = 0; i < rec.stamps.size(); ++i) {
    const std::int64_t t = rec.stamps[i];
    const bool at_array = std::find(receipts.begin(), receipts.end(), t) != receipts.end();
    if (i > 0) {
      // At least one cycle a period: silence is still published (the floor).
      EXPECT_LE(t - rec.stamps[i - 1], period) << i;
      // A cycle is either at an array's receipt or the floor, a period after the last cycle.
      EXPECT_TRUE(at_array || t - rec.stamps[i - 1] == period) << i;
    }
    if (at_array) {
      ++at_arrays;
      EXPECT_EQ(rec.used[i], t - latency) << "a triggered cycle uses its array, " << i;
    }
    // At most ~rate cycles a second plus the burst of 2, in every second from a cycle on.
    const auto in_second = std::count_if(rec.stamps.begin(), rec.stamps.end(), [&](std::int64_t u) {
      return u >= t && u < t + kSecond;
    });
    EXPECT_LE(in_second, 12) << i;
  }
  EXPECT_GE(kT0 + 5 * kSecond - rec.stamps.back(), 0);
  EXPECT_LE(kT0 + 5 * kSecond - rec.stamps.back(), period);
  // The flood ran the burst (112.5 and 137.5 ms), then one cycle per 0.1 s on its arrays
  // (212.5 to 1912.5 ms: 18); the slow tracker one cycle on each of its 8 arrays.
  EXPECT_EQ(at_arrays, 2 + 18 + 8);
  for (std::size_t k = 76; k < receipts.size(); ++k) {
    EXPECT_NE(std::find(rec.stamps.begin(), rec.stamps.end(), receipts[k]), rec.stamps.end()) << k;
  }
  EXPECT_EQ(stats.cycles, rec.stamps.size());
}

TEST_F(BagReplayTest, PermanentIssuesDegradeEveryCycle) {
  const std::string path = sceneBag(1.0);
  wp::ReplaySetup s = setup();
  s.permanent_issues = {"robot link 'gripper': mesh cannot be modelled"};
  wp::BagInput bag(path, s.topics);
  struct Lines : wp::ReplaySink {
    std::vector<std::vector<std::string>> lines;
    void onCycle(const wp::CycleReport&, const wp::ContactEventArray& c, const wp::Monitor&) override {
      lines.push_back(c.status == wp::ContactEventArray::DEGRADED ? c.status_details
                                                                  : std::vector<std::string>());
    }
  } rec;
  wp::BagReplay(s).run(&bag, &rec, 0.0);
  ASSERT_EQ(rec.lines.size(), 10u);
  for (const auto& l : rec.lines) {
    ASSERT_FALSE(l.empty());
    EXPECT_EQ(l.back(), "robot link 'gripper': mesh cannot be modelled");
  }
}

TEST_F(BagReplayTest, FramesWithoutTfAreNamed) {
  const std::string path = dir_ + "/scene.bag";
  SceneOptions o;
  o.seconds = 2.0;
  o.array_frame = "camera";  // no tf for it in the bag
  writeScene(path, o);
  wp::ReplaySetup s = setup();
  wp::RobotBodySpec ghost = s.robot[0];
  ghost.name = "gripper";
  ghost.frame = "ghost_link";  // not in the bag's tf at all
  s.robot.push_back(ghost);
  wp::BagInput bag(path, s.topics);
  const wp::ReplayStats stats = wp::BagReplay(s).run(&bag, nullptr, 0.0);
  ASSERT_EQ(stats.missing_frames.size(), 2u);
  EXPECT_NE(stats.missing_frames[0].find("'ghost_link' (robot body 'gripper')"), std::string::npos)
      << stats.missing_frames[0];
  EXPECT_NE(stats.missing_frames[1].find("'camera'"), std::string::npos) << stats.missing_frames[1];
  EXPECT_GT(stats.drops.count(wp::Drop::kFrame), 0u);  // the arrays were dropped, and counted
}

TEST_F(BagReplayTest, InputTopicMissingOrMistyped) {
  const std::string path = sceneBag(1.0);
  try {
    wp::BagInput bag(path, {"/boxes"});
    FAIL() << "no error for a missing input topic";
  } catch (const wp::ReplayError& e) {
    EXPECT_EQ(e.exitCode(), wp::ReplayError::kBag);
    EXPECT_NE(std::string(e.what()).find("has no topic /boxes"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("/tracked_objects (workspace_proximity/TrackedBoxArray)"),
              std::string::npos) << e.what();
  }
  try {
    wp::BagInput bag(path, {"/tf"});
    FAIL() << "no error for an input topic of another type";
  } catch (const wp::ReplayError& e) {
    EXPECT_NE(std::string(e.what()).find("topic /tf has type tf2_msgs/TFMessage, not "
                                         "workspace_proximity/TrackedBoxArray"),
              std::string::npos) << e.what();
  }
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
