#pragma once
/// The node's scenes without ROS: the monitor tests that replaced rostests (test/rules/
/// test_scene_*.cpp) drive the ROS-free Monitor the way proximity_monitor does, in simulated
/// time. A tracker publishes arrays of boxes every 50 ms, each stamped `latency` before it
/// arrives and carrying every box where it is at that stamp; the node cycles at its rate,
/// posing the static robot bodies first. The boxes' motion is known in closed form at every
/// instant (the oracle the checks use), as wp_node_testlib.py's Track was for the rostests.
///
/// feed() is the only place these tests hand an array to the monitor.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "workspace_proximity/rules/monitor.hpp"

namespace wp_test {

namespace wps = workspace_proximity;

/// The simulated clock's origin: scene time t (s) is the instant kSceneT0 + t.
constexpr wps::Stamp kSceneT0 = 1000LL * 1000000000LL;

inline wps::Stamp sceneStamp(double t) { return kSceneT0 + std::llround(t * 1e9); }
inline double sceneTime(wps::Stamp s) { return static_cast<double>(s - kSceneT0) * 1e-9; }

/// One array of source `source`, stamped `stamp`, arriving at `now`, its boxes in a frame
/// whose pose in the fixed frame is `fixed_from_frame`. Returns whether the monitor used it.
inline bool feed(wps::Monitor& monitor, int source, wps::Stamp stamp, wps::Stamp now,
                 const std::vector<wps::BoxObservation>& boxes,
                 const Eigen::Isometry3d& fixed_from_frame = Eigen::Isometry3d::Identity()) {
  monitor.noteReceipt(source, now);
  return monitor.ingest(source, stamp, now, fixed_from_frame, boxes);
}

/// The rostests' baseline parameters (test/ros/fixtures/common_params.yaml): 20 Hz, horizon
/// 5 s, no margins, so contact times, distances and nearest points have exact analytic values.
inline wps::MonitorParams commonParams() {
  wps::MonitorParams p;
  p.fixed_frame = "world";
  p.rate = 20.0;
  p.horizon = 5.0;
  p.track_timeout = 0.5;
  p.use_robot_description = false;
  p.robot_margin = 0.0;
  p.velocity_window = 0.1;
  p.tf_timeout = 0.5;
  p.labels["default"] = wps::LabelSettings{0.0, 1.0, 0.4, 0.5, 0.2};
  p.robot_thresholds = wps::LabelSettings{0.0, 1.0, 0.4, 0.3, 0.1};
  p.publish_markers = true;
  p.marker_lifetime = 0.7;
  p.marker_rate = 1000.0;
  return p;
}

/// A box moving with piecewise-constant linear velocity (position continuous), either at a
/// fixed orientation or turning about the world z axis through its centre at a constant rate.
class SceneTrack {
 public:
  SceneTrack(std::string id, std::string label, const Eigen::Vector3d& position,
             const Eigen::Vector3d& size,
             const Eigen::Vector3d& velocity = Eigen::Vector3d::Zero(),
             const Eigen::Quaterniond& orientation = Eigen::Quaterniond::Identity())
      : id(std::move(id)), label(std::move(label)), size(size), orientation_(orientation) {
    segments_.push_back({-std::numeric_limits<double>::infinity(), position, velocity});
    start_ = position;
  }
  /// Turning at `yaw_rate` rad/s from yaw `yaw` at t = 0 (angular twist (0, 0, yaw_rate)).
  static SceneTrack turning(std::string id, std::string label, const Eigen::Vector3d& position,
                            const Eigen::Vector3d& size, double yaw, double yaw_rate) {
    SceneTrack t(std::move(id), std::move(label), position, size);
    t.turning_ = true;
    t.yaw0_ = yaw;
    t.yaw_rate_ = yaw_rate;
    return t;
  }

