// The parameter reader on a parameter tree (the node's private namespace as one XmlRpcValue):
// every type and nesting level, defaults kept for what is not set, and each wrong type or
// structure rejected with a message naming the parameter.

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "params_expectations.hpp"  // test/shared
#include "workspace_proximity/rules/param_table.hpp"
#include "workspace_proximity/ros/ros_params.hpp"

namespace wp = workspace_proximity;
using XmlRpc::XmlRpcValue;

namespace {

XmlRpcValue dict() {
  XmlRpcValue v;
  v.begin();  // an empty dictionary
  return v;
}

XmlRpcValue list(std::initializer_list<XmlRpcValue> items) {
  XmlRpcValue v;
  v.setSize(static_cast<int>(items.size()));
  int i = 0;
  for (const XmlRpcValue& item : items) v[i++] = item;
  return v;
}

XmlRpcValue str(const char* s) { return XmlRpcValue(std::string(s)); }

// A dictionary of one entry: nested settings in one expression.
XmlRpcValue with(const char* key, const XmlRpcValue& value) {
  XmlRpcValue v = dict();
  v[key] = value;
  return v;
}

// The message readParams throws for `root`, or "" when it does not throw.
std::string errorOf(const XmlRpcValue& root) {
  try {
    wp::readParams(root);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

XmlRpcValue labelDict(double margin) {
  XmlRpcValue l = dict();
  l["margin"] = margin;
  return l;
}

}  // namespace

TEST(RosParams, NothingSetGivesTheDefaults) {
  const wp::MonitorParams defaults;
  for (const XmlRpcValue& root : {XmlRpcValue(), dict()}) {
    const wp::MonitorParams p = wp::readParams(root);
    wp_test::expectSameScalars(p, defaults);
    EXPECT_TRUE(p.input_topics.empty());
    EXPECT_TRUE(p.robot_bodies.empty());
    EXPECT_EQ(p.labels.size(), 1u);
    EXPECT_EQ(p.labels.at("default").margin, defaults.labels.at("default").margin);
    EXPECT_TRUE(wp::validate(p).empty());
  }
}

TEST(RosParams, ScalarsOfEachType) {
  XmlRpcValue root = dict();
  root["fixed_frame"] = str("map");
  root["rate"] = 20;            // an integer where a number is expected
  root["horizon"] = 1.5;
  root["track_timeout"] = 2;
  root["stale_after"] = 0.3;
  root["source_timeout"] = 0.7;
  root["max_future"] = 0.25;
  root["max_tracks"] = 55;
  root["use_robot_description"] = false;
  root["robot_description_param"] = str("arm_description");
  root["robot_margin"] = 0.05;
  root["velocity_window"] = 0.2;
  root["tf_timeout"] = 0.4;
  root["publish_markers"] = false;
  root["marker_lifetime"] = 1.0;
  root["marker_rate"] = 5;
  root["unrelated_key"] = str("ignored");  // other keys of the namespace are not ours
  const wp::MonitorParams p = wp::readParams(root);
  EXPECT_EQ(p.fixed_frame, "map");
  EXPECT_EQ(p.rate, 20.0);
  EXPECT_EQ(p.horizon, 1.5);
  EXPECT_EQ(p.track_timeout, 2.0);
  EXPECT_EQ(p.stale_after, 0.3);
  EXPECT_EQ(p.source_timeout, 0.7);
  EXPECT_EQ(p.max_future, 0.25);
  EXPECT_EQ(p.max_tracks, 55);
  EXPECT_FALSE(p.use_robot_description);
  EXPECT_EQ(p.robot_description_param, "arm_description");
  EXPECT_EQ(p.robot_margin, 0.05);
  EXPECT_EQ(p.velocity_window, 0.2);
  EXPECT_EQ(p.tf_timeout, 0.4);
  EXPECT_FALSE(p.publish_markers);
  EXPECT_EQ(p.marker_lifetime, 1.0);
  EXPECT_EQ(p.marker_rate, 5.0);
}

TEST(RosParams, ListsAndPairs) {
  XmlRpcValue root = dict();
  root["input_topics"] = list({str("/a/boxes"), str("b")});
  root["ignore_pairs"] = list({list({str("label:person"), str("label:person")})});
  root["check_pairs"] = list({list({str("id:gripper"), str("id:base_link")}),
                              list({str("*"), str("group:robot")})});
  const wp::MonitorParams p = wp::readParams(root);
  ASSERT_EQ(p.input_topics.size(), 2u);
  EXPECT_EQ(p.input_topics[0], "/a/boxes");
  EXPECT_EQ(p.input_topics[1], "b");
  ASSERT_EQ(p.ignore_pairs.size(), 1u);
  EXPECT_EQ(p.ignore_pairs[0].first, "label:person");
  EXPECT_EQ(p.ignore_pairs[0].second, "label:person");
  ASSERT_EQ(p.check_pairs.size(), 2u);
  EXPECT_EQ(p.check_pairs[1].first, "*");
  EXPECT_EQ(p.check_pairs[1].second, "group:robot");
}

TEST(RosParams, SsmCycleAndTheCycleTrigger) {
  XmlRpcValue root = dict();
  root["cycle_trigger"] = str("input");
  root["trigger_source"] = str("/lidar/boxes");
  // The numbers under ~ssm/: each as set here and its default when not set.
  struct SsmNumber {
    const char* key;
    double wp::SsmParams::*field;
    double set;
    double fallback;
  };
  const SsmNumber numbers[] = {
      {"reaction_time", &wp::SsmParams::reaction_time, 0.05, 0.1},
      {"stopping_time", &wp::SsmParams::stopping_time, 1.0, 0.3},
      {"intrusion_distance", &wp::SsmParams::intrusion_distance, 0.2, 0.1},
      {"sensor_uncertainty", &wp::SsmParams::sensor_uncertainty, 0.15, 0.1},
      {"robot_uncertainty", &wp::SsmParams::robot_uncertainty, 0.01, 0.02},
      {"robot_max_speed", &wp::SsmParams::robot_max_speed, 0.5, 1.0},
      {"max_increase_rate", &wp::SsmParams::max_increase_rate, 2.0, 0.5},
      {"hold_time", &wp::SsmParams::hold_time, 1.5, 0.5},
      {"degraded_scale", &wp::SsmParams::degraded_scale, 0.1, 0.0},
  };
  XmlRpcValue ssm = dict();
  ssm["enabled"] = false;
  ssm["labels"] = list({str("person")});
  for (const SsmNumber& n : numbers) ssm[n.key] = n.set;
  ssm["stopping_time"] = 1;  // an integer is a number too
  ssm["stop_trajectory_topics"] = list({str("/arm/command")});
  ssm["stop_event_topics"] = list({str("/trajectory_execution_event"), str("/other")});
  ssm["cmd_vel_in"] = str("cmd_vel_raw");
  ssm["cmd_vel_out"] = str("cmd_vel");
  root["ssm"] = ssm;
  XmlRpcValue person = dict();
  person["ssm_min_speed"] = 1.6;
  root["labels"] = dict();
  root["labels"]["person"] = person;
  const wp::MonitorParams p = wp::readParams(root);
  EXPECT_EQ(p.cycle_trigger, "input");
  EXPECT_EQ(p.trigger_source, "/lidar/boxes");
  EXPECT_FALSE(p.ssm.enabled);
  EXPECT_EQ(p.ssm.labels, std::vector<std::string>{"person"});
  for (const SsmNumber& n : numbers) EXPECT_EQ(p.ssm.*n.field, n.set) << n.key;
  EXPECT_EQ(p.ssm.stop_trajectory_topics, std::vector<std::string>{"/arm/command"});
  EXPECT_EQ(p.ssm.stop_event_topics.size(), 2u);
  EXPECT_EQ(p.ssm.cmd_vel_in, "cmd_vel_raw");
  EXPECT_EQ(p.ssm.cmd_vel_out, "cmd_vel");
  EXPECT_EQ(p.label("person").ssm_min_speed, 1.6);
  EXPECT_EQ(p.label("default").ssm_min_speed, 0.0);
  // Not set: the defaults.
  const wp::MonitorParams d = wp::readParams(dict());
  EXPECT_TRUE(d.ssm.enabled);
  EXPECT_EQ(d.cycle_trigger, "timer");
  for (const SsmNumber& n : numbers) EXPECT_EQ(d.ssm.*n.field, n.fallback) << n.key;
  EXPECT_TRUE(wp::unknownParams(root).empty()) << ::testing::PrintToString(wp::unknownParams(root));
}

TEST(RosParams, EveryRowOfTheTableIsReadFromItsName) {
  // Each plain row set alone at its name ("ssm/hold_time": hold_time in the dictionary ssm)
  // to a value other than its default: the member the row names takes it, as its type reads.
  for (const wp::ParamRow& row : wp::paramTable()) {
    wp::MonitorParams defaults;
    const wp::ParamMember& m = row.member;
    XmlRpcValue value;
    switch (m.type) {
      case wp::ParamType::kNumber:
        value = m.number(defaults) == row.min ? row.max : row.min;
        break;
      case wp::ParamType::kInteger:
        value = static_cast<int>(m.integer(defaults) == row.min ? row.max : row.min);
        break;
      case wp::ParamType::kBool: value = !m.flag(defaults); break;
      case wp::ParamType::kString: value = str("x"); break;
      case wp::ParamType::kStringList: value = list({str("x")}); break;
      case wp::ParamType::kPairs: value = list({list({str("*"), str("*")})}); break;
      case wp::ParamType::kStructure: continue;
    }
    const std::string name = row.name;
    const std::size_t slash = name.find('/');
    XmlRpcValue root = dict();
    if (slash == std::string::npos) {
      root[name] = value;
    } else {
      root[name.substr(0, slash)] = with(name.substr(slash + 1).c_str(), value);
    }
    wp::MonitorParams p = wp::readParams(root);
    bool changed = false;
    switch (m.type) {
      case wp::ParamType::kNumber: changed = m.number(p) == static_cast<double>(value); break;
      case wp::ParamType::kInteger: changed = m.integer(p) == static_cast<int>(value); break;
      case wp::ParamType::kBool: changed = m.flag(p) != m.flag(defaults); break;
      case wp::ParamType::kString: changed = m.text(p) == "x"; break;
      case wp::ParamType::kStringList: changed = m.names(p) == std::vector<std::string>{"x"}; break;
      case wp::ParamType::kPairs: changed = m.pairs(p).size() == 1u; break;
      case wp::ParamType::kStructure: break;
    }
    EXPECT_TRUE(changed) << name;
    EXPECT_TRUE(wp::unknownParams(root).empty()) << name;
  }
}

TEST(RosParams, LabelsInheritFromDefaultWhateverTheirOrder) {
  XmlRpcValue labels = dict();
  XmlRpcValue person = dict();  // "a..." sorts before "default": read after it all the same
  person["warning_time"] = 2.0;
  labels["a_person"] = person;
  XmlRpcValue def = dict();
  def["margin"] = 0.3;
  def["critical_distance"] = 0.1;
  labels["default"] = def;
  labels["forklift"] = labelDict(0.5);
  XmlRpcValue robot = dict();
  robot["warning_distance"] = 0.6;
  XmlRpcValue root = with("labels", labels);
  root["robot_thresholds"] = robot;

  const wp::MonitorParams p = wp::readParams(root);
  const wp::LabelSettings builtin;
  EXPECT_EQ(p.label("default").margin, 0.3);
  EXPECT_EQ(p.label("default").critical_distance, 0.1);
  EXPECT_EQ(p.label("a_person").margin, 0.3);  // inherited
  EXPECT_EQ(p.label("a_person").critical_distance, 0.1);
  EXPECT_EQ(p.label("a_person").warning_time, 2.0);
  EXPECT_EQ(p.label("a_person").critical_time, builtin.critical_time);
  EXPECT_EQ(p.label("forklift").margin, 0.5);
  EXPECT_EQ(p.label("unlisted").margin, 0.3);  // falls back to default
  EXPECT_EQ(p.robot_thresholds.warning_distance, 0.6);
  EXPECT_EQ(p.robot_thresholds.warning_time, builtin.warning_time);
}

TEST(RosParams, GrowthSettingsPerLabelInheritFromDefault) {
  XmlRpcValue def = dict();
  def["velocity_error"] = 0.2;
  XmlRpcValue person = dict();
  person["position_error"] = 0.1;
  person["velocity_error"] = 0.3;
  person["max_accel"] = 5;  // an integer is a number too
  person["max_speed"] = 2.0;
  XmlRpcValue labels = dict();
  labels["default"] = def;
  labels["person"] = person;
  labels["forklift"] = labelDict(0.5);
  const XmlRpcValue root = with("labels", labels);

  const wp::MonitorParams p = wp::readParams(root);
  EXPECT_EQ(p.label("person").position_error, 0.1);
  EXPECT_EQ(p.label("person").velocity_error, 0.3);
  EXPECT_EQ(p.label("person").max_accel, 5.0);
  EXPECT_EQ(p.label("person").max_speed, 2.0);
  EXPECT_EQ(p.label("forklift").velocity_error, 0.2);  // inherited from default
  EXPECT_EQ(p.label("forklift").max_accel, 0.0);
  EXPECT_EQ(p.label("unlisted").velocity_error, 0.2);
  EXPECT_TRUE(wp::validate(p).empty());
  EXPECT_TRUE(wp::unknownParams(root).empty());

  // A negative value reads, and validate() names it.
  const XmlRpcValue bad_root = with("labels", with("person", with("max_speed", -1.0)));
  bool named = false;
  for (const std::string& e : wp::validate(wp::readParams(bad_root))) {
    named = named || e.find("~labels/person/max_speed = -1") != std::string::npos;
  }
  EXPECT_TRUE(named);
}

// "person/head" in a YAML file reaches the node as the key "head" of "person" (the parameter
// server nests every '/', as rosparam and roslaunch load it): a sub-label inheriting from its
// parent, and the parent's own settings unharmed.
TEST(RosParams, PartLabelsWithASlashAreNestedSubLabels) {
  XmlRpcValue person = dict();
  person["margin"] = 0.2;
  person["max_speed"] = 1.6;
  XmlRpcValue hand = dict();
  hand["max_speed"] = 2.0;
  hand["size_x"] = 0.12;
  person["hand"] = hand;
  person["torso"] = dict();
  person["torso"]["size_x"] = 0.4;
  XmlRpcValue root = with("labels", with("person", person));

  const wp::MonitorParams p = wp::readParams(root);
  EXPECT_EQ(p.label("person").margin, 0.2);
  EXPECT_EQ(p.label("person").max_speed, 1.6);
  EXPECT_EQ(p.label("person/hand").max_speed, 2.0);
  EXPECT_EQ(p.label("person/hand").size_x, 0.12);
  EXPECT_EQ(p.label("person/hand").margin, 0.2);  // inherited from person
  EXPECT_EQ(p.label("person/torso").max_speed, 1.6);
  EXPECT_EQ(p.label("person/torso").size_x, 0.4);
  EXPECT_TRUE(wp::validate(p).empty());
  EXPECT_TRUE(wp::unknownParams(root).empty());

  // One key "person/hand" (a YAML file read without the parameter server): the same.
  XmlRpcValue flat = dict();
  flat["person"] = dict();
  flat["person"]["margin"] = 0.2;
  flat["person/hand"] = hand;
  const XmlRpcValue flat_root = with("labels", flat);
  const wp::MonitorParams q = wp::readParams(flat_root);
  EXPECT_EQ(q.label("person/hand").max_speed, 2.0);
  EXPECT_EQ(q.label("person/hand").margin, 0.2);

  // A scalar that is no setting is still refused by name.
  root["labels"]["person"]["hand"]["speed"] = 3.0;
  EXPECT_THROW(wp::readParams(root), std::exception);
}

TEST(RosParams, RobotBodiesWithOffsets) {
  XmlRpcValue offset = dict();
  offset["xyz"] = list({XmlRpcValue(0.1), XmlRpcValue(0), XmlRpcValue(-0.2)});
  offset["rpy"] = list({XmlRpcValue(0), XmlRpcValue(0), XmlRpcValue(M_PI / 2)});
  XmlRpcValue gripper = dict();
  gripper["name"] = str("gripper");
  gripper["frame"] = str("tool0");
  gripper["size"] = list({XmlRpcValue(0.2), XmlRpcValue(0.4), XmlRpcValue(1)});
  gripper["offset"] = offset;
  XmlRpcValue plain = dict();
  plain["name"] = str("post");
  plain["frame"] = str("base");
  plain["size"] = list({XmlRpcValue(1), XmlRpcValue(1), XmlRpcValue(2)});
  XmlRpcValue root = dict();
  root["robot_bodies"] = list({gripper, plain});

  const wp::MonitorParams p = wp::readParams(root);
  ASSERT_EQ(p.robot_bodies.size(), 2u);
  const wp::RobotBodySpec& g = p.robot_bodies[0];
  EXPECT_EQ(g.name, "gripper");
  EXPECT_EQ(g.frame, "tool0");
  EXPECT_TRUE(g.shape.half_extents.isApprox(Eigen::Vector3d(0.1, 0.2, 0.5)));
  EXPECT_TRUE(g.offset.translation().isApprox(Eigen::Vector3d(0.1, 0, -0.2)));
  // Yaw a quarter turn: x goes to y, y to -x, z stays.
  EXPECT_TRUE((g.offset.linear() * Eigen::Vector3d::UnitX()).isApprox(Eigen::Vector3d::UnitY()));
  EXPECT_TRUE((g.offset.linear() * Eigen::Vector3d::UnitY()).isApprox(-Eigen::Vector3d::UnitX()));
  EXPECT_TRUE((g.offset.linear() * Eigen::Vector3d::UnitZ()).isApprox(Eigen::Vector3d::UnitZ()));
  EXPECT_TRUE(p.robot_bodies[1].offset.isApprox(Eigen::Isometry3d::Identity()));
}

TEST(RosParams, EachWrongTypeOrStructureIsNamed) {
  struct Case {
    const char* expected;  // the message must contain this
    std::function<void(XmlRpcValue&)> set;
  };
  const Case cases[] = {
      {"~rate: must be a number", [](XmlRpcValue& r) { r["rate"] = str("fast"); }},
      {"~horizon: must be a number", [](XmlRpcValue& r) { r["horizon"] = true; }},
      {"~fixed_frame: must be a string", [](XmlRpcValue& r) { r["fixed_frame"] = 3; }},
      {"~use_robot_description: must be true or false",
       [](XmlRpcValue& r) { r["use_robot_description"] = 1; }},
      {"~publish_markers: must be true or false",
       [](XmlRpcValue& r) { r["publish_markers"] = str("yes"); }},
      {"~max_tracks: must be an integer", [](XmlRpcValue& r) { r["max_tracks"] = 2.5; }},
      {"~input_topics: must be a list of strings",
       [](XmlRpcValue& r) { r["input_topics"] = str("/boxes"); }},
      {"~input_topics: must be a string",
       [](XmlRpcValue& r) { r["input_topics"] = list({XmlRpcValue(1)}); }},
      {"~ignore_pairs: must be a list of [selector, selector]",
       [](XmlRpcValue& r) { r["ignore_pairs"] = str("*"); }},
      {"~check_pairs: entry 1 must be a list of two selectors",
       [](XmlRpcValue& r) {
         r["check_pairs"] = list({list({str("*"), str("*")}), list({str("*")})});
       }},
      {"~labels: must be a dictionary of labels", [](XmlRpcValue& r) { r["labels"] = str("x"); }},
      {"~labels/person: must be a dictionary",
       [](XmlRpcValue& r) { r["labels"] = with("person", 0.2); }},
      {"~labels/person/margin: must be a number",
       [](XmlRpcValue& r) { r["labels"] = with("person", with("margin", str("big"))); }},
      {"~labels/default/colour: unknown setting",
       [](XmlRpcValue& r) { r["labels"] = with("default", with("colour", 1.0)); }},
      {"~labels/person/max_accel: must be a number",
       [](XmlRpcValue& r) { r["labels"] = with("person", with("max_accel", str("fast"))); }},
      {"~robot_thresholds/velocity_error: unknown setting",
       [](XmlRpcValue& r) { r["robot_thresholds"] = with("velocity_error", 0.3); }},
      {"~robot_thresholds/margin: unknown setting",
       [](XmlRpcValue& r) { r["robot_thresholds"] = with("margin", 0.3); }},
      {"~robot_thresholds/critical_time: must be a number",
       [](XmlRpcValue& r) { r["robot_thresholds"] = with("critical_time", list({})); }},
      {"~robot_bodies: must be a list", [](XmlRpcValue& r) { r["robot_bodies"] = dict(); }},
      {"~ssm: must be a dictionary", [](XmlRpcValue& r) { r["ssm"] = 1.0; }},
      {"~ssm/hold_time: must be a number",
       [](XmlRpcValue& r) { r["ssm"] = with("hold_time", str("long")); }},
      {"~ssm/enabled: must be true or false",
       [](XmlRpcValue& r) { r["ssm"] = with("enabled", str("yes")); }},
      {"~ssm/stop_event_topics: must be a list of strings",
       [](XmlRpcValue& r) { r["ssm"] = with("stop_event_topics", str("/stop")); }},
      {"~cycle_trigger: must be a string", [](XmlRpcValue& r) { r["cycle_trigger"] = 1; }},
      {"~robot_bodies[0]: must be a dictionary",
       [](XmlRpcValue& r) { r["robot_bodies"] = list({str("gripper")}); }},
      {"~robot_bodies[0]: needs name, frame and size",
       [](XmlRpcValue& r) {
         XmlRpcValue b = dict();
         b["name"] = str("g");
         b["frame"] = str("f");
         r["robot_bodies"] = list({b});
       }},
      {"~robot_bodies[0]/size: must be a list of 3 numbers",
       [](XmlRpcValue& r) {
         XmlRpcValue b = dict();
         b["name"] = str("g");
         b["frame"] = str("f");
         b["size"] = list({XmlRpcValue(1), XmlRpcValue(2)});
         r["robot_bodies"] = list({b});
       }},
      {"~robot_bodies[0]/name: must be a string",
       [](XmlRpcValue& r) {
         XmlRpcValue b = dict();
         b["name"] = 7;
         b["frame"] = str("f");
         b["size"] = list({XmlRpcValue(1), XmlRpcValue(2), XmlRpcValue(3)});
         r["robot_bodies"] = list({b});
       }},
      {"~robot_bodies[0]/offset/rpy: must be a list of 3 numbers",
       [](XmlRpcValue& r) {
         XmlRpcValue o = dict();
         o["rpy"] = list({XmlRpcValue(0), XmlRpcValue(0)});
         XmlRpcValue b = dict();
         b["name"] = str("g");
         b["frame"] = str("f");
         b["size"] = list({XmlRpcValue(1), XmlRpcValue(2), XmlRpcValue(3)});
         b["offset"] = o;
         r["robot_bodies"] = list({b});
       }},
  };
  for (const Case& c : cases) {
    XmlRpcValue root = dict();
    c.set(root);
    const std::string error = errorOf(root);
    EXPECT_NE(error.find(c.expected), std::string::npos)
        << "expected '" << c.expected << "', got '" << error << "'";
  }
}

TEST(RosParams, TheNamespaceMustBeADictionary) {
  EXPECT_NE(errorOf(XmlRpcValue(3)).find("must be a dictionary"), std::string::npos);
  EXPECT_NE(errorOf(list({XmlRpcValue(1)})).find("must be a dictionary"), std::string::npos);
}

TEST(RosParams, UnknownKeysAreNamedWithTheClosestKnownOne) {
  XmlRpcValue root = dict();
  root["horizon"] = 2.0;
  root["horizen"] = 3.0;           // misspelled
  root["trak_timeout"] = 1.0;      // misspelled
  root["colour"] = str("red");     // nothing like it
  root["default_margin"] = 0.1;    // dynamic_reconfigure's own key: known
  root["diagnostic_period"] = 1.0; // diagnostic_updater's: known
  root["labels"] = dict();
  root["labels"]["anything"] = dict();  // label names are free
  XmlRpcValue body = dict();
  body["name"] = str("g");
  body["frame"] = str("tool0");
  body["size"] = list({0.1, 0.1, 0.1});
  body["ofset"] = dict();
  root["robot_bodies"] = list({body});
  root["ssm"] = dict();
  root["ssm"]["hold_time"] = 1.0;
  root["ssm"]["stoping_time"] = 1.0;   // misspelled
  root["ssm_hold_time"] = 1.0;         // dynamic_reconfigure's own key: known
  const std::vector<std::string> lines = wp::unknownParams(root);
  ASSERT_EQ(lines.size(), 5u) << ::testing::PrintToString(lines);
  auto has = [&](const std::string& text) {
    for (const std::string& l : lines) {
      if (l.find(text) != std::string::npos) return true;
    }
    return false;
  };
  EXPECT_TRUE(has("~horizen: unknown parameter, not used (did you mean ~horizon?)"));
  EXPECT_TRUE(has("~trak_timeout: unknown parameter, not used (did you mean ~track_timeout?)"));
  EXPECT_TRUE(has("~colour: unknown parameter, not used"));
  EXPECT_FALSE(has("~colour: unknown parameter, not used (did you mean"));
  EXPECT_TRUE(has("~robot_bodies[0]/ofset: unknown parameter, not used (did you mean "
                  "~robot_bodies[0]/offset?)"));
  EXPECT_TRUE(has("~ssm/stoping_time: unknown parameter, not used (did you mean ~ssm/stopping_time?)"));
  EXPECT_TRUE(wp::unknownParams(XmlRpcValue()).empty());
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
