// The parameter table's rules: names unique, every default inside its row's range,
// validate() applying each row's range with both ends included, and keepWiring() keeping
// exactly the wiring that Monitor::setParams restored by hand before the table (its 12
// fields) plus the four the node also fixes at start-up.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "workspace_proximity/rules/param_table.hpp"

namespace wp = workspace_proximity;

namespace {

// Whether validate() refuses `name`'s value for its range ("~name = value: must be in [").
bool rangeRefused(const wp::MonitorParams& p, const std::string& name) {
  for (const std::string& e : wp::validate(p)) {
    if (e.rfind("~" + name + " = ", 0) == 0 && e.find(": must be in [") != std::string::npos) {
      return true;
    }
  }
  return false;
}

double& numberIn(const wp::ParamRow& row, wp::MonitorParams& p) { return row.member.number(p); }

// Sets a number or integer row to `value` (integers: rounded).
void setNumber(const wp::ParamRow& row, wp::MonitorParams& p, double value) {
  if (row.member.type == wp::ParamType::kInteger) {
    row.member.integer(p) = static_cast<int>(value);
  } else {
    numberIn(row, p) = value;
  }
}

bool isNumber(const wp::ParamRow& row) {
  return row.member.type == wp::ParamType::kNumber || row.member.type == wp::ParamType::kInteger;
}

}  // namespace

TEST(ParamTable, NamesAreUniqueAndBoundsNameRowsOfTheSameUnit) {
  std::set<std::string> names;
  for (const wp::ParamRow& row : wp::paramTable()) {
    EXPECT_TRUE(names.insert(row.name).second) << row.name << " twice";
    EXPECT_NE(std::string(row.doc), "") << row.name;
    ASSERT_NE(row.member.copy, nullptr) << row.name;
    EXPECT_EQ(wp::findParam(row.name), &row);
    if (row.at_most != nullptr) {
      const wp::ParamRow* bound = wp::findParam(row.at_most);
      ASSERT_NE(bound, nullptr) << row.name << " at most " << row.at_most;
      EXPECT_TRUE(isNumber(*bound)) << row.name;
      EXPECT_EQ(std::string(bound->unit), row.unit) << row.name;
    }
  }
  std::set<std::string> keys;
  for (const wp::LabelRow& row : wp::labelTable()) {
    EXPECT_TRUE(keys.insert(row.key).second) << row.key << " twice";
    EXPECT_NE(std::string(row.doc), "") << row.key;
    EXPECT_EQ(wp::findLabelSetting(row.key), &row);
    if (row.at_most != nullptr) {
      const wp::LabelRow* bound = wp::findLabelSetting(row.at_most);
      ASSERT_NE(bound, nullptr) << row.key;
      EXPECT_EQ(std::string(bound->unit), row.unit) << row.key;
      EXPECT_EQ(bound->track_only, row.track_only) << row.key;
    }
  }
  EXPECT_EQ(wp::findParam("horizen"), nullptr);
  EXPECT_EQ(wp::findLabelSetting("colour"), nullptr);
}