  /// From scene time `t` on the box moves at `velocity`.
  void setVelocity(double t, const Eigen::Vector3d& velocity) {
    segments_.push_back({t, centre(t), velocity});
  }

  Eigen::Vector3d centre(double t) const {
    const Segment& s = segmentAt(t);
    // The first segment holds at every t before the next one, its position given at t = 0.
    const double from = std::isinf(s.start) ? 0.0 : s.start;
    return s.position + s.velocity * (t - from);
  }
  Eigen::Vector3d velocity(double t) const { return segmentAt(t).velocity; }
  Eigen::Vector3d half() const { return 0.5 * size; }
  double yaw(double t) const { return yaw0_ + yaw_rate_ * t; }
  Eigen::Quaterniond orientation(double t) const {
    return turning_ ? Eigen::Quaterniond(Eigen::AngleAxisd(yaw(t), Eigen::Vector3d::UnitZ()))
                    : orientation_;
  }

  /// The box as a tracker reports it for scene time `t` (views into this track).
  wps::BoxObservation observe(double t) const {
    wps::BoxObservation b;
    b.id = id;
    b.label = label;
    b.position = centre(t);
    const Eigen::Quaterniond q = orientation(t);
    b.quaternion = Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
    b.dimensions = size;
    b.linear_velocity = velocity(t);
    if (turning_) b.angular_velocity = Eigen::Vector3d(0.0, 0.0, yaw_rate_);
    b.position_error = position_error;
    b.velocity_error = velocity_error;
    b.velocity_known = velocity_known;
    return b;
  }

  std::string id;
  std::string label;
  Eigen::Vector3d size;
  bool active = true;  ///< published (false: left out of the arrays from now on)
  bool velocity_known = true;   ///< published as known (false: a tracker without it yet)
  double position_error = 0.0;  ///< m, the tracker's own error it publishes (0: none)
  double velocity_error = 0.0;  ///< m/s, likewise

 private:
  struct Segment {
    double start;
    Eigen::Vector3d position;  // at `start` (at 0 for the first segment)
    Eigen::Vector3d velocity;
  };
  const Segment& segmentAt(double t) const {
    const Segment* s = &segments_.front();
    for (const Segment& c : segments_) {
      if (c.start <= t) s = &c;
    }
    return *s;
  }

