// Pair rules: which body pairs the pipeline checks.

#include <gtest/gtest.h>

#include <stdexcept>

#include "workspace_proximity/pair_rules.hpp"

namespace wp = workspace_proximity;

namespace {
wp::BodyDesc body(const std::string& id, const std::string& label, wp::BodyGroup group) {
  wp::BodyDesc d;
  d.id = id;
  d.label = label;
  d.group = group;
  return d;
}
const wp::BodyDesc kLink1 = body("link1", "robot", wp::BodyGroup::kRobot);
const wp::BodyDesc kLink2 = body("link2", "robot", wp::BodyGroup::kRobot);
const wp::BodyDesc kAlice = body("alice", "person", wp::BodyGroup::kObject);
const wp::BodyDesc kBob = body("bob", "person", wp::BodyGroup::kObject);
const wp::BodyDesc kForklift = body("fl1", "forklift", wp::BodyGroup::kObject);
}  // namespace

TEST(PairRules, DefaultSkipsRobotRobotOnly) {
  const wp::PairRules rules;
  EXPECT_FALSE(rules.allowed(kLink1, kLink2));
  EXPECT_TRUE(rules.allowed(kLink1, kAlice));
  EXPECT_TRUE(rules.allowed(kAlice, kLink1));
  EXPECT_TRUE(rules.allowed(kAlice, kBob));
  EXPECT_TRUE(rules.allowed(kAlice, kForklift));
}

TEST(PairRules, AllowAllChecksEverything) {
  EXPECT_TRUE(wp::PairRules::allowAll().allowed(kLink1, kLink2));
}

TEST(PairRules, LastMatchWinsAndRulesAreSymmetric) {
  wp::PairRules rules;
  rules.add("label:person", "label:person", false);  // people do not collide with people
  rules.add("id:alice", "id:bob", true);             // ...except these two
  rules.add("id:link1", "id:link2", true);           // and these two links are checked
  EXPECT_TRUE(rules.allowed(kAlice, kBob));
  EXPECT_TRUE(rules.allowed(kBob, kAlice));
  EXPECT_TRUE(rules.allowed(kLink2, kLink1));
  const wp::BodyDesc carol = body("carol", "person", wp::BodyGroup::kObject);
  EXPECT_FALSE(rules.allowed(carol, kAlice));
  EXPECT_TRUE(rules.allowed(carol, kForklift));
}

TEST(PairRules, WildcardAndGroupSelectors) {
  wp::PairRules rules = wp::PairRules::allowAll();
  rules.add("label:forklift", "*", false);
  rules.add("label:forklift", "group:robot", true);
  EXPECT_FALSE(rules.allowed(kForklift, kAlice));
  EXPECT_TRUE(rules.allowed(kLink1, kForklift));
}

TEST(PairRules, SelectorParsingRoundTripsAndRejectsNonsense) {
  for (const std::string text : {"*", "group:robot", "group:object", "label:person", "id:a:b"}) {
    EXPECT_EQ(wp::BodySelector::parse(text).toString(), text);
  }
  for (const std::string bad : {"", "robot", "group:", "group:human", "colour:red", "label:"}) {
    EXPECT_THROW(wp::BodySelector::parse(bad), std::invalid_argument) << bad;
  }
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
