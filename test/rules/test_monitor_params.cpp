// Parameter checks: every nonsense value is reported, naming the parameter.

#include <gtest/gtest.h>

#include <limits>

#include "workspace_proximity/rules/monitor_params.hpp"

namespace wp = workspace_proximity;

namespace {
bool mentions(const std::vector<std::string>& errors, const std::string& name) {
  for (const std::string& e : errors) {
    if (e.find(name) != std::string::npos) return true;
  }
  return false;
}

// A gripper body "g": a box of half extents `half` (m) on `frame`, `offset_x` m along x.
wp::RobotBodySpec gripper(const char* frame, const Eigen::Vector3d& half, double offset_x = 0.0) {
  wp::RobotBodySpec b;
  b.name = "g";
  b.frame = frame;
  b.shape = wp::Shape::box(half);
  b.offset.translation() = Eigen::Vector3d(offset_x, 0, 0);
  return b;
}
}  // namespace

TEST(MonitorParams, DefaultsAreValid) { EXPECT_TRUE(wp::validate(wp::MonitorParams()).empty()); }

// The hand-off's sleep against the period: the default passes at the highest rate, and a
// quarter of the period passes exactly.
TEST(MonitorParams, SafetyHandoffFitsTheCycle) {
  wp::MonitorParams p;
  p.rate = 1000.0;
  EXPECT_TRUE(wp::validate(p).empty());
  p.rate = 200.0;
  p.safety_handoff = 0.25 / 200.0;
  EXPECT_TRUE(wp::validate(p).empty());
  p.safety_handoff = 0.0;
  EXPECT_TRUE(wp::validate(p).empty());
}

