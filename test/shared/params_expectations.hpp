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

/// Expects the multi-object tracker's settings in `got` to equal those in `want`, field by
/// field: TrackerParams or DetectionTrackerSettings (~detection_tracker/), the same names.
template <typename Got, typename Want>
void expectSameTrackerSettings(const Got& got, const Want& want) {
  EXPECT_EQ(got.gate_chi2, want.gate_chi2);
  EXPECT_EQ(got.gate_distance, want.gate_distance);
  EXPECT_EQ(got.confirm_hits, want.confirm_hits);
  EXPECT_EQ(got.max_misses, want.max_misses);
  EXPECT_EQ(got.timeout, want.timeout);
  EXPECT_EQ(got.known_velocity_error, want.known_velocity_error);
}

}  // namespace wp_test
