// Tests of sweptBounds / rotationHalfExtents. The oracle is the exact body: its pose is
// recomputed here from the motion model (centre = position + v t,
// orientation = AngleAxis(|w| t, w/|w|) * orientation), and its exact world AABB comes from
// closed-form support functions (validated against surface samples), never from the code
// under test.

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "workspace_proximity/swept_bounds.hpp"

using workspace_proximity::Aabb;
using workspace_proximity::BodyMotion;
using workspace_proximity::rotationHalfExtents;
using workspace_proximity::Shape;
using workspace_proximity::ShapeType;
using workspace_proximity::sweptBounds;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The test's own description of a shape, turned into a Shape through the public factories.
struct ShapeSpec {
  ShapeType type = ShapeType::kBox;
  Eigen::Vector3d half = Eigen::Vector3d::Constant(0.5);  // box
  double radius = 0.0, length = 0.0;                      // others

  Shape make() const {
    switch (type) {
      case ShapeType::kBox: return Shape::box(half);
      case ShapeType::kSphere: return Shape::sphere(radius);
      case ShapeType::kCylinder: return Shape::cylinder(radius, length);
      case ShapeType::kCapsule: return Shape::capsule(radius, length);
    }
    return Shape::box(half);
  }

  // Radius of the smallest origin-centred sphere containing the shape.
  double boundingRadius() const {
    switch (type) {
      case ShapeType::kBox: return half.norm();
      case ShapeType::kSphere: return radius;
      case ShapeType::kCylinder: return std::hypot(radius, 0.5 * length);
      case ShapeType::kCapsule: return radius + 0.5 * length;
    }
    return 0.0;
  }

  // Exact half extents of the world AABB of the shape rotated by R (support function along
  // +-world axes). Box: sum_j |R_kj| h_j. Cylinder with world axis a: (L/2)|a_k| + r sqrt(1 -
  // a_k^2) (the rim circle). Capsule: (L/2)|a_k| + r. Sphere: r.
  Eigen::Vector3d exactHalfExtents(const Eigen::Matrix3d& R) const {
    Eigen::Vector3d e;
    Eigen::Vector3d a = R.col(2);
    for (int k = 0; k < 3; ++k) {
      switch (type) {
        case ShapeType::kBox:
          e[k] = std::abs(R(k, 0)) * half[0] + std::abs(R(k, 1)) * half[1] +
                 std::abs(R(k, 2)) * half[2];
          break;
        case ShapeType::kSphere: e[k] = radius; break;
        case ShapeType::kCylinder:
          e[k] = 0.5 * length * std::abs(a[k]) +
                 radius * std::sqrt(std::max(0.0, 1.0 - a[k] * a[k]));
          break;
        case ShapeType::kCapsule: e[k] = 0.5 * length * std::abs(a[k]) + radius; break;
      }
    }
    return e;
  }

  // Points on the shape's surface in its local frame: box corners; sphere and capsule caps
  // on a Fibonacci lattice; cylinder rims (where AABB extremes lie) plus side lines.
  std::vector<Eigen::Vector3d> surfaceSamples(int n) const {
    std::vector<Eigen::Vector3d> pts;
    auto fib = [&](const Eigen::Vector3d& centre, double r) {
      const double golden = kPi * (3.0 - std::sqrt(5.0));
      for (int i = 0; i < n; ++i) {
        double z = 1.0 - 2.0 * (i + 0.5) / n, s = std::sqrt(1.0 - z * z), phi = golden * i;
        pts.push_back(centre + r * Eigen::Vector3d(s * std::cos(phi), s * std::sin(phi), z));
      }
      for (int k = 0; k < 3; ++k) {  // the six poles
        pts.push_back(centre + r * Eigen::Vector3d::Unit(k));
        pts.push_back(centre - r * Eigen::Vector3d::Unit(k));
      }
    };
    switch (type) {
      case ShapeType::kBox:
        for (int c = 0; c < 8; ++c)
          pts.emplace_back((c & 1 ? 1 : -1) * half[0], (c & 2 ? 1 : -1) * half[1],
                           (c & 4 ? 1 : -1) * half[2]);
        break;
      case ShapeType::kSphere: fib(Eigen::Vector3d::Zero(), radius); break;
      case ShapeType::kCapsule:
        fib(Eigen::Vector3d(0, 0, 0.5 * length), radius);
        fib(Eigen::Vector3d(0, 0, -0.5 * length), radius);
        break;
      case ShapeType::kCylinder:
        for (int i = 0; i < n; ++i) {
          double phi = 2.0 * kPi * i / n;
          for (double z : {-0.5 * length, 0.0, 0.5 * length})
            pts.emplace_back(radius * std::cos(phi), radius * std::sin(phi), z);
        }
        break;
    }
    return pts;
  }
};