  Eigen::Quaterniond orientation_;
  bool turning_ = false;
  double yaw0_ = 0.0;
  double yaw_rate_ = 0.0;
  Eigen::Vector3d start_;
  std::vector<Segment> segments_;
};

/// A tracker: every `period` s from `start` until `stop` it publishes its active tracks to
/// `source`, stamped `latency` s before the arrival, in a frame posed `frame` in the fixed one.
struct ScenePublisher {
  int source = 0;
  std::vector<SceneTrack>* tracks = nullptr;
  double latency = 0.05;
  double start = 0.0;
  double stop = std::numeric_limits<double>::infinity();
  double period = 0.05;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  std::vector<double> stamps;       ///< scene times of the stamps it sent
  std::vector<double> arrivals;     ///< scene times at which they arrived
  /// Scene time of the last stamp that carried each track (by index; -inf: never).
  std::vector<double> last_stamp;
};

/// The node's view of an event, as proximity_monitor publishes it (ContactEvent's fields).
struct SceneEvent {
  wps::ContactState state;
  std::string id_a, id_b, label_a, label_b;
  double time_to_contact, time_to_separation, distance, closing_speed;
  Eigen::Vector3d point_a, point_b, normal;
  wps::Level level;
  bool stale;
};

inline std::vector<SceneEvent> sceneEvents(const wps::Monitor& monitor,
                                           const wps::CycleReport& r) {
  std::vector<SceneEvent> out;
  for (std::size_t i = 0; i < r.eventCount(); ++i) {
    const wps::PairEvent& e = r.event(i);
    const wps::BodyDesc& a = monitor.world().desc(e.body_a);
    const wps::BodyDesc& b = monitor.world().desc(e.body_b);
    out.push_back({e.state, a.id, b.id, a.label, b.label, e.time_to_contact,
                   e.time_to_separation, e.distance, e.closing_speed, e.point_a, e.point_b,
                   e.normal, r.levels[i], r.stale[i] != 0});
  }
  return out;
}

inline std::string describe(const SceneEvent& e) {
  static const char* const kStates[] = {"BEGIN", "ONGOING", "END"};
  char line[320];
  std::snprintf(line, sizeof(line),
                "%s %s(%s)-%s(%s) ttc=%.6f tts=%.6f d=%.6f n=(%.4f,%.4f,%.4f) vc=%.4f lvl=%d",
                kStates[static_cast<int>(e.state)], e.id_a.c_str(), e.label_a.c_str(),
                e.id_b.c_str(), e.label_b.c_str(), e.time_to_contact, e.time_to_separation,
                e.distance, e.normal.x(), e.normal.y(), e.normal.z(), e.closing_speed,
                static_cast<int>(e.level));
  return line;
}

inline void expectArrayBasics(const wps::CycleReport& r, const std::vector<SceneEvent>& events);

/// What one cycle published: its instant (scene time), status, events and SSM verdict.
struct SceneCycle {
  double t = 0.0;
  bool degraded = false;
  std::vector<std::string> status_lines;
  std::vector<SceneEvent> events;
  wps::SsmVerdict ssm;
  std::string ssm_robot, ssm_object;  ///< ids of the limiting pair (SafetyStatus.id_*)
  std::size_t bodies = 0;             ///< live bodies reported
};

inline std::string joined(const std::vector<std::string>& lines) {
  std::string out;
  for (const std::string& l : lines) out += (out.empty() ? "" : "; ") + l;
  return out;
}

/// '.' and 'O' runs shortened to one: "..BOOOE.." -> ".BOE.", so a regex like
/// ^\.*BO+E\.*$ is a membership test of the shortened sequence.
inline std::string shortened(const std::string& seq) {
  std::string out;
  for (char c : seq) {
    if ((c == '.' || c == 'O') && !out.empty() && out.back() == c) continue;
    out += c;
  }
  return out;
}

/// The node in simulated time: a monitor, its static robot bodies (posed every cycle at
/// `robot_motion`) and its trackers. run() steps a millisecond clock; at each cycle instant
/// (every 1 / rate s, offset by `cycle_phase`) it poses the robot, cycles and calls the
/// callback with the scene time and the report.
class SceneNode {
 public:
  SceneNode(const wps::MonitorParams& params, std::vector<wps::RobotBodySpec> robot,
            const std::vector<std::string>& sources, bool qualify)
      : monitor(params, robot, sources, qualify, nullptr), clock_(&timing_) {
    for (const wps::RobotBodySpec& s : robot) {
      wps::BodyMotion m;
      m.position = s.offset.translation();  // on frames at the fixed frame's origin
      m.orientation = Eigen::Quaterniond(s.offset.linear());
      robot_motion.push_back(m);
    }
    cycle_period_ms_ = static_cast<int>(std::lround(1000.0 / params.rate));
  }

  /// Runs scene time [from, to) in 1 ms steps. `step` (may be empty) is called first at every
  /// step (scene changes), then the trackers publish, then the node cycles when due.
  void run(double from, double to,
           const std::function<void(double t, const wps::CycleReport& report)>& on_cycle,
           const std::function<void(double t)>& step = {}) {
    const long k0 = std::lround(from * 1000.0), k1 = std::lround(to * 1000.0);
    for (long k = k0; k < k1; ++k) {
      const double t = k * 1e-3;
      if (step) step(t);
      for (ScenePublisher& p : publishers) publish(p, k);
      if (((k - cycle_phase_ms) % cycle_period_ms_ + cycle_period_ms_) % cycle_period_ms_ == 0) {
        for (std::size_t i = 0; i < robot_motion.size(); ++i) {
          monitor.poseRobot(static_cast<int>(i), robot_motion[i]);
        }
        const wps::CycleReport& r = monitor.cycle(sceneStamp(t), &clock_);
        if (on_cycle) on_cycle(t, r);
      }
    }
  }