TEST(ParamTable, TheRowsTypesFollowTheirMembers) {
  // The accessor set matches the type the member deduced, for a few rows of each type.
  wp::MonitorParams p;
  EXPECT_EQ(wp::findParam("horizon")->member.type, wp::ParamType::kNumber);
  EXPECT_EQ(&wp::findParam("horizon")->member.number(p), &p.horizon);
  EXPECT_EQ(&wp::findParam("ssm/hold_time")->member.number(p), &p.ssm.hold_time);
  EXPECT_EQ(wp::findParam("max_tracks")->member.type, wp::ParamType::kInteger);
  EXPECT_EQ(&wp::findParam("max_tracks")->member.integer(p), &p.max_tracks);
  EXPECT_EQ(&wp::findParam("ssm/enabled")->member.flag(p), &p.ssm.enabled);
  EXPECT_EQ(&wp::findParam("fixed_frame")->member.text(p), &p.fixed_frame);
  EXPECT_EQ(&wp::findParam("ssm/labels")->member.names(p), &p.ssm.labels);
  EXPECT_EQ(&wp::findParam("check_pairs")->member.pairs(p), &p.check_pairs);
  EXPECT_EQ(wp::findParam("robot_bodies")->member.number, nullptr);
  // ~detection_tracker/: each row sets its own member.
  EXPECT_EQ(&wp::findParam("detection_tracker/gate_chi2")->member.number(p),
            &p.detection_tracker.gate_chi2);
  EXPECT_EQ(&wp::findParam("detection_tracker/gate_distance")->member.number(p),
            &p.detection_tracker.gate_distance);
  EXPECT_EQ(&wp::findParam("detection_tracker/confirm_hits")->member.integer(p),
            &p.detection_tracker.confirm_hits);
  EXPECT_EQ(&wp::findParam("detection_tracker/max_misses")->member.integer(p),
            &p.detection_tracker.max_misses);
  EXPECT_EQ(&wp::findParam("detection_tracker/timeout")->member.number(p),
            &p.detection_tracker.timeout);
  EXPECT_EQ(&wp::findParam("detection_tracker/known_velocity_error")->member.number(p),
            &p.detection_tracker.known_velocity_error);
  // The structures are the three with readers of their own (readParams).
  std::set<std::string> structures;
  for (const wp::ParamRow& row : wp::paramTable()) {
    if (row.member.type == wp::ParamType::kStructure) structures.insert(row.name);
  }
  EXPECT_EQ(structures, (std::set<std::string>{"robot_bodies", "labels", "robot_thresholds"}));
}

TEST(ParamTable, EveryDefaultIsInsideItsRange) {
  const wp::MonitorParams defaults;
  for (const wp::ParamRow& row : wp::paramTable()) {
    if (!isNumber(row)) continue;
    const double value = wp::numberOf(row, defaults);
    EXPECT_LE(row.min, value) << row.name;
    EXPECT_LE(value, row.max) << row.name;
    EXPECT_LT(row.min, row.max) << row.name;
  }
  const wp::LabelSettings label;
  for (const wp::LabelRow& row : wp::labelTable()) {
    EXPECT_LE(row.min, label.*row.member) << row.key;
    EXPECT_LE(label.*row.member, row.max) << row.key;
  }
  EXPECT_TRUE(wp::validate(defaults).empty());
}

TEST(ParamTable, ValidateAppliesEachRangeWithBothEndsIncluded) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (const wp::ParamRow& row : wp::paramTable()) {
    if (!isNumber(row)) continue;
    const bool integer = row.member.type == wp::ParamType::kInteger;
    const wp::MonitorParams defaults;
    const double hi = row.at_most != nullptr ? wp::numberOf(*wp::findParam(row.at_most), defaults)
                                             : row.max;
    // The next value outside each end: one for an integer, the next double otherwise.
    const double below = integer ? row.min - 1 : std::nextafter(row.min, -inf);
    const double above = integer ? hi + 1 : std::nextafter(hi, inf);
    for (double ok : {row.min, hi}) {
      wp::MonitorParams p;
      setNumber(row, p, ok);
      EXPECT_FALSE(rangeRefused(p, row.name)) << row.name << " = " << ok;
    }
    for (double bad : {below, above}) {
      wp::MonitorParams p;
      setNumber(row, p, bad);
      EXPECT_TRUE(rangeRefused(p, row.name)) << row.name << " = " << bad;
    }
    if (!integer) {
      for (double bad : {nan, inf, -inf}) {
        wp::MonitorParams p;
        setNumber(row, p, bad);
        EXPECT_TRUE(rangeRefused(p, row.name)) << row.name << " = " << bad;
      }
    }
  }
}

TEST(ParamTable, ValidateAppliesEachLabelRangeToLabelsAndTheRobotsThresholds) {
  const double inf = std::numeric_limits<double>::infinity();
  const wp::LabelSettings defaults;
  for (const wp::LabelRow& row : wp::labelTable()) {
    const double hi = row.at_most != nullptr ? defaults.*wp::findLabelSetting(row.at_most)->member
                                             : row.max;
    for (bool robot : {false, true}) {
      const std::string name = robot ? std::string("robot_thresholds/") + row.key
                                     : std::string("labels/person/") + row.key;
      auto settings = [&](wp::MonitorParams& p) -> wp::LabelSettings& {
        return robot ? p.robot_thresholds : p.labels["person"];
      };
      for (double ok : {row.min, hi}) {
        wp::MonitorParams p;
        settings(p).*row.member = ok;
        EXPECT_FALSE(rangeRefused(p, name)) << name << " = " << ok;
      }
      for (double bad : {std::nextafter(row.min, -inf), std::nextafter(hi, inf)}) {
        wp::MonitorParams p;
        settings(p).*row.member = bad;
        // The robot has no track-only settings: never checked there.
        EXPECT_EQ(rangeRefused(p, name), !(robot && row.track_only)) << name << " = " << bad;
      }
    }
  }
}