// Orientation at time t under the constant-twist model, computed independently.
Eigen::Matrix3d rotationAt(const BodyMotion& m, double t) {
  double w = m.angular_velocity.norm();
  if (w == 0.0) return m.orientation.toRotationMatrix();
  Eigen::AngleAxisd step(w * t, m.angular_velocity / w);
  return (Eigen::Quaterniond(step) * m.orientation).toRotationMatrix();
}

Eigen::Vector3d centreAt(const BodyMotion& m, double t) {
  return m.position + m.linear_velocity * t;
}

Eigen::Quaterniond randomRotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Quaterniond q(g(rng), g(rng), g(rng), g(rng));
  q.normalize();
  return q;
}

// The 24 rotations mapping axes to axes: the exact AABB of any shape's local box.
Eigen::Quaterniond randomAxisPermutation(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> axis(0, 2), quarter(0, 3);
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (int i = 0; i < 3; ++i)
    q = Eigen::Quaterniond(Eigen::AngleAxisd(quarter(rng) * 0.5 * kPi,
                                             Eigen::Vector3d::Unit(axis(rng)))) * q;
  return q.normalized();
}

ShapeSpec randomShape(std::mt19937_64& rng, int type) {
  std::uniform_real_distribution<double> u(0.01, 1.5);
  ShapeSpec s;
  s.type = static_cast<ShapeType>(type);
  s.half = Eigen::Vector3d(u(rng), u(rng), u(rng));
  s.radius = u(rng);
  s.length = 2.0 * u(rng);
  return s;
}

struct Case {
  ShapeSpec shape;
  BodyMotion motion;
  double margin = 0.0, horizon = 0.0;
};

Case randomCase(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> pos(-10.0, 10.0), vel(-3.0, 3.0), unit(0.0, 1.0);
  std::uniform_int_distribution<int> type(0, 3), pick(0, 9);
  std::normal_distribution<double> g(0.0, 1.0);
  Case c;
  c.shape = randomShape(rng, type(rng));
  c.motion.position = Eigen::Vector3d(pos(rng), pos(rng), pos(rng));
  c.motion.orientation = randomRotation(rng);
  if (pick(rng) != 0) c.motion.linear_velocity = Eigen::Vector3d(vel(rng), vel(rng), vel(rng));
  // Angular speed: none, slow, fast, or fast enough to turn more than a half revolution.
  int w_kind = pick(rng) % 4;
  double w_mag = w_kind == 0 ? 0.0 : w_kind == 1 ? 0.2 * unit(rng)
                                 : w_kind == 2 ? 3.0 * unit(rng) : 5.0 + 20.0 * unit(rng);
  Eigen::Vector3d dir(g(rng), g(rng), g(rng));
  if (pick(rng) == 0) dir = c.motion.orientation * Eigen::Vector3d::UnitZ();  // spin on axis
  c.motion.angular_velocity = w_mag * dir.normalized();
  c.margin = pick(rng) < 3 ? 0.0 : 0.5 * unit(rng);
  c.horizon = pick(rng) == 0 ? 0.0 : 3.0 * unit(rng);
  return c;
}

// A translating case whose world AABB the oracle knows exactly at every instant: boxes and
// spheres at any orientation, cylinders and capsules at axis-permuting orientations (their
// local box's rotated AABB is then exact). Position within 10 m of the origin, velocity
// components up to `speed` m/s.
Case exactAabbCase(std::mt19937_64& rng, int type, double speed) {
  std::uniform_real_distribution<double> pos(-10.0, 10.0), vel(-speed, speed);
  Case c;
  c.shape = randomShape(rng, type);
  c.motion.position = Eigen::Vector3d(pos(rng), pos(rng), pos(rng));
  c.motion.orientation = (c.shape.type == ShapeType::kBox || c.shape.type == ShapeType::kSphere)
                             ? randomRotation(rng)
                             : randomAxisPermutation(rng);
  c.motion.linear_velocity = Eigen::Vector3d(vel(rng), vel(rng), vel(rng));
  return c;
}

