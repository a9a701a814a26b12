// The configuration's fingerprint (config_fingerprint.hpp): every row of the parameter table,
// every label setting, every robot threshold and every field of an extra robot body changes it
// (the rows are walked here, by their types, independently of the canonical text); equal
// configurations give equal fingerprints whatever order their labels were given in; FNV-1a 64
// against the published test vectors; values cannot forge one another's lines.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "workspace_proximity/rules/config_fingerprint.hpp"
#include "workspace_proximity/rules/param_table.hpp"

namespace wp = workspace_proximity;

namespace {

// A configuration with something in every list and structure, so that changing an element is
// possible for each.
wp::MonitorParams populated() {
  wp::MonitorParams p;
  p.input_topics = {"a", "b"};
  p.skeleton_marker_topics = {"a"};
  p.perception_status_topics = {"perception_status"};
  p.ignore_pairs = {{"label:person", "label:person"}};
  p.check_pairs = {{"id:gripper", "id:base_link"}};
  p.labels["person"] = wp::LabelSettings();
  p.labels["person"].margin = 0.3;
  wp::RobotBodySpec body;
  body.name = "pillar";
  body.frame = "base_link";
  body.shape = wp::Shape::box(Eigen::Vector3d(0.5, 0.5, 0.5));
  p.robot_bodies.push_back(body);
  p.ssm.labels = {"person"};
  p.ssm.stop_trajectory_topics = {"stop"};
  p.ssm.stop_event_topics = {"event"};
  return p;
}

// The next double above `v` (the smallest change there is).
double bump(double v) { return std::nextafter(v, std::numeric_limits<double>::infinity()); }

// Expects `changed` to differ from `base` in fingerprint, and configChanges to name `what`.
void expectSeen(const wp::MonitorParams& base, const wp::MonitorParams& changed,
                const std::string& what) {
  EXPECT_NE(wp::configFingerprint(base), wp::configFingerprint(changed)) << what;
  const std::vector<std::string> changes = wp::configChanges(base, changed);
  ASSERT_FALSE(changes.empty()) << what;
  bool named = false;
  for (const std::string& c : changes) named = named || c.rfind(what, 0) == 0;
  EXPECT_TRUE(named) << what << ": " << changes.front();
}

}  // namespace

TEST(ConfigFingerprint, IsFnv1a64AsPublished) {
  // The FNV authors' test vectors (64-bit FNV-1a).
  EXPECT_EQ(wp::hex64(wp::fnv1a64("")), "cbf29ce484222325");
  EXPECT_EQ(wp::hex64(wp::fnv1a64("a")), "af63dc4c8601ec8c");
  EXPECT_EQ(wp::hex64(wp::fnv1a64("foobar")), "85944171f73967e8");
  const std::string f = wp::configFingerprint(wp::MonitorParams());
  EXPECT_EQ(f.size(), 16u);
  EXPECT_EQ(f.find_first_not_of("0123456789abcdef"), std::string::npos) << f;
}