TEST(MonitorParams, EachBadValueIsNamed) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  struct Case {
    const char* name;
    void (*change)(wp::MonitorParams&);
  };
  const Case cases[] = {
      {"~rate", [](wp::MonitorParams& p) { p.rate = -1; }},
      {"~rate", [](wp::MonitorParams& p) { p.rate = 0; }},
      {"~horizon", [](wp::MonitorParams& p) { p.horizon = -0.5; }},
      {"~horizon", [](wp::MonitorParams& p) { p.horizon = 1e9; }},
      {"~track_timeout", [](wp::MonitorParams& p) { p.track_timeout = 0; }},
      {"~robot_margin", [](wp::MonitorParams& p) { p.robot_margin = -0.1; }},
      {"~velocity_window", [](wp::MonitorParams& p) { p.velocity_window = 0; }},
      {"~tf_timeout", [](wp::MonitorParams& p) { p.tf_timeout = -1; }},
      {"~marker_lifetime", [](wp::MonitorParams& p) { p.marker_lifetime = 0; }},
      {"~marker_rate", [](wp::MonitorParams& p) { p.marker_rate = 0; }},
      {"~marker_lifetime", [](wp::MonitorParams& p) { p.marker_lifetime = 0.05; }},
      {"~safety_handoff", [](wp::MonitorParams& p) { p.safety_handoff = -0.001; }},
      {"~safety_handoff: must be at most a quarter",
       [](wp::MonitorParams& p) {
         p.rate = 200.0;  // a period of 5 ms
         p.safety_handoff = 0.0013;
       }},
      {"~fixed_frame", [](wp::MonitorParams& p) { p.fixed_frame.clear(); }},
      {"~fixed_frame = '/map'", [](wp::MonitorParams& p) { p.fixed_frame = "/map"; }},
      {"~input_topics", [](wp::MonitorParams& p) { p.input_topics = {"a", "a"}; }},
      {"~labels", [](wp::MonitorParams& p) { p.labels.erase("default"); }},
      {"labels/person/margin", [](wp::MonitorParams& p) { p.labels["person"].margin = -1; }},
      {"labels/person/critical_time",
       [](wp::MonitorParams& p) { p.labels["person"].critical_time = 5; }},  // > warning_time
      {"robot_thresholds/warning_distance",
       [](wp::MonitorParams& p) { p.robot_thresholds.warning_distance = -2; }},
      {"~robot_bodies[0]/size",
       [](wp::MonitorParams& p) { p.robot_bodies.push_back(gripper("tool0", {0.1, 0, 0.1})); }},
      {"~robot_bodies[0]/frame",
       [](wp::MonitorParams& p) { p.robot_bodies.push_back(gripper("", {0.1, 0.1, 0.1})); }},
      {"~robot_bodies[0]/frame = '/tool0'",
       [](wp::MonitorParams& p) { p.robot_bodies.push_back(gripper("/tool0", {0.1, 0.1, 0.1})); }},
      {"~robot_bodies[0]/offset",
       [](wp::MonitorParams& p) {
         p.robot_bodies.push_back(gripper("tool0", {0.1, 0.1, 0.1}, 1e300));
       }},
      {"~ignore_pairs", [](wp::MonitorParams& p) { p.ignore_pairs.push_back({"colour:red", "*"}); }},
      {"~cycle_trigger = 'sometimes'", [](wp::MonitorParams& p) { p.cycle_trigger = "sometimes"; }},
      {"~trigger_source = 'other'", [](wp::MonitorParams& p) { p.trigger_source = "other"; }},
      {"~trigger_source = 'tracked_objects'",
       [](wp::MonitorParams& p) {
         p.input_topics = {"a", "b"};
         p.trigger_source = "tracked_objects";
       }},
      {"labels/person/ssm_min_speed",
       [](wp::MonitorParams& p) { p.labels["person"].ssm_min_speed = -1; }},
      {"~ssm/reaction_time", [](wp::MonitorParams& p) { p.ssm.reaction_time = -0.1; }},
      {"~ssm/stopping_time", [](wp::MonitorParams& p) { p.ssm.stopping_time = 100; }},
      {"~ssm/intrusion_distance", [](wp::MonitorParams& p) { p.ssm.intrusion_distance = -1; }},
      {"~ssm/sensor_uncertainty", [](wp::MonitorParams& p) { p.ssm.sensor_uncertainty = 1e6; }},
      {"~ssm/robot_uncertainty", [](wp::MonitorParams& p) { p.ssm.robot_uncertainty = -1; }},
      {"~ssm/robot_max_speed", [](wp::MonitorParams& p) { p.ssm.robot_max_speed = 0; }},
      {"~ssm/max_increase_rate", [](wp::MonitorParams& p) { p.ssm.max_increase_rate = 0; }},
      {"~ssm/hold_time", [](wp::MonitorParams& p) { p.ssm.hold_time = -1; }},
      {"~ssm/degraded_scale", [](wp::MonitorParams& p) { p.ssm.degraded_scale = 1.5; }},
      {"~ssm/labels[0]", [](wp::MonitorParams& p) { p.ssm.labels = {""}; }},
      {"~ssm/stop_trajectory_topics", [](wp::MonitorParams& p) {
         p.ssm.stop_trajectory_topics = {"/arm/command", "/arm/command"}; }},
      {"~ssm/stop_event_topics[0]", [](wp::MonitorParams& p) { p.ssm.stop_event_topics = {""}; }},
      {"~ssm/cmd_vel_in and ~ssm/cmd_vel_out", [](wp::MonitorParams& p) { p.ssm.cmd_vel_in = "in"; }},
      {"~ssm/cmd_vel_out = 'v'", [](wp::MonitorParams& p) {
         p.ssm.cmd_vel_in = "v";
         p.ssm.cmd_vel_out = "v"; }},
      {"~ssm/restart = 'auto'", [](wp::MonitorParams& p) { p.ssm.restart = "auto"; }},
      {"~ssm/stop_category", [](wp::MonitorParams& p) { p.ssm.stop_category = 0; }},
      {"~ssm/stop_category = 1", [](wp::MonitorParams& p) { p.ssm.stop_category = 1; }},
      {"~ssm/stop_category = 1", [](wp::MonitorParams& p) {
         p.ssm.stop_category = 1;
         p.ssm.halt_service = "/brakes";
         p.ssm.halt_topic = "/halt"; }},
      {"~ssm/min_stop_time", [](wp::MonitorParams& p) { p.ssm.min_stop_time = -1.0; }},
      {"~ssm/standstill_speed", [](wp::MonitorParams& p) { p.ssm.standstill_speed = std::numeric_limits<double>::quiet_NaN(); }},
      {"~ssm/max_mute_time", [](wp::MonitorParams& p) { p.ssm.max_mute_time = 3601.0; }},
      {"~detection_tracker/gate_chi2",
       [](wp::MonitorParams& p) { p.detection_tracker.gate_chi2 = 0.0; }},
      {"~detection_tracker/gate_distance",
       [](wp::MonitorParams& p) { p.detection_tracker.gate_distance = -1.0; }},
      {"~detection_tracker/confirm_hits",
       [](wp::MonitorParams& p) { p.detection_tracker.confirm_hits = 0; }},
      {"~detection_tracker/max_misses",
       [](wp::MonitorParams& p) { p.detection_tracker.max_misses = 1001; }},
      {"~detection_tracker/timeout",
       [](wp::MonitorParams& p) { p.detection_tracker.timeout = std::numeric_limits<double>::quiet_NaN(); }},
      {"~detection_tracker/known_velocity_error",
       [](wp::MonitorParams& p) { p.detection_tracker.known_velocity_error = 0.0; }},
  };
  for (const Case& c : cases) {
    wp::MonitorParams p;
    c.change(p);
    const std::vector<std::string> errors = wp::validate(p);
    EXPECT_TRUE(mentions(errors, c.name)) << c.name;
  }
  wp::MonitorParams p;
  p.rate = nan;
  EXPECT_TRUE(mentions(wp::validate(p), "~rate"));
}

