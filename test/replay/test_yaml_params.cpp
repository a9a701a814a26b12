// The replay's YAML configuration: scalars typed as roslaunch (PyYAML, YAML 1.1) types them,
// nesting, merging several files as <rosparam command="load"> does, errors naming the file or
// the parameter; and the shipped configuration files read through the node's reader.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "params_expectations.hpp"  // test/shared
#include "workspace_proximity/replay/yaml_params.hpp"
#include "workspace_proximity/ros/ros_params.hpp"

namespace wp = workspace_proximity;
using XmlRpc::XmlRpcValue;

namespace {

XmlRpcValue value(const std::string& scalar) {
  XmlRpcValue root = wp::yamlToParams("k: " + scalar + "\n", "test.yaml");
  return root["k"];
}

std::string errorOf(const std::string& yaml) {
  try {
    wp::yamlToParams(yaml, "test.yaml");
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// The expected types and values are what PyYAML 6.0's safe_load (which roslaunch uses) gives
// for the same text; they were taken from it (python3 -c "import yaml; yaml.safe_load(...)").
TEST(YamlParams, PlainScalarsAreTypedAsRoslaunchTypesThem) {
  struct Int { const char* text; int value; };
  for (const Int& c : {Int{"1", 1}, Int{"-1", -1}, Int{"+1", 1}, Int{"0x1F", 31}, Int{"017", 15},
                       Int{"0b101", 5}, Int{"1_000", 1000}, Int{"0", 0}, Int{"00", 0},
                       Int{"1:30", 90}, Int{"2147483647", 2147483647}, Int{"1:5", 65},
                       Int{"+0x1F", 31}, Int{"-0b11", -3}, Int{"1__0", 10}, Int{"0_7", 7},
                       Int{"-0", 0}, Int{"12:30:45", 45045}, Int{"-1:30", -90}, Int{"010", 8}}) {
    const XmlRpcValue v = value(c.text);
    ASSERT_EQ(v.getType(), XmlRpcValue::TypeInt) << c.text;
    EXPECT_EQ(static_cast<int>(const_cast<XmlRpcValue&>(v)), c.value) << c.text;
  }
  struct Double { const char* text; double value; };
  for (const Double& c : {Double{"1.0e-3", 0.001}, Double{"1.0e+3", 1000.0}, Double{".5", 0.5},
                          Double{"1.", 1.0}, Double{"3.", 3.0}, Double{"30.0", 30.0},
                          Double{"-2.5", -2.5}, Double{"1.5_0", 1.5}, Double{"1_0.5", 10.5},
                          Double{"1:30.5", 90.5}, Double{"1.0E+3", 1000.0}, Double{".5e-3", 0.0005},
                          Double{"0.", 0.0}}) {
    const XmlRpcValue v = value(c.text);
    ASSERT_EQ(v.getType(), XmlRpcValue::TypeDouble) << c.text;
    EXPECT_DOUBLE_EQ(static_cast<double>(const_cast<XmlRpcValue&>(v)), c.value) << c.text;
  }
  for (const char* text : {".inf", "+.inf", "-.Inf", ".NaN", ".nan"}) {
    const XmlRpcValue v = value(text);
    ASSERT_EQ(v.getType(), XmlRpcValue::TypeDouble) << text;
    const double d = static_cast<double>(const_cast<XmlRpcValue&>(v));
    if (text[1] == 'n' || text[1] == 'N') {
      EXPECT_TRUE(std::isnan(d)) << text;
    } else {
      EXPECT_EQ(d, text[0] == '-' ? -INFINITY : INFINITY) << text;
    }
  }
  struct Bool { const char* text; bool value; };
  for (const Bool& c : {Bool{"true", true}, Bool{"True", true}, Bool{"TRUE", true}, Bool{"yes", true},
                        Bool{"on", true}, Bool{"No", false}, Bool{"OFF", false}, Bool{"false", false}}) {
    const XmlRpcValue v = value(c.text);
    ASSERT_EQ(v.getType(), XmlRpcValue::TypeBoolean) << c.text;
    EXPECT_EQ(static_cast<bool>(const_cast<XmlRpcValue&>(v)), c.value) << c.text;
  }
  // YAML 1.1 as PyYAML reads it: these are strings, not numbers or booleans.
  for (const char* text : {"1e-3", "1.e3", "-.5", "+.5", "inf", "NaN", "tRue", "y", "n", "abc", "09",
                           "0o17", "world", "1:60", "0b", "0x", "1e+3", "1.0e3", "_1", "-.nan",
                           ".5e3", "1.2.3", "0:30", "1:030"}) {
    const XmlRpcValue v = value(text);
    ASSERT_EQ(v.getType(), XmlRpcValue::TypeString) << text;
    EXPECT_EQ(static_cast<std::string>(const_cast<XmlRpcValue&>(v)), text);
  }
  // Quoted or tagged.
  EXPECT_EQ(value("\"30\"").getType(), XmlRpcValue::TypeString);
  EXPECT_EQ(value("'true'").getType(), XmlRpcValue::TypeString);
  EXPECT_EQ(value("!!str 5").getType(), XmlRpcValue::TypeString);
  EXPECT_EQ(value("!!float 5").getType(), XmlRpcValue::TypeDouble);
}

TEST(YamlParams, Nesting) {
  const XmlRpcValue root = wp::yamlToParams(
      "labels:\n"
      "  person: {margin: 0.2, warning_time: 1}\n"
      "pairs:\n"
      "  - [\"label:person\", \"*\"]\n"
      "  - [a, b]\n"
      "bodies:\n"
      "  - name: g\n"
      "    size: [0.1, 0.2, 3]\n"
      "empty_list: []\n"
      "empty_dict: {}\n",
      "test.yaml");
  ASSERT_EQ(root.getType(), XmlRpcValue::TypeStruct);
  const XmlRpcValue& person = root["labels"]["person"];
  ASSERT_EQ(person.getType(), XmlRpcValue::TypeStruct);
  EXPECT_EQ(person["margin"].getType(), XmlRpcValue::TypeDouble);
  EXPECT_EQ(person["warning_time"].getType(), XmlRpcValue::TypeInt);
  const XmlRpcValue& pairs = root["pairs"];
  ASSERT_EQ(pairs.getType(), XmlRpcValue::TypeArray);
  ASSERT_EQ(pairs.size(), 2);
  EXPECT_EQ(static_cast<std::string>(const_cast<XmlRpcValue&>(pairs[0][0])), "label:person");
  EXPECT_EQ(static_cast<std::string>(const_cast<XmlRpcValue&>(pairs[1][1])), "b");
  const XmlRpcValue& size = root["bodies"][0]["size"];
  ASSERT_EQ(size.size(), 3);
  EXPECT_EQ(size[2].getType(), XmlRpcValue::TypeInt);
  EXPECT_EQ(root["empty_list"].getType(), XmlRpcValue::TypeArray);
  EXPECT_EQ(root["empty_list"].size(), 0);
  EXPECT_EQ(root["empty_dict"].getType(), XmlRpcValue::TypeStruct);
  EXPECT_TRUE(wp::yamlToParams("# only a comment\n", "c.yaml").getType() == XmlRpcValue::TypeStruct);
}

TEST(YamlParams, MergeIsKeyByKeyForDictionariesAndReplacesTheRest) {
  XmlRpcValue base = wp::yamlToParams(
      "rate: 30\nlabels: {default: {margin: 0.1, warning_time: 1.0}, person: {margin: 0.2}}\n"
      "ignore_pairs: [[a, b], [c, d]]\n",
      "base.yaml");
  wp::mergeParams(&base, wp::yamlToParams(
                             "rate: 10.0\nlabels: {default: {margin: 0.3}, forklift: {margin: 0.5}}\n"
                             "ignore_pairs: [[e, f]]\n",
                             "overlay.yaml"));
  EXPECT_EQ(static_cast<double>(base["rate"]), 10.0);
  EXPECT_EQ(static_cast<double>(base["labels"]["default"]["margin"]), 0.3);
  EXPECT_EQ(static_cast<double>(base["labels"]["default"]["warning_time"]), 1.0);  // kept
  EXPECT_EQ(static_cast<double>(base["labels"]["person"]["margin"]), 0.2);         // kept
  EXPECT_EQ(static_cast<double>(base["labels"]["forklift"]["margin"]), 0.5);       // added
  ASSERT_EQ(base["ignore_pairs"].size(), 1);  // lists are replaced, not appended
  EXPECT_EQ(static_cast<std::string>(base["ignore_pairs"][0][0]), "e");
}

TEST(YamlParams, ErrorsNameTheFileOrTheParameter) {
  // Syntax: file, line and column.
  const std::string syntax = errorOf("rate: 30\nlabels: {default: [1, 2}\n");
  EXPECT_NE(syntax.find("test.yaml:2:"), std::string::npos) << syntax;
  EXPECT_NE(syntax.find("YAML syntax error"), std::string::npos) << syntax;
  // Values the parameter server cannot hold, named as the node names parameters.
  const std::string null_value = errorOf("labels:\n  person:\n    margin:\n");
  EXPECT_NE(null_value.find("~labels/person/margin: has no value"), std::string::npos) << null_value;
  EXPECT_NE(null_value.find("test.yaml line 3"), std::string::npos) << null_value;
  const std::string big = errorOf("max_tracks: 3000000000\n");
  EXPECT_NE(big.find("~max_tracks: integer 3000000000 does not fit in 32 bits"), std::string::npos) << big;
  const std::string in_list = errorOf("input_topics: [a, ~]\n");
  EXPECT_NE(in_list.find("~input_topics[1]: has no value"), std::string::npos) << in_list;
  const std::string tag = errorOf("rate: !degrees 30\n");
  EXPECT_NE(tag.find("~rate: unsupported tag"), std::string::npos) << tag;
  EXPECT_NE(errorOf("- 1\n- 2\n").find("must be a dictionary"), std::string::npos);
  try {
    wp::loadYamlParams({"/nonexistent/config.yaml"});
    FAIL() << "no error for a missing file";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/config.yaml: cannot read"), std::string::npos);
  }
}

TEST(YamlParams, TheNodesReaderGivesTheNodesMessages) {
  // A string where a number is expected: the node says "~rate: must be a number" for the
  // same file loaded by roslaunch (test/ros/test_invalid_params.py checks the node's side).
  try {
    wp::readParams(wp::yamlToParams("rate: fast\n", "c.yaml"));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "~rate: must be a number");
  }
  // `1e-3` is a string to roslaunch too, so it fails the same way.
  try {
    wp::readParams(wp::yamlToParams("horizon: 1e-3\n", "c.yaml"));
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), "~horizon: must be a number");
  }
  const wp::MonitorParams p = wp::readParams(wp::yamlToParams("rate: -1\n", "c.yaml"));
  const std::vector<std::string> errors = wp::validate(p);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].rfind("~rate = -1: must be in", 0), 0u) << errors[0];
}