double scaleOf(const Case& c) {
  return 1.0 + c.motion.position.cwiseAbs().maxCoeff() +
         c.motion.linear_velocity.cwiseAbs().maxCoeff() * c.horizon +
         c.shape.boundingRadius() + c.margin;
}

bool inside(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, const Aabb& box, double tol) {
  return (lo.array() >= box.lower.array() - tol).all() &&
         (hi.array() <= box.upper.array() + tol).all();
}

}  // namespace

// The oracle's closed-form extents agree with dense surface sampling: no sampled point lies
// outside them, and sampling gets close to them (so they are not loose either).
TEST(SweptBoundsOracle, SupportExtentsMatchSurfaceSamples) {
  std::mt19937_64 rng(99);
  for (int trial = 0; trial < 400; ++trial) {
    ShapeSpec s = randomShape(rng, trial % 4);
    Eigen::Matrix3d R = randomRotation(rng).toRotationMatrix();
    Eigen::Vector3d e = s.exactHalfExtents(R);
    Eigen::Vector3d seen = Eigen::Vector3d::Zero();
    for (const auto& p : s.surfaceSamples(4000)) seen = seen.cwiseMax((R * p).cwiseAbs());
    // (Samples are symmetric about the origin, so |R p| covers both sides of each axis.)
    EXPECT_TRUE((seen.array() <= e.array() + 1e-12).all()) << "trial " << trial;
    EXPECT_TRUE((seen.array() >= e.array() - 2e-3 * s.boundingRadius()).all())
        << "trial " << trial << " seen " << seen.transpose() << " exact " << e.transpose();
  }
}

// Main property: the swept box contains the exact body (its exact AABB grown by the margin)
// at 201 instants of [0, H], for random shapes, poses, twists, margins and horizons. For boxes
// the eight world-space vertices are also checked one by one. rotationHalfExtents must contain
// the exact extents about the moving centre at every instant.
TEST(SweptBounds, ContainsExactBodyAtEverySampledTime) {
  std::mt19937_64 rng(2024);
  const int kSteps = 200;
  for (int trial = 0; trial < 3000; ++trial) {
    Case c = randomCase(rng);
    Shape shape = c.shape.make();
    ASSERT_TRUE(shape.valid());
    ASSERT_TRUE(c.motion.valid());
    Aabb swept = sweptBounds(shape, c.motion, c.margin, c.horizon);
    Eigen::Vector3d rot = rotationHalfExtents(shape, c.motion, c.margin, c.horizon);
    ASSERT_TRUE(swept.valid()) << "trial " << trial;
    const double tol = 1e-9 * scaleOf(c);
    for (int i = 0; i <= kSteps; ++i) {
      double t = c.horizon * i / kSteps;
      Eigen::Matrix3d R = rotationAt(c.motion, t);
      Eigen::Vector3d centre = centreAt(c.motion, t);
      Eigen::Vector3d e = c.shape.exactHalfExtents(R) + Eigen::Vector3d::Constant(c.margin);
      ASSERT_TRUE(inside(centre - e, centre + e, swept, tol))
          << "trial " << trial << " type " << int(c.shape.type) << " t=" << t
          << "\n body lower " << (centre - e).transpose() << " upper "
          << (centre + e).transpose() << "\n swept lower " << swept.lower.transpose()
          << " upper " << swept.upper.transpose();
      ASSERT_TRUE((e.array() <= rot.array() + tol).all())
          << "trial " << trial << " t=" << t << " exact " << e.transpose()
          << " rotationHalfExtents " << rot.transpose();
      if (c.shape.type == ShapeType::kBox) {
        for (const auto& v : c.shape.surfaceSamples(0)) {
          Eigen::Vector3d w = centre + R * v;
          Eigen::Vector3d m = Eigen::Vector3d::Constant(c.margin);
          ASSERT_TRUE(inside(w - m, w + m, swept, tol)) << "trial " << trial << " t=" << t;
        }
      }
    }
  }
}

