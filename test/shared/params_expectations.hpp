#pragma once
/// Checks shared by the tests of the parameter readers (the ROS parameter tree and the replay's
/// YAML files): both must carry the same scalar settings into MonitorParams.

#include <gtest/gtest.h>

#include "workspace_proximity/rules/monitor_params.hpp"

namespace wp_test {

/// Expects the top-level scalar settings of `got` to equal those of `want`.
inline void expectSameScalars(const workspace_proximity::MonitorParams& got,
                              const workspace_proximity::MonitorParams& want) {
  EXPECT_EQ(got.fixed_frame, want.fixed_frame);
  EXPECT_EQ(got.rate, want.rate);
  EXPECT_EQ(got.horizon, want.horizon);
  EXPECT_EQ(got.track_timeout, want.track_timeout);
  EXPECT_EQ(got.max_tracks, want.max_tracks);
  EXPECT_EQ(got.robot_margin, want.robot_margin);
  EXPECT_EQ(got.use_robot_description, want.use_robot_description);
}

}  // namespace wp_test