// ~detection_tracker/ (the detections' multi-object tracker) read through the node's reader,
// each value as written, and each refused by validate() out of its range, by name.
TEST(YamlParams, TheDetectionTrackerGroupIsReadAndChecked) {
  const wp::MonitorParams p = wp::readParams(wp::yamlToParams(
      "detection_tracker:\n  gate_chi2: 9.5\n  gate_distance: 0.75\n  confirm_hits: 1\n"
      "  max_misses: 5\n  timeout: 0.4\n  known_velocity_error: 0.3\n",
      "c.yaml"));
  EXPECT_EQ(p.detection_tracker.gate_chi2, 9.5);
  EXPECT_EQ(p.detection_tracker.gate_distance, 0.75);
  EXPECT_EQ(p.detection_tracker.confirm_hits, 1);
  EXPECT_EQ(p.detection_tracker.max_misses, 5);
  EXPECT_EQ(p.detection_tracker.timeout, 0.4);
  EXPECT_EQ(p.detection_tracker.known_velocity_error, 0.3);
  EXPECT_TRUE(wp::validate(p).empty());
  const std::pair<const char*, const char*> bad[] = {
      {"gate_chi2", "0.05"},   {"gate_distance", "200.0"},        {"confirm_hits", "0"},
      {"max_misses", "1001"},  {"timeout", "0.0"},                {"known_velocity_error", "0.0"}};
  for (const auto& [key, text] : bad) {
    const std::string yaml = std::string("detection_tracker:\n  ") + key + ": " + text + "\n";
    const std::vector<std::string> errors =
        wp::validate(wp::readParams(wp::yamlToParams(yaml, "c.yaml")));
    ASSERT_EQ(errors.size(), 1u) << key;
    EXPECT_EQ(errors[0].rfind(std::string("~detection_tracker/") + key + " = ", 0), 0u)
        << errors[0];
  }
}

