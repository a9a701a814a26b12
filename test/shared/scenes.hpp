#pragma once
// Scene generators for the tests, fuzz harnesses, benchmarks and the core demo: moving
// bodies with known, reproducible motion. They build inputs only; what the library makes of
// them is checked against oracles.hpp.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "random.hpp"
#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/body.hpp"
#include "workspace_proximity/motion_path.hpp"
#include "workspace_proximity/proximity_world.hpp"

namespace wp_test {

namespace wp = workspace_proximity;

// ------------------------------------------------------------------------------------------
// Motions.

/// A body turning about the vertical through the origin at `omega` rad/s: at time t (s) it
/// sits `radius` m from the axis at `height`, at the angle omega t + phase, turned the same
/// way, with that point's velocity (omega x r) and angular velocity (0, 0, omega). An arm
/// link swinging about its base.
inline wp::BodyMotion turningLink(double t, double radius, double height, double omega,
                                  double phase = 0.0) {
  const double yaw = omega * t + phase;
  wp::BodyMotion m;
  m.position = Eigen::Vector3d(radius * std::cos(yaw), radius * std::sin(yaw), height);
  m.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  m.angular_velocity = Eigen::Vector3d(0, 0, omega);
  m.linear_velocity = m.angular_velocity.cross(Eigen::Vector3d(m.position.x(), m.position.y(), 0));
  return m;
}

/// Walks start -> end -> start, forever, at constant speed (one round trip per `period` s),
/// facing the way it goes.
inline wp::BodyMotion shuttle(double t, const Eigen::Vector3d& start, const Eigen::Vector3d& end,
                              double period) {
  const double phase = std::fmod(t, period) / period;
  const double s = phase < 0.5 ? 2.0 * phase : 2.0 - 2.0 * phase;
  const Eigen::Vector3d direction = (phase < 0.5 ? 1.0 : -1.0) * (end - start) * 2.0 / period;
  wp::BodyMotion m;
  m.position = start + s * (end - start);
  m.linear_velocity = direction;
  const double heading = std::atan2(direction.y(), direction.x());
  m.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()));
  return m;
}

/// A point moving at constant velocity inside a box region: after each step, a coordinate
/// outside [lower, upper] turns that velocity component back.
struct Walker {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();

  void step(double dt, const Eigen::Vector3d& lower, const Eigen::Vector3d& upper) {
    position += velocity * dt;
    for (int k = 0; k < 3; ++k) {
      if (position[k] < lower[k] || position[k] > upper[k]) velocity[k] = -velocity[k];
    }
  }
  /// Translation only, unrotated.
  wp::BodyMotion motion() const {
    wp::BodyMotion m;
    m.position = position;
    m.linear_velocity = velocity;
    return m;
  }
};

/// Random motion: centre within +-position m of the origin on each axis, each linear velocity
/// component within +-speed m/s, turning at a uniform rate in [-spin, spin] rad/s about a
/// random axis, any orientation. `upright`: turned and turning about z only, as trackers
/// report people and vehicles.
inline wp::BodyMotion randomMotion(Rng& rng, double position, double speed, double spin,
                                   bool upright = false) {
  wp::BodyMotion m;
  m.position = rng.vector(-position, position);
  m.linear_velocity = rng.vector(-speed, speed);
  m.orientation = upright ? rng.yaw() : rng.rotation();
  if (spin > 0.0) {
    const double rate = rng.uniform(-spin, spin);
    const Eigen::Vector3d axis = upright ? Eigen::Vector3d::UnitZ()
                                         : Eigen::Vector3d(rng.rotation() * Eigen::Vector3d::UnitX());
    m.angular_velocity = rate * axis;
  }
  return m;
}

