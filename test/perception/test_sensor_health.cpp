// Sensor health rules worked out by hand: a sensor never heard, silent past the timeout,
// whose frame tf cannot place or that came without robot poses is named in a DEGRADED reason
// for as long as that lasts, and a malformed frame does not count as heard.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "workspace_proximity/perception/sensor_health.hpp"

namespace pc = workspace_proximity::perception;

namespace {

constexpr std::int64_t kSec = 1000000000;

std::vector<std::string> reasons(const pc::SensorHealth& h, std::int64_t now) {
  std::vector<std::string> out;
  h.degradedReasons(now, &out);
  return out;
}

bool mentions(const std::vector<std::string>& lines, const std::string& a, const std::string& b) {
  for (const std::string& l : lines) {
    if (l.find(a) != std::string::npos && l.find(b) != std::string::npos) return true;
  }
  return false;
}

TEST(SensorHealth, NeverHeardIsDegradedAtOnceAndByName) {
  pc::SensorHealth h({"/cam/points", "/scan"}, 1.0, 10 * kSec);
  const auto r = reasons(h, 10 * kSec);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_TRUE(mentions(r, "/cam/points", "no usable frame"));
  EXPECT_TRUE(mentions(r, "/scan", "no usable frame"));
}

TEST(SensorHealth, SilentPastTheTimeoutAndBackAgain) {
  pc::SensorHealth h({"/cam/points"}, 1.0, 0);
  h.frameUsed(0, 5 * kSec, pc::CloudFrameStats{}, "");
  EXPECT_TRUE(reasons(h, 6 * kSec).empty());  // exactly the timeout: still fine
  const auto r = reasons(h, 6 * kSec + 1);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_TRUE(mentions(r, "/cam/points", "silent for 1.00 s"));
  h.frameUsed(0, 7 * kSec, pc::CloudFrameStats{}, "");
  EXPECT_TRUE(reasons(h, 7 * kSec).empty());
}

TEST(SensorHealth, MalformedFramesDoNotCountAsHeard) {
  pc::SensorHealth h({"/cam/points"}, 1.0, 0);
  h.frameUsed(0, 1 * kSec, pc::CloudFrameStats{}, "");
  for (int i = 0; i < 20; ++i) h.frameRejected(0, 1 * kSec + i * kSec / 10, "missing_xyz");
  EXPECT_EQ(h.framesRejected(0), 20);
  const auto r = reasons(h, 3 * kSec);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_TRUE(mentions(r, "silent", "missing_xyz"));
}

TEST(SensorHealth, UnplacedFramesAndUnknownRobotPosesAreNamedUntilFixed) {
  pc::SensorHealth h({"/cam/points"}, 1.0, 0);
  h.frameUsed(0, 1 * kSec, pc::CloudFrameStats{}, "");
  h.frameUnplaced(0, 1 * kSec + 1, "frame camera_link unreachable: no transform");
  auto r = reasons(h, 1 * kSec + 2);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_TRUE(mentions(r, "/cam/points", "camera_link unreachable"));
  h.frameUsed(0, 1 * kSec + 3, pc::CloudFrameStats{}, "link forearm: no transform");
  r = reasons(h, 1 * kSec + 4);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_TRUE(mentions(r, "robot poses unknown", "forearm"));
  h.frameUsed(0, 1 * kSec + 5, pc::CloudFrameStats{}, "");
  EXPECT_TRUE(reasons(h, 1 * kSec + 6).empty());
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