TEST(ConfigFingerprint, EveryRowOfTheTableChangesIt) {
  const wp::MonitorParams base = populated();
  int rows = 0;
  for (const wp::ParamRow& row : wp::paramTable()) {
    ++rows;
    const std::string name = row.name;
    wp::MonitorParams p = base;
    switch (row.member.type) {
      case wp::ParamType::kNumber: {
        // The smallest change of the double, and an ordinary one.
        row.member.number(p) = bump(row.member.number(p));
        expectSeen(base, p, name);
        p = base;
        row.member.number(p) += 0.5;
        expectSeen(base, p, name);
        break;
      }
      case wp::ParamType::kInteger:
        row.member.integer(p) += 1;
        expectSeen(base, p, name);
        break;
      case wp::ParamType::kBool:
        row.member.flag(p) = !row.member.flag(p);
        expectSeen(base, p, name);
        break;
      case wp::ParamType::kString:
        row.member.text(p) += "x";
        expectSeen(base, p, name);
        break;
      case wp::ParamType::kStringList:
        row.member.names(p).push_back("x");
        expectSeen(base, p, name);
        p = base;
        row.member.names(p).front() += "x";
        expectSeen(base, p, name);
        break;
      case wp::ParamType::kPairs:
        row.member.pairs(p).push_back({"id:a", "id:b"});
        expectSeen(base, p, name);
        p = base;
        row.member.pairs(p).front().second += "x";
        expectSeen(base, p, name);
        break;
      case wp::ParamType::kStructure:
        if (name == "labels") {
          for (const wp::LabelRow& l : wp::labelTable()) {
            for (const char* label : {"default", "person"}) {
              p = base;
              p.labels[label].*l.member = bump(p.labels[label].*l.member);
              expectSeen(base, p, std::string("labels/") + label + "/" + l.key);
            }
          }
          p = base;
          p.labels["forklift"] = wp::LabelSettings();  // a new label, at the defaults
          expectSeen(base, p, "labels/forklift/");
        } else if (name == "robot_thresholds") {
          for (const wp::LabelRow& l : wp::labelTable()) {
            p = base;
            p.robot_thresholds.*l.member = bump(p.robot_thresholds.*l.member);
            if (l.track_only) {
              // Not a setting of the robot (validate() does not read it either): no change.
              EXPECT_EQ(wp::configFingerprint(base), wp::configFingerprint(p)) << l.key;
            } else {
              expectSeen(base, p, std::string("robot_thresholds/") + l.key);
            }
          }
        } else if (name == "robot_bodies") {
          p.robot_bodies.push_back(base.robot_bodies.front());
          p.robot_bodies.back().name = "second";
          expectSeen(base, p, "robot_bodies");
          using Edit = void (*)(wp::RobotBodySpec&);
          const Edit edits[] = {
              [](wp::RobotBodySpec& b) { b.name += "x"; },
              [](wp::RobotBodySpec& b) { b.frame += "x"; },
              [](wp::RobotBodySpec& b) { b.shape.type = wp::ShapeType::kSphere; },
              [](wp::RobotBodySpec& b) { b.shape.half_extents.x() = bump(b.shape.half_extents.x()); },
              [](wp::RobotBodySpec& b) { b.shape.half_extents.y() = bump(b.shape.half_extents.y()); },
              [](wp::RobotBodySpec& b) { b.shape.half_extents.z() = bump(b.shape.half_extents.z()); },
              [](wp::RobotBodySpec& b) { b.shape.radius = bump(b.shape.radius); },
              [](wp::RobotBodySpec& b) { b.shape.length = bump(b.shape.length); },
              [](wp::RobotBodySpec& b) { b.offset.translation().z() = bump(0.0); },
              [](wp::RobotBodySpec& b) { b.offset.rotate(Eigen::AngleAxisd(1e-9, Eigen::Vector3d::UnitX())); },
          };
          for (const Edit edit : edits) {
            p = base;
            edit(p.robot_bodies.front());
            expectSeen(base, p, "robot_bodies/0");
          }
        } else {
          ADD_FAILURE() << "~" << name << ": a structure row this test does not know";
        }
        break;
    }
  }
  EXPECT_EQ(rows, static_cast<int>(wp::paramTable().size));
}

TEST(ConfigFingerprint, EqualConfigurationsGiveEqualFingerprintsWhateverTheLabelsOrder) {
  // Labels are a map (a label's name finds its settings): the order they were given in is no
  // part of the configuration.
  wp::MonitorParams a;
  wp::MonitorParams b;
  a.labels["person"].margin = 0.3;
  a.labels["forklift"].margin = 0.5;
  b.labels["forklift"].margin = 0.5;
  b.labels["person"].margin = 0.3;
  EXPECT_EQ(wp::configFingerprint(a), wp::configFingerprint(b));
  EXPECT_TRUE(wp::configChanges(a, b).empty());
  const wp::MonitorParams c = a;
  EXPECT_EQ(wp::configFingerprint(a), wp::configFingerprint(c));
  EXPECT_EQ(wp::configFingerprint(wp::MonitorParams()), wp::configFingerprint(wp::MonitorParams()));
}