// Same property with explicit surface points of the round shapes, each grown by the margin
// along every axis (the margin ball around it), as an oracle independent of the closed forms.
TEST(SweptBounds, ContainsSurfacePointsWithMargin) {
  std::mt19937_64 rng(555);
  const int kSteps = 50;
  for (int trial = 0; trial < 300; ++trial) {
    Case c = randomCase(rng);
    c.shape = randomShape(rng, 1 + trial % 3);  // sphere, cylinder, capsule
    Shape shape = c.shape.make();
    Aabb swept = sweptBounds(shape, c.motion, c.margin, c.horizon);
    const double tol = 1e-9 * scaleOf(c);
    std::vector<Eigen::Vector3d> pts = c.shape.surfaceSamples(300);
    Eigen::Vector3d m = Eigen::Vector3d::Constant(c.margin);
    for (int i = 0; i <= kSteps; ++i) {
      double t = c.horizon * i / kSteps;
      Eigen::Matrix3d R = rotationAt(c.motion, t);
      Eigen::Vector3d centre = centreAt(c.motion, t);
      for (const auto& p : pts) {
        Eigen::Vector3d w = centre + R * p;
        ASSERT_TRUE(inside(w - m, w + m, swept, tol))
            << "trial " << trial << " t=" << t << " point " << w.transpose();
      }
    }
  }
}

// Without rotation the swept box is exactly the union of the start and end boxes grown by
// the margin. Shapes are chosen so the local box's rotated AABB is the exact AABB: boxes at
// any orientation, spheres, and cylinders/capsules at axis-permuting orientations.
TEST(SweptBounds, PureTranslationIsUnionOfEndBoxes) {
  std::mt19937_64 rng(31337);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    Case c = exactAabbCase(rng, trial % 4, 3.0);
    if (trial % 5 == 0) c.motion.linear_velocity[trial % 3] = 0.0;
    c.margin = trial % 3 == 0 ? 0.0 : 0.5 * unit(rng);
    c.horizon = 3.0 * unit(rng);
    Shape shape = c.shape.make();
    Aabb swept = sweptBounds(shape, c.motion, c.margin, c.horizon);
    Eigen::Vector3d e = c.shape.exactHalfExtents(c.motion.orientation.toRotationMatrix()) +
                        Eigen::Vector3d::Constant(c.margin);
    Eigen::Vector3d p0 = centreAt(c.motion, 0.0), p1 = centreAt(c.motion, c.horizon);
    Eigen::Vector3d lo = p0.cwiseMin(p1) - e, hi = p0.cwiseMax(p1) + e;
    const double tol = 1e-12 * scaleOf(c);
    Eigen::Vector3d rot = rotationHalfExtents(shape, c.motion, c.margin, c.horizon);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(swept.lower[k], lo[k], tol) << "trial " << trial << " axis " << k;
      EXPECT_NEAR(swept.upper[k], hi[k], tol) << "trial " << trial << " axis " << k;
      EXPECT_NEAR(rot[k], e[k], tol) << "trial " << trial << " axis " << k;
    }
    if (::testing::Test::HasFailure()) return;  // report the first failing trial only
  }
}

// A zero horizon leaves no time to move or turn: the static AABB (+ margin) at t = 0, even
// with large linear and angular velocity.
TEST(SweptBounds, ZeroHorizonGivesStaticAabb) {
  std::mt19937_64 rng(4242);
  std::uniform_real_distribution<double> vel(-30.0, 30.0), unit(0.0, 1.0);
  for (int trial = 0; trial < 1000; ++trial) {
    Case c = exactAabbCase(rng, trial % 4, 30.0);
    c.motion.angular_velocity = Eigen::Vector3d(vel(rng), vel(rng), vel(rng));
    c.margin = 0.5 * unit(rng);
    Shape shape = c.shape.make();
    Aabb swept = sweptBounds(shape, c.motion, c.margin, 0.0);
    Eigen::Vector3d e = c.shape.exactHalfExtents(c.motion.orientation.toRotationMatrix()) +
                        Eigen::Vector3d::Constant(c.margin);
    const double tol = 1e-12 * scaleOf(c);
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(swept.lower[k], c.motion.position[k] - e[k], tol) << "trial " << trial;
      EXPECT_NEAR(swept.upper[k], c.motion.position[k] + e[k], tol) << "trial " << trial;
    }
    if (::testing::Test::HasFailure()) return;  // report the first failing trial only
  }
}

