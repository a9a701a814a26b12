#pragma once
/// The robot's own bodies (links from the URDF and ~robot_bodies) in the world: posed every
/// cycle by a bridge (tf today), or marked unknown. An unknown body is never absent: a body
/// seen before stays at its last pose without velocity, its pairs are stale, and the status
/// is DEGRADED until it is posed again. ROS-free.

#include <cstdint>
#include <string>
#include <vector>

#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace workspace_proximity {

class RobotBodies {
 public:
  /// `world` is borrowed. `margin`: m, added around every robot body.
  RobotBodies(ProximityWorld* world, std::vector<RobotBodySpec> specs, double margin);

  int size() const { return static_cast<int>(bodies_.size()); }
  const RobotBodySpec& spec(int i) const { return at(i).spec; }

  /// Body i is at `motion` now. Returns false (and marks it unknown with the reason) when the
  /// core refuses the motion. A non-empty `stale_reason` poses it but keeps it stale: its pose
  /// is known, its motion is not (e.g. its velocity before enough history has arrived), so its
  /// pairs are stale and the status DEGRADED rather than the body read as standing still.
  bool pose(int i, const BodyMotion& motion, const std::string& stale_reason = std::string());
  /// Body i follows a piecewise path over the horizon (ProximityWorld::setPath; the first
  /// segment's pose is the pose now), e.g. keyframes of its joints' motion. Otherwise as pose().
  bool posePath(int i, const MotionSegment* segments, int count,
                const std::string& stale_reason = std::string());
  /// Body i cannot be posed this cycle: kept at its last pose without velocity, stale.
  void markUnknown(int i, const std::string& why);
  /// Removes every body from the world (after the clock went back); they are added again
  /// when next posed.
  void clear();
  /// A new margin (m) for every body, now and when added later.
  void setMargin(double margin);

  /// In the world (posed at least once since the last clear()).
  bool present(int i) const { return at(i).present; }
  /// Not posed this cycle.
  bool stale(int i) const { return at(i).stale; }
  const std::string& why(int i) const { return at(i).why; }
  BodyHandle handle(int i) const { return at(i).handle; }
  /// Bodies not posed (stale or never seen).
  int unknownCount() const;
  /// Index of the robot body owning world body slot `slot`, or -1.
  int robotOfSlot(std::int32_t slot) const {
    const auto s = static_cast<std::size_t>(slot);
    return s < robot_of_slot_.size() ? robot_of_slot_[s] : -1;
  }
  /// Mean position of the bodies present (the cap's "nearest to the robot"), fixed frame.
  Eigen::Vector3d centre() const;
  /// One status line per body that is stale or unknown, appended to `lines`.
  void statusLines(std::vector<std::string>* lines) const;

 private:
  struct Body {
    RobotBodySpec spec;
    BodyHandle handle;
    bool present = false;
    bool stale = false;
    std::string why;
  };
  const Body& at(int i) const { return bodies_[static_cast<std::size_t>(i)]; }

  ProximityWorld* world_;
  double margin_;
  std::vector<Body> bodies_;
  std::vector<int> robot_of_slot_;
};

}  // namespace workspace_proximity