/// A random piecewise path over [0, horizon] starting at `start` (its pose; its twist is the
/// first segment's unless `redraw_first`): `segments` segments with random increasing starts,
/// each later one with a random twist (linear components within +-speed m/s, turning at up to
/// `spin` rad/s about a random axis, or about z when `upright`). `continuous`: each segment
/// starts where the previous one ends; otherwise up to 0.3 m away (and turned by up to 0.5 rad
/// about a random axis, about z when upright). `margins`: each segment adds a margin in
/// [0, 0.05] m.
inline std::vector<wp::MotionSegment> randomPath(Rng& rng, const wp::BodyMotion& start, int segments,
                                                 double horizon, double speed, double spin,
                                                 bool upright, bool continuous, bool margins) {
  std::vector<double> starts{0.0};
  for (int k = 1; k < segments; ++k) starts.push_back(rng.uniform(0.02, horizon * 0.98));
  std::sort(starts.begin(), starts.end());
  starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
  std::vector<wp::MotionSegment> path;
  wp::BodyMotion m = start;
  for (std::size_t k = 0; k < starts.size(); ++k) {
    if (k > 0) {
      m = path.back().motion.advanced(starts[k] - starts[k - 1]);
      if (!continuous) {
        m.position += rng.vector(-0.3, 0.3);
        const Eigen::Vector3d axis = upright ? Eigen::Vector3d::UnitZ()
                                             : Eigen::Vector3d(rng.rotation() * Eigen::Vector3d::UnitX());
        m.orientation = (Eigen::Quaterniond(Eigen::AngleAxisd(rng.uniform(-0.5, 0.5), axis)) * m.orientation).normalized();
      }
      const wp::BodyMotion twist = randomMotion(rng, 0.0, speed, spin, upright);
      m.linear_velocity = twist.linear_velocity;
      m.angular_velocity = twist.angular_velocity;
    }
    wp::MotionSegment segment;
    segment.start = starts[k];
    segment.motion = m;
    segment.margin = margins ? rng.uniform(0.0, 0.05) : 0.0;
    path.push_back(segment);
  }
  return path;
}

/// Keyframes of a turningLink() (the arm link swinging about the vertical at `omega` rad/s)
/// over [0, horizon] from time t, as a path of `segments` equal segments: each segment goes in
/// a straight line from one keyframe's centre to the next (the chord) while turning at the
/// true rate, and adds as margin the bound on how far its points leave the true arc: a point
/// at distance rho from the axis deviates from the chord by at most the sagitta
/// rho (1 - cos(omega dt / 2)) <= rho omega^2 dt^2 / 8, rho at most radius + `reach` (the
/// shape's bounding radius).
inline void turningLinkPath(double t, double radius, double height, double omega, double phase,
                            double horizon, int segments, double reach,
                            std::vector<wp::MotionSegment>* path) {
  path->resize(static_cast<std::size_t>(segments));
  const double dt = horizon / segments;
  const double sagitta = (radius + reach) * omega * omega * dt * dt / 8.0;
  for (int k = 0; k < segments; ++k) {
    wp::MotionSegment& s = (*path)[static_cast<std::size_t>(k)];
    const wp::BodyMotion from = turningLink(t + k * dt, radius, height, omega, phase);
    const wp::BodyMotion to = turningLink(t + (k + 1) * dt, radius, height, omega, phase);
    s.start = k * dt;
    s.motion = from;
    s.motion.linear_velocity = (to.position - from.position) / dt;
    s.margin = sagitta;
  }
}

// ------------------------------------------------------------------------------------------
// Worlds.

/// The robot cell of the pipeline benchmark: an arm of `links` link boxes (chains of six
/// links at 0.25 to 1.5 m from the base, one chain per height) turning about the base at
/// 0.8 rad/s, and `objects` tracked objects (people 0.5 x 0.5 x 1.8 m, every tenth a
/// 2.4 x 1.2 x 2.0 m forklift) walking at 0.3 to 1.5 m/s in a 16 m square around it, turning
/// back at the walls. Margins 0.02 (links), 0.2 (people), 0.3 m (forklifts).
class RobotCell {
 public:
  static constexpr double kOmega = 0.8;      // rad/s
  static constexpr double kHalfWidth = 8.0;  // m

  RobotCell(wp::ProximityWorld* world, int links, int objects, std::uint32_t seed = 7)
      : world_(world), rng_(seed) {
    for (int i = 0; i < links; ++i) {
      const int chain = i / 6, k = i % 6;
      Link l{wp::BodyHandle(), 0.25 + 0.25 * k, 0.5 + 0.2 * chain,
             2 * M_PI * chain / std::max(1, links / 6)};
      l.handle = world->addBody({"link_" + std::to_string(i), "robot", wp::BodyGroup::kRobot,
                                 wp::Shape::box({0.13, 0.06, 0.06}), 0.02},
                                wp::BodyMotion());
      links_.push_back(l);
    }
    for (int i = 0; i < objects; ++i) {
      const bool forklift = i % 10 == 0;
      const double heading = rng_.uniform(0, 2 * M_PI);
      const double speed = rng_.uniform(0.3, 1.5);
      Object o;
      o.walker.position.x() = rng_.uniform(-kHalfWidth, kHalfWidth);
      o.walker.position.y() = rng_.uniform(-kHalfWidth, kHalfWidth);
      o.walker.position.z() = 1.0;
      o.walker.velocity = Eigen::Vector3d(speed * std::cos(heading), speed * std::sin(heading), 0);
      o.handle = world->addBody({"object_" + std::to_string(i), forklift ? "forklift" : "person",
                                 wp::BodyGroup::kObject,
                                 wp::Shape::box(forklift ? Eigen::Vector3d(1.2, 0.6, 1.0)
                                                         : Eigen::Vector3d(0.25, 0.25, 0.9)),
                                 forklift ? 0.3 : 0.2},
                                wp::BodyMotion());
      objects_.push_back(o);
    }
  }

