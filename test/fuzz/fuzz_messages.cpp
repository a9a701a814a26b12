// libFuzzer harness over the node's message handling (no ROS master, no topics): what the
// proximity_monitor does with every TrackedBox it receives, and with its parameters.
//
// Boxes (most inputs): a TrackedBox from arbitrary doubles and strings goes through
// observe() and checkBox(); when it is accepted, boxShape() / boxMotion() with an arbitrary finite
// isometry (the tf of the box's frame) must give finite numbers, a valid shape and a valid
// motion, and ProximityWorld must accept the body (addBody with any valid label margin,
// setMotion of the latency-compensated motion) and predict() any valid horizon without
// throwing: the node calls all of these without a try block.
//
// Parameters (inputs starting with 0xFF): MonitorParams with arbitrary numbers and selector
// strings; when validate() accepts them, makePairRules() must not throw and every label
// margin, the robot margin, the robot bodies' shapes and the horizon must be accepted by the
// world.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "fuzz_input.hpp"
#include "workspace_proximity/proximity_world.hpp"
#include "workspace_proximity/ros/conversions.hpp"
#include "workspace_proximity/rules/monitor_params.hpp"

namespace wp = workspace_proximity;
using wp_fuzz::fail;
using wp_fuzz::Input;

namespace {

constexpr int kMaxBoxes = 4;

// WP_FUZZ_TRACE=1 prints what happens to each box (for replaying a finding).
bool trace() {
  static const bool on = [] {
    const char* s = std::getenv("WP_FUZZ_TRACE");
    return s != nullptr && s[0] == '1';
  }();
  return on;
}

std::string str(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

std::string describe(const wp::TrackedBox& b) {
  return "position " + str(b.pose.position.x) + " " + str(b.pose.position.y) + " " +
         str(b.pose.position.z) + " q " + str(b.pose.orientation.w) + " " +
         str(b.pose.orientation.x) + " " + str(b.pose.orientation.y) + " " +
         str(b.pose.orientation.z) + " dimensions " + str(b.dimensions.x) + " " +
         str(b.dimensions.y) + " " + str(b.dimensions.z) + " linear " + str(b.twist.linear.x) +
         " " + str(b.twist.linear.y) + " " + str(b.twist.linear.z) + " angular " +
         str(b.twist.angular.x) + " " + str(b.twist.angular.y) + " " + str(b.twist.angular.z);
}

// A value near one of BoxLimits' limits (either side), or any number().
double nearLimit(Input& in) {
  const std::uint8_t s = in.byte();
  if (s >= 64) return in.number();
  static const double limits[] = {1000.0, 1.0e5, 100.0, 0.0};
  double v = limits[s & 3];
  const int steps = static_cast<std::int8_t>(in.byte()) % 3;
  for (int i = 0; i < std::abs(steps); ++i) v = std::nextafter(v, steps > 0 ? 2e5 : -2e5);
  return Input::clampRange((s & 4) ? -v : v);
}

double coordinate(Input& in) { return in.flag() ? nearLimit(in) : in.number(); }

wp::TrackedBox makeBox(Input& in) {
  wp::TrackedBox box;
  const std::uint8_t naming = in.byte();
  box.id = (naming & 7) == 0 ? std::string() : in.text(8);
  if (box.id.empty() && (naming & 7) != 0) box.id = "t";
  static const char* const labels[] = {"person", "forklift", "", "robot"};
  box.label = (naming & 0x80) ? in.text(8) : labels[(naming >> 3) & 3];
  box.pose.position.x = coordinate(in);
  box.pose.position.y = coordinate(in);
  box.pose.position.z = coordinate(in);
  const std::uint8_t qmode = in.byte();
  Eigen::Quaterniond q = in.quaternion();
  if (qmode & 1) q.coeffs() *= 1.0 + static_cast<std::int8_t>(in.byte()) * 1e-4;  // ~ 0.01 tolerance
  box.pose.orientation.w = q.w();
  box.pose.orientation.x = q.x();
  box.pose.orientation.y = q.y();
  box.pose.orientation.z = q.z();
  box.dimensions.x = in.flag() ? nearLimit(in) : in.dimension();
  box.dimensions.y = in.flag() ? nearLimit(in) : in.dimension();
  box.dimensions.z = in.flag() ? nearLimit(in) : in.dimension();
  const std::uint8_t twist = in.byte();
  if (twist & 1) {
    box.twist.linear.x = coordinate(in);
    box.twist.linear.y = coordinate(in);
    box.twist.linear.z = coordinate(in);
  }
  if (twist & 2) {
    box.twist.angular.x = coordinate(in);
    box.twist.angular.y = coordinate(in);
    box.twist.angular.z = coordinate(in);
  }
  return box;
}

// An arbitrary finite rigid transform: the pose of the box's frame in the fixed frame.
Eigen::Isometry3d makeTransform(Input& in) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  Eigen::Vector3d translation = in.vector();
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(translation[k])) translation[k] = 0.0;
  }
  t.translation() = translation;
  Eigen::Quaterniond q = in.quaternion();
  const double n = q.norm();
  if (!std::isfinite(n) || !(n > 0.0) || !q.coeffs().allFinite()) q = Eigen::Quaterniond::Identity();
  t.linear() = q.normalized().toRotationMatrix();
  if (!t.matrix().allFinite()) t = Eigen::Isometry3d::Identity();
  return t;
}