  /// run() recording every cycle from `record_from` on, each checked by expectArrayBasics.
  std::vector<SceneCycle> record(double from, double to, double record_from = 0.0,
                                 const std::function<void(double t)>& step = {}) {
    std::vector<SceneCycle> out;
    run(from, to, [&](double t, const wps::CycleReport& r) {
      if (t < record_from) return;
      SceneCycle c;
      c.t = t;
      c.degraded = r.degraded;
      c.status_lines = r.status_lines;
      c.events = sceneEvents(monitor, r);
      c.ssm = r.ssm;
      if (r.ssm.limited && monitor.world().contains(r.ssm.robot) &&
          monitor.world().contains(r.ssm.object)) {
        c.ssm_robot = monitor.world().desc(r.ssm.robot).id;
        c.ssm_object = monitor.world().desc(r.ssm.object).id;
      }
      c.bodies = r.bodies.size();
      expectArrayBasics(r, c.events);
      out.push_back(std::move(c));
    }, step);
    return out;
  }

  wps::Monitor monitor;
  std::vector<wps::BodyMotion> robot_motion;
  std::vector<ScenePublisher> publishers;
  int cycle_phase_ms = 23;  ///< cycles fall between the arrays (which arrive on whole 50 ms)

 private:
  void publish(ScenePublisher& p, long k) {
    const long period_ms = std::lround(p.period * 1000.0);
    const long start_ms = std::lround(p.start * 1000.0);
    if (k < start_ms || k * 1e-3 >= p.stop || (k - start_ms) % period_ms != 0) return;
    const double now = k * 1e-3, stamp = now - p.latency;
    if (p.last_stamp.size() != p.tracks->size()) {
      p.last_stamp.assign(p.tracks->size(), -std::numeric_limits<double>::infinity());
    }
    boxes_.clear();
    for (std::size_t i = 0; i < p.tracks->size(); ++i) {
      const SceneTrack& tr = (*p.tracks)[i];
      if (!tr.active) continue;
      boxes_.push_back(tr.observe(stamp));
      p.last_stamp[i] = stamp;
    }
    p.stamps.push_back(stamp);
    p.arrivals.push_back(now);
    feed(monitor, p.source, sceneStamp(stamp), sceneStamp(now), boxes_, p.frame);
  }