  int linkCount() const { return static_cast<int>(links_.size()); }
  wp::BodyHandle link(int i) const { return links_[static_cast<std::size_t>(i)].handle; }

  /// From the next step on, each link follows its true arc as `segments` keyframed segments
  /// over `horizon` (turningLinkPath) instead of one constant twist (0: constant twist).
  void setKeyframes(int segments, double horizon) {
    keyframes_ = segments;
    keyframe_horizon_ = horizon;
  }
  /// From the next step on, every object's margin grows with `growth` (its age ignored).
  void setObjectGrowth(const wp::MarginGrowth& growth) { growth_ = growth; }
  /// Object i's body; replaceObject gives it a new one (its walk goes on).
  wp::BodyHandle object(int i) const { return objects_[static_cast<std::size_t>(i)].handle; }
  void replaceObject(int i, wp::BodyHandle handle) { objects_[static_cast<std::size_t>(i)].handle = handle; }

  /// Poses the arm at time t (s) and walks every object dt (s) on.
  void step(double t, double dt) {
    for (const Link& l : links_) {
      if (keyframes_ > 0) {
        turningLinkPath(t, l.radius, l.height, kOmega, l.phase, keyframe_horizon_, keyframes_,
                        kLinkReach, &path_);
        world_->setPath(l.handle, path_.data(), keyframes_);
      } else {
        world_->setMotion(l.handle, turningLink(t, l.radius, l.height, kOmega, l.phase));
      }
    }
    const Eigen::Vector3d lower(-kHalfWidth, -kHalfWidth, -kHalfWidth);
    const Eigen::Vector3d upper(kHalfWidth, kHalfWidth, kHalfWidth);
    for (Object& o : objects_) {
      o.walker.step(dt, lower, upper);
      world_->setMotion(o.handle, o.walker.motion());
      if (!growth_.none()) world_->setGrowth(o.handle, growth_);
    }
  }

 private:
  struct Link {
    wp::BodyHandle handle;
    double radius, height, phase;
  };
  struct Object {
    wp::BodyHandle handle;
    Walker walker;
  };

  // Bounding radius of a link box (half extents 0.13 x 0.06 x 0.06 m).
  static constexpr double kLinkReach = 0.1555;

  wp::ProximityWorld* world_;
  Rng rng_;
  std::vector<Link> links_;
  std::vector<Object> objects_;
  int keyframes_ = 0;
  double keyframe_horizon_ = 2.0;
  std::vector<wp::MotionSegment> path_;
  wp::MarginGrowth growth_;
};

/// A box body with its motion, for scenes checked against the box oracles.
struct BoxBody {
  Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5);
  wp::BodyMotion motion;
  wp::BodyHandle handle;
};

/// Random box for the no-false-negative scenes: half extents 0.1 to 0.8 m, centre within
/// 2.5 m of the origin, velocity components up to 2 m/s (randomMotion). `rotate`: turning at
/// up to 4 rad/s. `upright`: see randomMotion.
inline BoxBody randomBoxBody(Rng& rng, bool rotate, bool upright) {
  BoxBody b;
  b.half = rng.vector(0.1, 0.8);
  b.motion = randomMotion(rng, 2.5, 2.0, rotate ? 4.0 : 0.0, upright);
  return b;
}