void checkEvents(const std::vector<wp::PairEvent>& events, const std::string& where) {
  for (const wp::PairEvent& e : events) {
    if (std::isnan(e.time_to_contact) || std::isnan(e.time_to_separation) ||
        std::isnan(e.distance) || std::isnan(e.closing_speed) || e.point_a.hasNaN() ||
        e.point_b.hasNaN() || e.normal.hasNaN()) {
      fail("NaN in an event", where);
    }
  }
}

void fuzzBoxes(Input& in) {
  wp::ProximityWorld world(wp::WorldConfig{});
  std::vector<wp::BodyHandle> handles;
  std::string log;
  const int count = 1 + in.byte() % kMaxBoxes;
  for (int i = 0; i < count && !in.empty(); ++i) {
    const wp::TrackedBox box = makeBox(in);
    const wp::BoxObservation observed = wp::observe(box);
    std::string why;
    const bool accepted = wp::checkBox(observed, wp::BoxLimits(), &why) == wp::Drop::kCount;
    if (trace()) std::fprintf(stderr, "box %s: %s\n", describe(box).c_str(), accepted ? "accepted" : why.c_str());
    if (!accepted) continue;
    const std::string where = describe(box);

    const Eigen::Isometry3d fixed_from_frame = makeTransform(in);
    const wp::Shape shape = wp::boxShape(observed);
    if (!shape.valid() || !shape.half_extents.allFinite() || !(shape.half_extents.array() > 0.0).all()) {
      fail("accepted box gives an invalid shape", where);
    }
    const wp::BodyMotion motion = wp::boxMotion(observed, fixed_from_frame);
    if (!motion.position.allFinite() || !motion.linear_velocity.allFinite() ||
        !motion.angular_velocity.allFinite() || !motion.orientation.coeffs().allFinite()) {
      fail("accepted box gives a non-finite motion", where);
    }
    if (std::abs(motion.orientation.norm() - 1.0) > 1e-6) {
      fail("accepted box gives a non-unit orientation", where);
    }
    // A frame transform can carry an accepted box past the core's limits (Limits::
    // kMaxCoordinate); the node catches the core's rejection and drops that box, so that is
    // not a finding. Anything else that makes the motion invalid is.
    if (!motion.valid()) {
      if (motion.position.cwiseAbs().maxCoeff() > wp::Limits::kMaxCoordinate) continue;
      fail("accepted box gives an invalid motion", where);
    }

    // Any margin validate() allows for a label: [0, 10] m.
    const double margin = in.byte() / 25.5;
    const wp::BodyDesc desc{std::to_string(i) + "/" + box.id, box.label, wp::BodyGroup::kObject,
                            shape, margin};
    try {
      handles.push_back(world.addBody(desc, motion));
    } catch (const std::invalid_argument& e) {
      fail("addBody rejects an accepted box", where + ": " + e.what());
    }
    log += where + "; ";

    // Latency compensation as the node does it: the motion moved by the message's age
    // (at most ~track_timeout <= 3600 s old, at most ~max_future <= 60 s ahead).
    const double dt = static_cast<std::int16_t>(in.u16()) / 8.0;
    const wp::BodyMotion advanced = motion.advanced(dt);
    try {
      world.setMotion(handles.back(), advanced);
    } catch (const std::invalid_argument& e) {
      fail("setMotion rejects the latency-compensated motion of an accepted box",
           where + " dt " + str(dt) + ": " + e.what());
    }
  }
  if (handles.empty()) return;
  // Any horizon validate() allows: [0, 60] s.
  const double horizon = in.byte() * (60.0 / 255.0);
  try {
    checkEvents(world.predict(horizon), log);
    const std::vector<wp::PairEvent>& events = world.predict(horizon);
    checkEvents(events, log);
    if (trace()) std::fprintf(stderr, "predict %g: %zu events\n", horizon, events.size());
  } catch (const std::invalid_argument& e) {
    fail("predict throws on accepted boxes", log + " horizon " + str(horizon) + ": " + e.what());
  }
}