TEST(YamlParams, TheShippedConfigurationFiles) {
  const std::string dir = WP_SOURCE_DIR "/config/";
  // The default file states the defaults of the struct.
  const wp::MonitorParams defaults;
  const wp::MonitorParams p = wp::readParams(wp::loadYamlParams({dir + "proximity_monitor.yaml"}));
  EXPECT_TRUE(wp::validate(p).empty());
  wp_test::expectSameScalars(p, defaults);
  EXPECT_TRUE(p.ignore_pairs.empty());
  EXPECT_EQ(p.label("person").margin, 0.20);
  // The documented bounds of people (docs/node.md, "Tracked objects within bounds"); other labels
  // keep the constant-velocity prediction.
  EXPECT_EQ(p.label("person").position_error, 0.05);
  EXPECT_EQ(p.label("person").velocity_error, 0.3);
  EXPECT_EQ(p.label("person").max_accel, 4.0);
  EXPECT_EQ(p.label("person").max_speed, 2.0);
  EXPECT_EQ(p.label("forklift").velocity_error, 0.0);
  EXPECT_EQ(p.label("default").max_accel, 0.0);
  EXPECT_EQ(p.label("forklift").critical_time, 1.0);
  EXPECT_EQ(p.robot_thresholds.warning_distance, 0.3);
  // The demo's overlay on top, as demo.launch loads them.
  const wp::MonitorParams demo = wp::readParams(
      wp::loadYamlParams({dir + "proximity_monitor.yaml", dir + "demo_monitor.yaml"}));
  EXPECT_TRUE(wp::validate(demo).empty());
  ASSERT_EQ(demo.ignore_pairs.size(), 1u);
  EXPECT_EQ(demo.ignore_pairs[0].first, "label:person");
  EXPECT_EQ(demo.ignore_pairs[0].second, "label:person");
  EXPECT_EQ(demo.label("person").margin, 0.20);  // the base file's, kept
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