/// A grid of mixed shapes (spheres, boxes, capsules) 1 m apart, each oscillating along x with
/// amplitude 0.15 m at 3 rad/s, neighbours in opposite phase, all spinning about z at
/// 0.5 rad/s: they close at up to 0.9 m/s, so contacts are predicted within 1 s, but the gaps
/// (>= 0.3 m) never close.
class OscillatingGrid {
 public:
  OscillatingGrid(wp::ProximityWorld* world, int nx, int ny, int nz) : world_(world) {
    int i = 0;
    for (int x = 0; x < nx; ++x) {
      for (int y = 0; y < ny; ++y) {
        for (int z = 0; z < nz; ++z, ++i) {
          const wp::Shape shape = (i % 3 == 0)   ? wp::Shape::sphere(0.2)
                                  : (i % 3 == 1) ? wp::Shape::box({0.2, 0.15, 0.1})
                                                 : wp::Shape::capsule(0.1, 0.2);
          Oscillator o{wp::BodyHandle(), Eigen::Vector3d(x, y, z), (x % 2) ? M_PI : 0.0};
          o.handle = world->addBody(
              wp::BodyDesc{"b" + std::to_string(i), "thing", wp::BodyGroup::kObject, shape, 0.02},
              wp::BodyMotion());
          bodies_.push_back(o);
        }
      }
    }
  }

  /// Sets every body's motion for time t (s).
  void pose(double t) {
    constexpr double kOmega = 3.0, kAmplitude = 0.15;
    for (const Oscillator& o : bodies_) {
      wp::BodyMotion m;
      m.position = o.centre + Eigen::Vector3d(kAmplitude * std::sin(kOmega * t + o.phase), 0, 0);
      m.linear_velocity = {kAmplitude * kOmega * std::cos(kOmega * t + o.phase), 0, 0};
      m.angular_velocity = {0, 0, 0.5};
      world_->setMotion(o.handle, m);
    }
  }

 private:
  struct Oscillator {
    wp::BodyHandle handle;
    Eigen::Vector3d centre;
    double phase;
  };
  wp::ProximityWorld* world_;
  std::vector<Oscillator> bodies_;
};

// ------------------------------------------------------------------------------------------
// Axis-aligned boxes for the broad phase.

// Random boxes for one scene. In exact mode every coordinate is a multiple of `quantum`
// (itself a multiple of 1/64) clamped to +-1000, hence exactly representable in float.
struct AabbScene {
  bool exact = true;
  double quantum = 1.0 / 64.0;
  double extent = 100.0;     // lower corners in [-extent, extent] (+ offset)
  double max_size = 10.0;
  double offset = 0.0;       // arbitrary-double scenes: shift far from the origin
  double shared = 0.0;       // a coordinate many boxes share

  double q(double x) const {
    if (!exact) return x;
    return std::clamp(quantum * std::round(x / quantum), -1000.0, 1000.0);
  }

  wp::Aabb fresh(Rng& rng) const {
    std::uniform_real_distribution<double> pos(-extent, extent), size(0.0, max_size);
    wp::Aabb b;
    for (int k = 0; k < 3; ++k) {
      b.lower[k] = q(offset + pos(rng));
      b.upper[k] = std::max(b.lower[k], q(b.lower[k] + size(rng)));
    }
    return b;
  }