std::string selector(Input& in) {
  static const char* const table[] = {"*", "group:robot", "group:object", "label:person",
                                      "id:arm", "label:", "group:x", "bogus"};
  const std::uint8_t s = in.byte();
  if (s < 200) return table[s & 7];
  return in.text(12);
}

void fuzzParams(Input& in) {
  wp::MonitorParams p;
  p.horizon = in.number();
  p.robot_margin = in.margin();
  const int labels = in.byte() % 3;
  for (int i = 0; i < labels; ++i) {
    wp::LabelSettings l;
    l.margin = in.margin();
    l.warning_time = in.number();
    l.critical_time = in.number();
    l.warning_distance = in.number();
    l.critical_distance = in.number();
    const std::uint8_t which = in.byte();
    p.labels[(which & 1) ? "default" : in.text(6)] = l;
  }
  const int rules = in.byte() % 4;
  for (int i = 0; i < rules; ++i) {
    const std::string first = selector(in);
    const std::string second = selector(in);
    (in.flag() ? p.ignore_pairs : p.check_pairs).emplace_back(first, second);
  }
  const int bodies = in.byte() % 3;
  for (int i = 0; i < bodies; ++i) {
    wp::RobotBodySpec b;
    b.name = in.text(4);
    b.frame = in.flag() ? std::string("link") : in.text(4);
    const std::uint8_t t = in.byte();
    const double a = in.dimension(), c = in.dimension();
    switch (t % 4) {
      case 0:
        b.shape = wp::Shape::box(Eigen::Vector3d(a, c, in.dimension()));
        break;
      case 1:
        b.shape = wp::Shape::sphere(a);
        break;
      case 2:
        b.shape = wp::Shape::cylinder(a, c);
        break;
      default:
        b.shape = wp::Shape::capsule(a, c);
        break;
    }
    b.offset.translation() = in.vector();
    p.robot_bodies.push_back(b);
  }

  const std::vector<std::string> errors = wp::validate(p);
  if (trace()) {
    for (const std::string& e : errors) std::fprintf(stderr, "params: %s\n", e.c_str());
    if (errors.empty()) std::fprintf(stderr, "params accepted\n");
  }
  if (!errors.empty()) return;

  wp::WorldConfig config;
  try {
    config.rules = wp::makePairRules(p);
  } catch (const std::invalid_argument& e) {
    fail("makePairRules throws on validated parameters", e.what());
  }
  wp::ProximityWorld world(config);
  try {
    int n = 0;
    for (const auto& kv : p.labels) {
      world.addBody(wp::BodyDesc{"label" + std::to_string(n++), kv.first, wp::BodyGroup::kObject,
                                 wp::Shape::box(Eigen::Vector3d::Constant(0.5)), kv.second.margin},
                    wp::BodyMotion());
    }
    for (const wp::RobotBodySpec& b : p.robot_bodies) {
      wp::BodyMotion m;
      m.position = b.offset.translation();
      world.addBody(wp::BodyDesc{"robot/" + b.name, "robot", wp::BodyGroup::kRobot, b.shape,
                                 p.robot_margin},
                    m);
    }
    checkEvents(world.predict(p.horizon), "params");
  } catch (const std::invalid_argument& e) {
    fail("the world rejects validated parameters", e.what());
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Input in(data, size);
  if (size > 0 && data[0] == 0xFF) {
    in.byte();
    fuzzParams(in);
  } else {
    fuzzBoxes(in);
  }
  return 0;
}