  wps::CycleTiming timing_;
  wps::StageClock clock_;
  int cycle_period_ms_ = 50;
  std::vector<wps::BoxObservation> boxes_;
};

// ------------------------------------------------------------------------------------------
// The rostests' analytic oracle (wp_node_testlib.py), written out again.

/// Tolerances of the analytic checks.
constexpr double kTimeTol = 1e-3;    // s, time_to_contact / time_to_separation
constexpr double kDistTol = 1e-4;    // m, distance and nearest points
constexpr double kSpeedTol = 1e-3;   // m/s, closing speed
constexpr double kNormalTol = 1e-3;  // per component

/// Exact prediction for two axis-aligned boxes translating at constant velocity (centres c,
/// half extents h, velocities v at the prediction instant), when they touch within
/// [0, horizon].
struct AabbPrediction {
  bool touches = false;
  double ttc = 0.0, tts = 0.0, distance = 0.0;
  bool has_normal = false;  ///< apart now: normal and closing speed are defined
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  double closing_speed = 0.0;
  int axis = -1;  ///< the single separating axis of a face-face configuration, else -1
};

inline AabbPrediction aabbPrediction(const Eigen::Vector3d& ca, const Eigen::Vector3d& ha,
                                     const Eigen::Vector3d& va, const Eigen::Vector3d& cb,
                                     const Eigen::Vector3d& hb, const Eigen::Vector3d& vb,
                                     double horizon) {
  const double inf = std::numeric_limits<double>::infinity();
  double lo = -inf, hi = inf;
  for (int k = 0; k < 3; ++k) {
    const double d = cb[k] - ca[k], w = vb[k] - va[k], s = ha[k] + hb[k];
    if (w == 0.0) {
      if (std::abs(d) > s) {
        lo = inf;
        hi = -inf;
      }
      continue;
    }
    const double t1 = (-s - d) / w, t2 = (s - d) / w;
    lo = std::max(lo, std::min(t1, t2));
    hi = std::min(hi, std::max(t1, t2));
  }
  lo = std::max(lo, 0.0);
  hi = std::min(hi, horizon);
  Eigen::Vector3d gaps;
  for (int k = 0; k < 3; ++k) {
    const double d = cb[k] - ca[k], g = std::abs(d) - (ha[k] + hb[k]);
    gaps[k] = g > 0 ? std::copysign(g, d) : 0.0;
  }
  AabbPrediction res;
  res.distance = gaps.norm();
  if (res.distance > 0) {
    res.has_normal = true;
    res.normal = gaps / res.distance;
    res.closing_speed = -(vb - va).dot(res.normal);
    int nonzero = 0;
    for (int k = 0; k < 3; ++k) {
      if (gaps[k] != 0.0) {
        ++nonzero;
        res.axis = k;
      }
    }
    if (nonzero != 1) res.axis = -1;
  }
  if (!(lo <= hi)) return res;
  res.touches = true;
  res.ttc = lo;
  res.tts = hi;
  return res;
}

/// Compares an event with the prediction for boxes a, b (in the event's id order). Nearest
/// points along the separating axis exactly, across it inside both boxes' extents.
inline void expectFaceContact(const SceneEvent& ev, const AabbPrediction& exp,
                              const Eigen::Vector3d& ca, const Eigen::Vector3d& ha,
                              const Eigen::Vector3d& cb, const Eigen::Vector3d& hb,
                              const std::string& where, bool check_points = true) {
  const std::string ctx = where + ": " + describe(ev);
  EXPECT_NEAR(ev.time_to_contact, exp.ttc, kTimeTol) << "ttc " << ctx;
  EXPECT_NEAR(ev.time_to_separation, exp.tts, kTimeTol) << "tts " << ctx;
  EXPECT_NEAR(ev.distance, exp.distance, kDistTol) << "distance " << ctx;
  if (exp.has_normal) {
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(ev.normal[k], exp.normal[k], kNormalTol) << "normal " << ctx;
    EXPECT_NEAR(ev.closing_speed, exp.closing_speed, kSpeedTol) << "closing_speed " << ctx;
  }
  if (exp.axis >= 0 && check_points) {
    const int k = exp.axis;
    const double sgn = cb[k] > ca[k] ? 1.0 : -1.0;
    EXPECT_NEAR(ev.point_a[k], ca[k] + sgn * ha[k], kDistTol) << "point_a " << ctx;
    EXPECT_NEAR(ev.point_b[k], cb[k] - sgn * hb[k], kDistTol) << "point_b " << ctx;
    for (int j = 0; j < 3; ++j) {
      if (j == k) continue;
      for (const Eigen::Vector3d* p : {&ev.point_a, &ev.point_b}) {
        EXPECT_LE(std::abs((*p)[j] - ca[j]), ha[j] + kDistTol) << "outside a's face " << ctx;
        EXPECT_LE(std::abs((*p)[j] - cb[j]), hb[j] + kDistTol) << "outside b's face " << ctx;
      }
    }
  }
}

/// Level from thresholds; `decided` false when too close to a threshold to decide.
inline wps::Level expectedLevel(double ttc, double dist, const wps::LabelSettings& thr,
                                bool* decided, double margin_t = 3e-3, double margin_d = 3e-3) {
  *decided = !(std::abs(ttc - thr.critical_time) < margin_t ||
               std::abs(ttc - thr.warning_time) < margin_t ||
               std::abs(dist - thr.critical_distance) < margin_d ||
               std::abs(dist - thr.warning_distance) < margin_d);
  if (ttc <= thr.critical_time || dist <= thr.critical_distance) return wps::Level::kCritical;
  if (ttc <= thr.warning_time || dist <= thr.warning_distance) return wps::Level::kWarning;
  return wps::Level::kNotice;
}

/// The contract every contacts array satisfies (wp_node_testlib.check_array_basics): ids in
/// order, each pair once, END with ttc = +inf and tts = 0, otherwise 0 <= ttc <= tts, a unit
/// normal, distance >= 0; events sorted by time to contact; OK without status lines,
/// DEGRADED with at least one.
inline void expectArrayBasics(const wps::CycleReport& r, const std::vector<SceneEvent>& events) {
  if (r.degraded) {
    EXPECT_FALSE(r.status_lines.empty()) << "DEGRADED without status_details";
  } else {
    EXPECT_TRUE(r.status_lines.empty()) << "OK with status_details";
  }
  EXPECT_GT(r.stamp, 0);
  double prev = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < events.size(); ++i) {
    const SceneEvent& ev = events[i];
    EXPECT_LT(ev.id_a, ev.id_b) << describe(ev);
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_FALSE(events[j].id_a == ev.id_a && events[j].id_b == ev.id_b)
          << "pair reported twice: " << describe(ev);
    }
    if (ev.state == wps::ContactState::kEnd) {
      EXPECT_TRUE(std::isinf(ev.time_to_contact) && ev.time_to_contact > 0) << describe(ev);
      EXPECT_EQ(ev.time_to_separation, 0.0) << describe(ev);
    } else {
      EXPECT_GE(ev.time_to_contact, 0.0) << describe(ev);
      EXPECT_GE(ev.time_to_separation, ev.time_to_contact) << describe(ev);
      EXPECT_GE(ev.distance, 0.0) << describe(ev);
      EXPECT_NEAR(ev.normal.norm(), 1.0, 1e-6) << "normal not unit: " << describe(ev);
    }
    EXPECT_GE(ev.time_to_contact, prev) << "events not sorted by time_to_contact";
    prev = ev.time_to_contact;
  }
}