TEST(MonitorParams, TheTriggerSourceIsAnInputTopicAsListed) {
  wp::MonitorParams p;
  p.cycle_trigger = "input";
  p.trigger_source = "tracked_objects";
  EXPECT_TRUE(wp::validate(p).empty());
  p.input_topics = {"/cam/boxes", "/lidar/boxes"};
  p.trigger_source = "/lidar/boxes";
  EXPECT_TRUE(wp::validate(p).empty());
  p.ssm.cmd_vel_in = "cmd_vel_raw";
  p.ssm.cmd_vel_out = "cmd_vel";
  p.ssm.labels = {"person", "forklift"};
  EXPECT_TRUE(wp::validate(p).empty());
  p.ssm.restart = "manual";
  p.ssm.stop_category = 1;
  p.ssm.halt_topic = "/halt";
  EXPECT_TRUE(wp::validate(p).empty());
}

TEST(MonitorParams, EachBadGrowthSettingIsNamed) {
  // A label's growth: negative or non-finite values are refused at start-up by name.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  struct Case {
    const char* name;
    void (*change)(wp::LabelSettings&, double);
  };
  const Case cases[] = {
      {"labels/person/position_error", [](wp::LabelSettings& l, double x) { l.position_error = x; }},
      {"labels/person/velocity_error", [](wp::LabelSettings& l, double x) { l.velocity_error = x; }},
      {"labels/person/max_accel", [](wp::LabelSettings& l, double x) { l.max_accel = x; }},
      {"labels/person/max_speed", [](wp::LabelSettings& l, double x) { l.max_speed = x; }},
  };
  for (const Case& c : cases) {
    for (double bad : {-0.1, nan, inf, -inf, 1e6}) {
      wp::MonitorParams p;
      c.change(p.labels["person"], bad);
      EXPECT_TRUE(mentions(wp::validate(p), c.name)) << c.name << " = " << bad;
    }
    wp::MonitorParams p;
    c.change(p.labels["person"], 0.5);
    EXPECT_TRUE(wp::validate(p).empty()) << c.name << " = 0.5";
  }
  // Zero everywhere is today's behaviour and valid; the robot's thresholds have no growth.
  EXPECT_EQ(wp::LabelSettings().position_error, 0.0);
  EXPECT_EQ(wp::LabelSettings().velocity_error, 0.0);
  EXPECT_EQ(wp::LabelSettings().max_accel, 0.0);
  EXPECT_EQ(wp::LabelSettings().max_speed, 0.0);
  wp::MonitorParams p;
  p.robot_thresholds.velocity_error = -1.0;  // never used for the robot: not checked
  EXPECT_TRUE(wp::validate(p).empty());
}

TEST(MonitorParams, PairRulesComeFromIgnoreThenCheck) {
  wp::MonitorParams p;
  p.ignore_pairs = {{"label:person", "label:person"}};
  p.check_pairs = {{"id:gripper", "group:robot"}};
  const wp::PairRules rules = wp::makePairRules(p);
  wp::BodyDesc a, b, g, l;
  a.id = "a";
  a.label = "person";
  b.id = "b";
  b.label = "person";
  g.id = "gripper";
  g.group = wp::BodyGroup::kRobot;
  l.id = "link";
  l.group = wp::BodyGroup::kRobot;
  EXPECT_FALSE(rules.allowed(a, b));
  EXPECT_TRUE(rules.allowed(g, l));
  wp::BodyDesc l2 = l;
  l2.id = "link2";
  EXPECT_FALSE(rules.allowed(l, l2));
}

TEST(MonitorParams, UnknownLabelsUseDefault) {
  wp::MonitorParams p;
  p.labels["person"].margin = 0.3;
  EXPECT_DOUBLE_EQ(p.label("person").margin, 0.3);
  EXPECT_DOUBLE_EQ(p.label("unicorn").margin, p.labels.at("default").margin);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