TEST(ConfigFingerprint, ListsKeepTheirOrder) {
  // A list is compared as given: a reordered list counts as a change (never a change hidden).
  wp::MonitorParams a;
  wp::MonitorParams b;
  a.input_topics = {"x", "y"};
  b.input_topics = {"y", "x"};
  EXPECT_NE(wp::configFingerprint(a), wp::configFingerprint(b));
}

TEST(ConfigFingerprint, NoValueCanImitateAnotherConfiguration) {
  // Without quoting, ["a,b"] and ["a", "b"], or a frame holding a line break and a second
  // "name=value", would read alike.
  wp::MonitorParams a;
  wp::MonitorParams b;
  a.input_topics = {"a,b"};
  b.input_topics = {"a", "b"};
  EXPECT_NE(wp::configFingerprint(a), wp::configFingerprint(b));
  wp::MonitorParams c;
  c.fixed_frame = "world\nrate=31";
  const std::string text = wp::canonicalConfig(c);
  const std::string plain = wp::canonicalConfig(wp::MonitorParams());
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), std::count(plain.begin(), plain.end(), '\n'));
  EXPECT_NE(text.find("fixed_frame=\"world\\nrate=31\"\n"), std::string::npos) << text;
  // Nor can a label's name: "a/margin=1\nlabels/b" stays one label's lines.
  wp::MonitorParams e;
  e.labels["a/margin=1\nlabels/b"] = wp::LabelSettings();
  const std::string labelled = wp::canonicalConfig(e);
  EXPECT_EQ(std::count(labelled.begin(), labelled.end(), '\n'),
            std::count(plain.begin(), plain.end(), '\n') +
                static_cast<long>(wp::labelTable().size))
      << labelled;
  EXPECT_NE(labelled.find("labels/a\\x2fmargin\\x3d1\\x0alabels\\x2fb/margin=0.1\n"),
            std::string::npos)
      << labelled;
  wp::MonitorParams d;
  d.fixed_frame = "a\"b\\c\td\x01";
  EXPECT_NE(wp::canonicalConfig(d).find("fixed_frame=\"a\\\"b\\\\c\\td\\x01\"\n"), std::string::npos);
}

TEST(ConfigFingerprint, TheUrdfCountsWhileTheRobotComesFromIt) {
  wp::MonitorParams p;
  ASSERT_TRUE(p.use_robot_description);
  EXPECT_NE(wp::configFingerprint(p, "<robot name='a'/>"), wp::configFingerprint(p, "<robot name='b'/>"));
  EXPECT_NE(wp::configFingerprint(p, "<robot name='a'/>"), wp::configFingerprint(p));
  p.use_robot_description = false;  // not read: not part of the configuration
  EXPECT_EQ(wp::configFingerprint(p, "<robot name='a'/>"), wp::configFingerprint(p, "<robot name='b'/>"));
}

TEST(ConfigFingerprint, ChangesNameEachParameterWithItsOldAndNewValue) {
  wp::MonitorParams a;
  wp::MonitorParams b;
  b.ssm.hold_time = 1.0;
  b.labels["default"].margin = 0.25;
  b.fixed_frame = "map";
  const std::vector<std::string> changes = wp::configChanges(a, b);
  const std::set<std::string> got(changes.begin(), changes.end());
  const std::set<std::string> want = {"fixed_frame: \"world\" -> \"map\"",
                                      "ssm/hold_time: 0.5 -> 1",
                                      "labels/default/margin: 0.1 -> 0.25"};
  EXPECT_EQ(got, want);
  wp::MonitorParams c = a;
  c.labels["person"] = wp::LabelSettings();
  const std::vector<std::string> added = wp::configChanges(a, c);
  ASSERT_FALSE(added.empty());
  EXPECT_EQ(added.front(), "labels/person/margin: (none) -> 0.1");
  const std::vector<std::string> removed = wp::configChanges(c, a);
  ASSERT_FALSE(removed.empty());
  EXPECT_EQ(removed.front(), "labels/person/margin: 0.1 -> (none)");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