  // A new box with a special relation to `other` (or a fresh one when there is no other).
  wp::Aabb related(Rng& rng, const wp::Aabb* other) const {
    std::uniform_int_distribution<int> kind(0, 99), coin(0, 1), axis(0, 2);
    std::uniform_real_distribution<double> size(0.0, max_size), unit(0.0, 1.0);
    int k = kind(rng);
    if (k < 6) {  // zero-size (point) box
      wp::Aabb b = fresh(rng);
      b.upper = b.lower;
      return b;
    }
    if (k < 12) {  // many boxes whose lower or upper x is the same coordinate
      wp::Aabb b = fresh(rng);
      double w = b.upper.x() - b.lower.x();
      if (coin(rng)) {
        b.lower.x() = shared;
        b.upper.x() = q(shared + w);
      } else {
        b.upper.x() = shared;
        b.lower.x() = q(shared - w);
      }
      return b;
    }
    if (other == nullptr || k < 45) return fresh(rng);
    if (k < 55) return *other;  // identical box
    if (k < 60) {               // point on a corner of the other box
      wp::Aabb b;
      for (int a = 0; a < 3; ++a) b.lower[a] = coin(rng) ? other->lower[a] : other->upper[a];
      b.upper = b.lower;
      return b;
    }
    // Touching the other box on a random nonempty subset of axes (face, edge or corner
    // contact), overlapping it on the rest. Arbitrary-double scenes also get near-touching
    // boxes, separated or overlapping by a hair.
    int touch_mask = 1 + std::uniform_int_distribution<int>(0, 6)(rng);
    bool nudge = !exact && k >= 85;
    wp::Aabb b;
    for (int a = 0; a < 3; ++a) {
      double w = q(size(rng));
      if (touch_mask & (1 << a)) {
        if (coin(rng)) {
          b.lower[a] = other->upper[a];
          if (nudge) b.lower[a] += (unit(rng) - 0.5) * 1e-7 * std::max(1.0, std::abs(b.lower[a]));
          b.upper[a] = std::max(b.lower[a], q(b.lower[a] + w));
        } else {
          b.upper[a] = other->lower[a];
          if (nudge) b.upper[a] += (unit(rng) - 0.5) * 1e-7 * std::max(1.0, std::abs(b.upper[a]));
          b.lower[a] = std::min(b.upper[a], q(b.upper[a] - w));
        }
        if (nudge && coin(rng)) {  // one double ulp apart
          b.lower[a] = std::nextafter(b.lower[a], 1e300);
          b.upper[a] = std::max(b.upper[a], b.lower[a]);
        }
      } else {
        double lo = other->lower[a], hi = other->upper[a];
        b.lower[a] = q(lo - w * unit(rng));
        b.upper[a] = std::max(b.lower[a], q(std::max(b.lower[a], lo) + (hi - lo) * unit(rng) + w));
      }
    }
    return b;
  }

  // Small motion: shift by a few quanta (exact) or a small random amount, sometimes resize.
  wp::Aabb jitter(Rng& rng, const wp::Aabb& b) const {
    std::uniform_int_distribution<int> steps(-2, 2), pick(0, 9);
    std::uniform_real_distribution<double> small(-0.02, 0.02);
    wp::Aabb out = b;
    for (int a = 0; a < 3; ++a) {
      double d = exact ? quantum * steps(rng) : small(rng) * max_size;
      out.lower[a] = q(b.lower[a] + d);
      out.upper[a] = q(b.upper[a] + d);
      if (pick(rng) == 0) out.upper[a] = q(out.upper[a] + (exact ? quantum : 0.01 * max_size));
      if (out.upper[a] < out.lower[a]) out.upper[a] = out.lower[a];
    }
    return out;
  }
};

inline AabbScene randomAabbScene(Rng& rng, bool exact) {
  AabbScene g;
  g.exact = exact;
  std::uniform_int_distribution<int> pick(0, 3);
  const double quanta[] = {1.0 / 64.0, 1.0 / 8.0, 1.0, 4.0};
  const double extents[] = {4.0, 30.0, 200.0, 600.0};
  const double size_fraction[] = {0.05, 0.2, 0.5, 1.0};
  g.extent = extents[pick(rng)];
  g.max_size = g.extent * size_fraction[pick(rng)];
  if (exact) {
    g.quantum = quanta[pick(rng)];
    g.max_size = std::min(g.max_size, 350.0);
    g.shared = g.q(std::uniform_real_distribution<double>(-g.extent, g.extent)(rng));
  } else {
    const double extents_d[] = {1e-3, 1.0, 100.0, 5000.0};
    // Far from the origin (relative to the scene size) float keys get coarse; keep the
    // offset at most 1000 scene sizes so rounding stays a boundary effect.
    const double offsets[] = {0.0, 0.0, 10.0, 1000.0};
    g.extent = extents_d[pick(rng)];
    g.max_size = g.extent * size_fraction[pick(rng)];
    g.offset = offsets[pick(rng)] * g.extent;
    g.shared = g.offset + std::uniform_real_distribution<double>(-g.extent, g.extent)(rng);
  }
  return g;
}

// `n` half-unit cubes at random integer corners in [-900, 900]^3: sparse, exact in float.
inline std::vector<wp::Aabb> spreadBoxes(Rng& rng, int n) {
  std::vector<wp::Aabb> out;
  std::uniform_real_distribution<double> pos(-900.0, 900.0);
  for (int i = 0; i < n; ++i) {
    double x = std::round(pos(rng)), y = std::round(pos(rng)), z = std::round(pos(rng));
    out.push_back(wp::Aabb{Eigen::Vector3d(x, y, z), Eigen::Vector3d(x + 0.5, y + 0.5, z + 0.5)});
  }
  return out;
}


}  // namespace wp_test
