#pragma once
/// A predicted contact between two bodies, as reported every cycle.

#include <cstdint>

#include <Eigen/Core>

#include "workspace_proximity/body.hpp"

namespace workspace_proximity {

enum class ContactState : std::uint8_t { kBegin = 0, kOngoing = 1, kEnd = 2 };

/// One pair's prediction for this cycle. Times are seconds after the prediction instant.
/// BEGIN: first cycle the pair is predicted to touch within the horizon.
/// ONGOING: still predicted (numbers updated). END: no longer predicted; sent once, with
/// time_to_contact = +infinity and time_to_separation = 0, other fields as last predicted.
struct PairEvent {
  ContactState state = ContactState::kBegin;
  /// Small non-negative integer naming the pair for its whole life (from its BEGIN to its END
  /// inclusive); reused by later pairs after the END. (The EventTracker's record index; -1
  /// on a prediction not yet reported.)
  std::int32_t pair = -1;
  BodyHandle body_a;               ///< body whose id sorts first
  BodyHandle body_b;
  double time_to_contact = 0.0;     ///< s until first contact; 0 when touching now
  double time_to_separation = 0.0;  ///< s until predicted contact ends (the horizon if later)
  double distance = 0.0;            ///< gap between margin-inflated shapes now, m (>= 0)
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< nearest point on a now, world, m
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< nearest point on b now, world, m
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();  ///< unit, from a towards b
  double closing_speed = 0.0;       ///< m/s, > 0 when approaching
};

}  // namespace workspace_proximity
