// replay_bag's command line and topic resolution.

#include <gtest/gtest.h>

#include "workspace_proximity/replay/replay_options.hpp"

namespace wp = workspace_proximity;

namespace {
bool parse(const std::vector<std::string>& args, wp::ReplayOptions* o, std::string* error) {
  return wp::parseReplayOptions(args, o, error);
}
}  // namespace

TEST(ReplayOptions, EveryOption) {
  wp::ReplayOptions o;
  std::string error;
  ASSERT_TRUE(parse({"dir/cell.bag", "--config", "a.yaml", "--config=b.yaml", "--urdf", "arm.urdf",
                     "--out=out", "--input-topic", "/boxes", "--rate-factor", "2.5", "--no-report"},
                    &o, &error))
      << error;
  EXPECT_EQ(o.bag, "dir/cell.bag");
  EXPECT_EQ(o.config_files, (std::vector<std::string>{"a.yaml", "b.yaml"}));
  EXPECT_EQ(o.urdf, "arm.urdf");
  EXPECT_EQ(o.out_dir, "out");
  EXPECT_EQ(o.input_topic, "/boxes");
  EXPECT_EQ(o.rate_factor, 2.5);
  EXPECT_FALSE(o.report);
}

TEST(ReplayOptions, Defaults) {
  wp::ReplayOptions o;
  std::string error;
  ASSERT_TRUE(parse({"/data/run 3.bag", "--as-fast-as-possible"}, &o, &error)) << error;
  EXPECT_EQ(o.out_dir, "replay-run 3");
  EXPECT_EQ(o.rate_factor, 0.0);
  EXPECT_TRUE(o.report);
  EXPECT_TRUE(o.config_files.empty());
  ASSERT_TRUE(parse({"--help"}, &o, &error));
  EXPECT_TRUE(o.help);
}

TEST(ReplayOptions, MistakesAreNamed) {
  struct Case {
    std::vector<std::string> args;
    const char* error;
  };
  const Case cases[] = {
      {{}, "no bag given"},
      {{"a.bag", "b.bag"}, "one bag at a time"},
      {{"a.bag", "--config"}, "--config needs a value"},
      {{"a.bag", "--rate-factor", "0"}, "--rate-factor wants a positive number, got '0'"},
      {{"a.bag", "--rate-factor", "fast"}, "--rate-factor wants a positive number"},
      {{"a.bag", "--rate-factor=-1"}, "--rate-factor wants a positive number, got '-1'"},
      {{"a.bag", "--rate-factor", "2", "--as-fast-as-possible"}, "exclude each other"},
      {{"a.bag", "--input-topic="}, "--input-topic must not be empty"},
      {{"a.bag", "--speed", "2"}, "unknown option --speed"},
  };
  for (const Case& c : cases) {
    wp::ReplayOptions o;
    std::string error;
    EXPECT_FALSE(parse(c.args, &o, &error)) << c.error;
    EXPECT_NE(error.find(c.error), std::string::npos) << "expected '" << c.error << "', got '" << error << "'";
  }
}

TEST(ReplayOptions, TopicsResolveAsTheNodeResolvesThem) {
  EXPECT_EQ(wp::resolveTopic("tracked_objects"), "/tracked_objects");
  EXPECT_EQ(wp::resolveTopic("tracker/boxes"), "/tracker/boxes");
  EXPECT_EQ(wp::resolveTopic("/tracker/boxes"), "/tracker/boxes");
  EXPECT_EQ(wp::resolveTopic("~boxes"), "/proximity_monitor/boxes");
  EXPECT_EQ(wp::resolveTopic("~/boxes"), "/proximity_monitor/boxes");
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
