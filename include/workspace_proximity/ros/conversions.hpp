#pragma once
/// Free conversion functions between the package's messages and the ROS-free core.
/// Each has an inverse so round trips are tested (test/node/test_conversions.cpp).

#include <cstdint>
#include <string>

#include <Eigen/Geometry>

#include <workspace_proximity/ContactEvent.h>
#include <workspace_proximity/TrackedBox.h>

#include "workspace_proximity/body.hpp"
#include "workspace_proximity/pair_event.hpp"
#include "workspace_proximity/ros/monitor_params.hpp"

namespace workspace_proximity {

/// Limits on what a tracked box may say before it is rejected as nonsense.
struct BoxLimits {
  double max_dimension = 1000.0;    ///< m, full edge
  double max_coordinate = 1.0e5;    ///< m, |position| in its frame
  double max_speed = 100.0;         ///< m/s
  double max_angular_speed = 100.0; ///< rad/s
  double quaternion_tolerance = 0.01;  ///< | |q| - 1 | up to this is normalised, beyond rejected
};

/// Why a box cannot be used, or an empty string when it can. Checks ids, finiteness of
/// every number, dimensions (> 0, <= max), coordinates, speeds and the quaternion's length.
std::string checkTrackedBox(const TrackedBox& box, const BoxLimits& limits = BoxLimits());

/// The box's shape (half extents from the full dimensions).
Shape toShape(const TrackedBox& box);

/// The box's pose and twist expressed in the fixed frame, given the pose of the box's
/// frame in the fixed frame (the twist's vectors are rotated; the frame is assumed not to
/// move). The quaternion is normalised. Call checkTrackedBox first.
BodyMotion toMotion(const TrackedBox& box, const Eigen::Isometry3d& fixed_from_box_frame);

/// Inverse of toShape/toMotion for a box already in the fixed frame.
TrackedBox toTrackedBox(const std::string& id, const std::string& label, const Shape& shape,
                        const BodyMotion& motion);

/// Level of an event from the thresholds of its two bodies (the stricter one counts).
std::uint8_t contactLevel(const PairEvent& event, const LabelSettings& a, const LabelSettings& b);

/// Core event + the two bodies' descriptions -> message.
ContactEvent toMsg(const PairEvent& event, const BodyDesc& a, const BodyDesc& b,
                   std::uint8_t level);
/// The same, written into an existing message (its strings' capacity is reused); `stale`
/// is set to false.
void toMsg(const PairEvent& event, const BodyDesc& a, const BodyDesc& b, std::uint8_t level,
           ContactEvent* out);

/// Message -> core event (body handles are not in the message and stay invalid).
PairEvent fromMsg(const ContactEvent& msg);

}  // namespace workspace_proximity