/// The events of pair (a, b).
inline std::vector<const SceneEvent*> eventsFor(const std::vector<SceneEvent>& events,
                                                const std::string& a, const std::string& b) {
  std::vector<const SceneEvent*> out;
  for (const SceneEvent& e : events) {
    if (e.id_a == a && e.id_b == b) out.push_back(&e);
  }
  return out;
}

/// One character per cycle: '.' no event for the pair, else B / O / E.
inline char stateChar(const std::vector<SceneEvent>& events, const std::string& a,
                      const std::string& b) {
  const auto evs = eventsFor(events, a, b);
  return evs.empty() ? '.' : "BOE"[static_cast<int>(evs[0]->state)];
}

/// A body of a scene as the checks see it: axis-aligned, translating; `centre(t)` and
/// `velocity(t)` in the fixed frame at scene time t.
struct CheckedBody {
  std::string id, label;
  Eigen::Vector3d half;
  std::function<Eigen::Vector3d(double)> centre;
  std::function<Eigen::Vector3d(double)> velocity;
};

inline CheckedBody checkedTrack(const SceneTrack& t, double margin = 0.0) {
  return {t.id, t.label, t.half() + Eigen::Vector3d::Constant(margin),
          [&t](double s) { return t.centre(s); }, [&t](double s) { return t.velocity(s); }};
}

