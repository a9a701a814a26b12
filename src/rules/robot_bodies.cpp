#include "workspace_proximity/rules/robot_bodies.hpp"

#include <exception>

namespace workspace_proximity {

RobotBodies::RobotBodies(ProximityWorld* world, std::vector<RobotBodySpec> specs, double margin)
    : world_(world), margin_(margin) {
  bodies_.resize(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) bodies_[i].spec = std::move(specs[i]);
}

bool RobotBodies::pose(int i, const BodyMotion& motion, const std::string& stale_reason) {
  Body& b = bodies_[static_cast<std::size_t>(i)];
  try {
    if (!b.present) {
      b.handle = world_->addBody(
          BodyDesc{b.spec.name, "robot", BodyGroup::kRobot, b.spec.shape, margin_}, motion);
      b.present = true;
      const auto slot = static_cast<std::size_t>(b.handle.index);
      if (slot >= robot_of_slot_.size()) robot_of_slot_.resize(slot + 1, -1);
      robot_of_slot_[slot] = i;
    } else {
      world_->setMotion(b.handle, motion);
    }
  } catch (const std::exception& e) {
    markUnknown(i, std::string("rejected by the core: ") + e.what());
    return false;
  }
  b.stale = !stale_reason.empty();
  b.why = stale_reason;
  return true;
}

bool RobotBodies::posePath(int i, const MotionSegment* segments, int count,
                           const std::string& stale_reason) {
  Body& b = bodies_[static_cast<std::size_t>(i)];
  if (count < 1 || segments == nullptr) {
    markUnknown(i, "empty path");
    return false;
  }
  if (!pose(i, segments[0].motion, stale_reason)) return false;
  if (count == 1 && segments[0].margin == 0.0) return true;
  try {
    world_->setPath(b.handle, segments, count);
  } catch (const std::exception& e) {
    markUnknown(i, std::string("rejected by the core: ") + e.what());
    return false;
  }
  return true;
}

void RobotBodies::markUnknown(int i, const std::string& why) {
  Body& b = bodies_[static_cast<std::size_t>(i)];
  b.stale = true;
  b.why = why.empty() ? "invalid pose" : why;
  if (!b.present) return;
  // Unknown, not absent: a body last seen stays where it was, without extrapolating an old
  // velocity, and its pairs are marked stale.
  BodyMotion still = world_->motion(b.handle);
  still.linear_velocity.setZero();
  still.angular_velocity.setZero();
  world_->setMotion(b.handle, still);
}

void RobotBodies::clear() {
  for (Body& b : bodies_) {
    if (b.present) {
      world_->removeBody(b.handle);
      robot_of_slot_[static_cast<std::size_t>(b.handle.index)] = -1;
    }
    b.present = false;
    b.stale = false;
  }
}

void RobotBodies::setMargin(double margin) {
  if (margin == margin_) return;
  margin_ = margin;
  for (const Body& b : bodies_) {
    if (b.present) world_->setShape(b.handle, b.spec.shape, margin_);
  }
}

int RobotBodies::unknownCount() const {
  int n = 0;
  for (const Body& b : bodies_) n += (b.stale || !b.present) ? 1 : 0;
  return n;
}

Eigen::Vector3d RobotBodies::centre() const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (const Body& b : bodies_) {
    if (!b.present) continue;
    sum += world_->motion(b.handle).position;
    ++n;
  }
  return n > 0 ? Eigen::Vector3d(sum / n) : Eigen::Vector3d::Zero();
}

void RobotBodies::statusLines(std::vector<std::string>* lines) const {
  for (const Body& b : bodies_) {
    if (b.stale || !b.present) {
      lines->push_back("robot body " + b.spec.name + (b.present ? " stale: " : " unknown: ") + b.why);
    }
  }
}

}  // namespace workspace_proximity
