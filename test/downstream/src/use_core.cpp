// The core example of docs/design.md ("Using the core from C++"), checked: a person 2 m in
// front of a link, walking at it at 1 m/s.
#include <cmath>
#include <cstdio>

#include "workspace_proximity/proximity_world.hpp"
namespace wp = workspace_proximity;

int main() {
  wp::ProximityWorld world;  // default rules: robot-robot pairs skipped
  wp::BodyMotion m;
  m.position = {2.0, 0.0, 0.9};
  m.linear_velocity = {-1.0, 0.0, 0.0};
  const wp::BodyHandle person = world.addBody(
      {"person_1", "person", wp::BodyGroup::kObject, wp::Shape::box({0.25, 0.25, 0.9}), 0.2}, m);
  world.addBody({"link_1", "robot", wp::BodyGroup::kRobot, wp::Shape::cylinder(0.1, 0.6), 0.02},
                wp::BodyMotion());
  const auto& events = world.predict(/*horizon s*/ 2.0);
  // Face at 1.75 m, cylinder radius 0.1 m, margins 0.22 m: gap 1.43 m at 1 m/s.
  if (events.size() != 1 || std::abs(events[0].time_to_contact - 1.43) > 1e-3) {
    std::printf("use_core: expected one event at 1.43 s, got %zu\n", events.size());
    return 1;
  }
  std::printf("use_core: %s - %s in %.3f s\n", world.desc(events[0].body_a).id.c_str(),
              world.desc(events[0].body_b).id.c_str(), events[0].time_to_contact);
  world.setMotion(person, m.advanced(0.1));
  return world.predict(2.0).size() == 1 ? 0 : 1;
}