TEST(ParamTable, KeepWiringKeepsWhatSetParamsRestoredByHand) {
  // Monitor::setParams restored these 12 by hand before the table; require_all_links,
  // use_joint_states and trajectory_topic are fixed at start-up by the node too, and so is
  // audit_log (the file opened at start-up), perception_status_topics (subscribed then) and
  // skeleton_marker_topics (how a topic is read), and detection_tracker/ (each detection
  // input's tracker is made at its first message).
  const std::set<std::string> wiring = {
      "fixed_frame", "input_topics", "use_robot_description", "robot_description_param",
      "robot_bodies", "cycle_trigger", "trigger_source", "ssm/enabled",
      "ssm/stop_trajectory_topics", "ssm/stop_event_topics", "ssm/cmd_vel_in", "ssm/cmd_vel_out",
      "ssm/halt_service", "ssm/halt_topic", "require_all_links", "use_joint_states", "trajectory_topic",
      "audit_log", "perception_status_topics", "skeleton_marker_topics",
      "detection_tracker/gate_chi2", "detection_tracker/gate_distance",
      "detection_tracker/confirm_hits", "detection_tracker/max_misses",
      "detection_tracker/timeout", "detection_tracker/known_velocity_error"};
  std::set<std::string> wiring_rows;
  for (const wp::ParamRow& row : wp::paramTable()) {
    if (row.tuning == wp::Tuning::kWiring) wiring_rows.insert(row.name);
  }
  EXPECT_EQ(wiring_rows, wiring);

  // Each row changed alone: keepWiring undoes the change exactly for the wiring rows.
  for (const wp::ParamRow& row : wp::paramTable()) {
    const wp::MonitorParams built;
    wp::MonitorParams next;
    const wp::ParamMember& m = row.member;
    // Whether `p`'s member differs from `built`'s.
    auto differs = [&](wp::MonitorParams& p) {
      wp::MonitorParams& b = const_cast<wp::MonitorParams&>(built);
      switch (m.type) {
        case wp::ParamType::kNumber: return m.number(p) != m.number(b);
        case wp::ParamType::kInteger: return m.integer(p) != m.integer(b);
        case wp::ParamType::kBool: return m.flag(p) != m.flag(b);
        case wp::ParamType::kString: return m.text(p) != m.text(b);
        case wp::ParamType::kStringList: return m.names(p) != m.names(b);
        case wp::ParamType::kPairs: return m.pairs(p) != m.pairs(b);
        case wp::ParamType::kStructure: break;
      }
      const std::string name = row.name;
      if (name == "robot_bodies") return p.robot_bodies.size() != b.robot_bodies.size();
      if (name == "labels") return p.labels.size() != b.labels.size();
      return p.robot_thresholds.warning_time != b.robot_thresholds.warning_time;
    };
    switch (m.type) {
      case wp::ParamType::kNumber: m.number(next) += 0.5; break;
      case wp::ParamType::kInteger: m.integer(next) += 1; break;
      case wp::ParamType::kBool: m.flag(next) = !m.flag(next); break;
      case wp::ParamType::kString: m.text(next) += "x"; break;
      case wp::ParamType::kStringList: m.names(next).push_back("x"); break;
      case wp::ParamType::kPairs: m.pairs(next).push_back({"*", "*"}); break;
      case wp::ParamType::kStructure:
        if (std::string(row.name) == "robot_bodies") {
          next.robot_bodies.emplace_back();
        } else if (std::string(row.name) == "labels") {
          next.labels["x"] = wp::LabelSettings();
        } else {
          next.robot_thresholds.warning_time += 0.5;
        }
        break;
    }
    ASSERT_TRUE(differs(next)) << row.name;
    wp::keepWiring(built, &next);
    EXPECT_EQ(differs(next), wiring.count(row.name) == 0) << row.name;
  }
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