inline CheckedBody checkedStatic(const std::string& id, const Eigen::Vector3d& centre,
                                 const Eigen::Vector3d& half) {
  return {id, "robot", half, [centre](double) { return centre; },
          [](double) { return Eigen::Vector3d::Zero(); }};
}

/// One cycle's events against the exact prediction for a scene of axis-aligned translating
/// bodies (wp_node_testlib.check_scene_events): every non-END event an expected pair with
/// analytic numbers; every expected pair reported unless within `ambiguity` s of the horizon
/// or of separating; no robot-robot pair. With `thresholds` (by label, "robot" for robot
/// bodies) the level too, the stricter label's. Returns the number of events checked.
inline int expectSceneEvents(
    double t, const std::vector<SceneEvent>& events, const std::vector<CheckedBody>& bodies,
    double horizon, double ambiguity = 5e-3,
    const std::function<const wps::LabelSettings&(const std::string&)>& thresholds = {},
    bool check_points = true) {
  struct Expected {
    AabbPrediction exp;
    const CheckedBody* a;
    const CheckedBody* b;
    bool optional;
  };
  std::vector<const CheckedBody*> sorted;
  for (const CheckedBody& b : bodies) sorted.push_back(&b);
  std::sort(sorted.begin(), sorted.end(),
            [](const CheckedBody* x, const CheckedBody* y) { return x->id < y->id; });
  std::vector<Expected> expected;
  for (std::size_t i = 0; i < sorted.size(); ++i) {
    for (std::size_t j = i + 1; j < sorted.size(); ++j) {
      const CheckedBody* a = sorted[i];
      const CheckedBody* b = sorted[j];
      if (a->label == "robot" && b->label == "robot") continue;
      AabbPrediction exp = aabbPrediction(a->centre(t), a->half, a->velocity(t), b->centre(t),
                                          b->half, b->velocity(t), horizon + ambiguity);
      if (!exp.touches) continue;
      bool optional = false;
      if (exp.ttc > horizon - ambiguity || exp.tts < ambiguity) {
        optional = true;
        if (exp.ttc > horizon) continue;
      }
      exp.tts = std::min(exp.tts, horizon);
      expected.push_back({exp, a, b, optional});
    }
  }
  char where[32];
  std::snprintf(where, sizeof(where), "t=%.4f", t);
  int checked = 0;
  for (const SceneEvent& ev : events) {
    if (ev.state == wps::ContactState::kEnd) continue;
    const Expected* x = nullptr;
    for (const Expected& e : expected) {
      if (e.a->id == ev.id_a && e.b->id == ev.id_b) x = &e;
    }
    EXPECT_NE(x, nullptr) << where << " unexpected event " << describe(ev);
    if (x == nullptr) continue;
    ++checked;
    EXPECT_EQ(ev.label_a, x->a->label) << describe(ev);
    EXPECT_EQ(ev.label_b, x->b->label) << describe(ev);
    expectFaceContact(ev, x->exp, x->a->centre(t), x->a->half, x->b->centre(t), x->b->half,
                      where, check_points);
    if (thresholds) {
      bool da = false, db = false;
      const wps::Level la = expectedLevel(x->exp.ttc, x->exp.distance, thresholds(x->a->label), &da);
      const wps::Level lb = expectedLevel(x->exp.ttc, x->exp.distance, thresholds(x->b->label), &db);
      if (da && db) {
        EXPECT_EQ(ev.level, std::max(la, lb)) << where << " level of " << describe(ev);
      }
    }
  }
  for (const Expected& e : expected) {
    if (e.optional) continue;
    bool got = false;
    for (const SceneEvent& ev : events) {
      got |= ev.state != wps::ContactState::kEnd && ev.id_a == e.a->id && ev.id_b == e.b->id;
    }
    EXPECT_TRUE(got) << where << " missing event for pair (" << e.a->id << ", " << e.b->id
                     << "), ttc " << e.exp.ttc;
  }
  return checked;
}

}  // namespace wp_test