// The rotation inflation never exceeds the bounding sphere (radius computed here) plus margin,
// however fast the body turns; and it always covers the static extents.
TEST(SweptBounds, RotationHalfExtentsBoundedByBoundingSphere) {
  std::mt19937_64 rng(8080);
  for (int trial = 0; trial < 5000; ++trial) {
    Case c = randomCase(rng);
    if (trial % 4 == 0) c.motion.angular_velocity *= 100.0;  // many revolutions
    if (trial % 7 == 0) c.horizon *= 50.0;
    Shape shape = c.shape.make();
    Eigen::Vector3d rot = rotationHalfExtents(shape, c.motion, c.margin, c.horizon);
    double bound = c.shape.boundingRadius() + c.margin;
    EXPECT_NEAR(shape.boundingRadius(), c.shape.boundingRadius(), 1e-12) << "trial " << trial;
    Eigen::Vector3d e0 = c.shape.exactHalfExtents(c.motion.orientation.toRotationMatrix()) +
                         Eigen::Vector3d::Constant(c.margin);
    for (int k = 0; k < 3; ++k) {
      EXPECT_LE(rot[k], bound * (1.0 + 1e-12) + 1e-12)
          << "trial " << trial << " axis " << k << " type " << int(c.shape.type)
          << " |w|H = " << c.motion.angular_velocity.norm() * c.horizon;
      EXPECT_GE(rot[k], e0[k] - 1e-12 * bound) << "trial " << trial << " axis " << k;
    }
    if (::testing::Test::HasFailure()) return;  // report the first failing trial only
  }
}

// Minimal case of the bounding-sphere cap without any rotation over the horizon: a sphere of
// radius 1 turned 45 degrees about z, not spinning. Its exact half extents are (1, 1, 1) and the
// header promises the result never exceeds the bounding radius (1) plus margin; the rotated
// local box would give (sqrt 2, sqrt 2, 1).
TEST(SweptBounds, StaticRotatedSphereIsCappedByBoundingSphere) {
  BodyMotion m;
  m.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.25 * kPi, Eigen::Vector3d::UnitZ()));
  Shape s = Shape::sphere(1.0);
  Eigen::Vector3d rot = rotationHalfExtents(s, m, 0.0, 1.0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rot[k], 1.0, 1e-12) << "axis " << k;
  Aabb box = sweptBounds(s, m, 0.0, 0.0);
  EXPECT_NEAR(box.upper.x(), 1.0, 1e-12);
  EXPECT_NEAR(box.lower.y(), -1.0, 1e-12);
}

// A sphere is rotation invariant: spinning it must not inflate its bounds at all.
TEST(SweptBounds, SpinningSphereIsNotInflated) {
  BodyMotion m;
  m.position = Eigen::Vector3d(1, 2, 3);
  m.angular_velocity = Eigen::Vector3d(0, 0, 7);
  Shape s = Shape::sphere(0.5);
  Eigen::Vector3d rot = rotationHalfExtents(s, m, 0.1, 2.0);
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(rot[k], 0.6, 1e-12);
}

// A person-sized box turning about the vertical keeps its height, and grows sideways by no
// more than half a turn of its footprint allows; the swept box still contains every pose.
TEST(SweptBounds, SpinAboutAnAxisDoesNotGrowAlongIt) {
  BodyMotion m;
  m.angular_velocity = Eigen::Vector3d(0, 0, 1.0);  // rad/s about z
  const Shape person = Shape::box(Eigen::Vector3d(0.25, 0.25, 0.9));
  const double horizon = 0.5;
  const Eigen::Vector3d h = rotationHalfExtents(person, m, 0.0, horizon);
  EXPECT_DOUBLE_EQ(h.z(), 0.9);
  // Chord of 0.5 rad times the footprint's half extents (0.25 + 0.25): 0.247 m at most.
  const double chord = 2.0 * std::sin(0.25);
  EXPECT_LE(h.x(), 0.25 + chord * 0.5 + 1e-12);
  EXPECT_LE(h.y(), 0.25 + chord * 0.5 + 1e-12);
  for (int s = 0; s <= 100; ++s) {
    const double t = horizon * s / 100.0;
    const Eigen::Matrix3d r = Eigen::AngleAxisd(t, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::Vector3d exact = r.cwiseAbs() * Eigen::Vector3d(0.25, 0.25, 0.9);
    EXPECT_TRUE((exact.array() <= h.array() + 1e-12).all()) << "t=" << t;
  }
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
