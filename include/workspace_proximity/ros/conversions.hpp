#pragma once
/// Free conversion functions between the package's messages and the ROS-free layers. Each has
/// an inverse so round trips are tested (test/ros/test_conversions.cpp).

#include <cstdint>
#include <string>

#include <ros/time.h>
#include <workspace_proximity/ContactEvent.h>
#include <workspace_proximity/TrackedBox.h>

#include "workspace_proximity/body.hpp"
#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/level_policy.hpp"
#include "workspace_proximity/rules/stamp.hpp"
#include "workspace_proximity/pair_event.hpp"

namespace workspace_proximity {

/// ros::Time <-> Stamp (nanoseconds); ros::Time(0) is Stamp 0 ("never" / "now" by context).
inline Stamp toStamp(const ros::Time& t) { return static_cast<Stamp>(t.toNSec()); }
inline ros::Time toTime(Stamp s) {
  ros::Time t;
  t.fromNSec(static_cast<std::uint64_t>(s));
  return t;
}

/// The box as the monitor reads it. Its id and label are views into `box`, which must
/// outlive the observation. No allocation.
void observe(const TrackedBox& box, BoxObservation* out);
BoxObservation observe(const TrackedBox& box);

/// Inverse of observe + boxShape / boxMotion for a box already in the fixed frame.
TrackedBox toTrackedBox(const std::string& id, const std::string& label, const Shape& shape,
                        const BodyMotion& motion);

/// Core event + the two bodies' descriptions -> message, written into an existing message (its
/// strings' capacity is reused); `stale` is set to false.
void toMsg(const PairEvent& event, const BodyDesc& a, const BodyDesc& b, Level level,
           ContactEvent* out);
ContactEvent toMsg(const PairEvent& event, const BodyDesc& a, const BodyDesc& b, Level level);

/// Message -> core event (body handles and the pair id are not in the message and stay unset).
PairEvent fromMsg(const ContactEvent& msg);

}  // namespace workspace_proximity
