// Narrow phase tests. Every expectation comes from an independent oracle (test/shared/
// oracles.hpp: exact box-box distance, separating-axis overlap, segment distances, closed-form
// motion) or an analytic case, never from the code under test. predict() runs as in the
// pipeline: the window's moving separating-axis step (refineWindow), then the narrow phase.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>
#include <limits>
#include <random>
#include <vector>

#include <fcl/geometry/shape/box.h>
#include <fcl/geometry/shape/capsule.h>
#include <fcl/geometry/shape/cylinder.h>
#include <fcl/geometry/shape/sphere.h>
#include <fcl/narrowphase/distance.h>

#include "fcl_geometry.hpp"  // the narrow phase's private geometry (src/core)
#include "oracles.hpp"
#include "random.hpp"
#include "scenes.hpp"
#include "workspace_proximity/contact_window.hpp"
#include "workspace_proximity/narrow_phase.hpp"
#include "workspace_proximity/upright_box_distance.hpp"

namespace workspace_proximity {
namespace {

using Eigen::Isometry3d;
using Eigen::Quaterniond;
using Eigen::Vector3d;
using oracle::boxBoxDistance;
using oracle::makePose;
using oracle::Obb;
using oracle::pointBoxDepth;
using oracle::pointBoxDistance;
using oracle::segmentClosestPoints;
using oracle::segmentDistance;
using wp_test::Rng;

bool boxesOverlap(const Obb& a, const Obb& b) { return oracle::overlaps(a, b); }
Quaterniond yaw(double angle) { return Rng::yaw(angle); }

// ------------------------------------------------------------------------------------------
// Fixtures and helpers.

/// A body for predict(): shape, motion and margin kept alive together.
struct MovingBody {
  Shape shape;
  BodyMotion motion;
  double margin = 0.0;

  MovingBody(const Shape& s, const BodyMotion& m, double margin_m = 0.0)
      : shape(s), motion(m), margin(margin_m) {}
  PairBody body() const {
    PairBody b;
    b.shape = &shape;
    b.motion = &motion;
    b.margin = margin;
    return b;  // no cached geometry: the narrow phase builds it for the query
  }
};

BodyMotion motion(const Vector3d& position, const Vector3d& velocity = Vector3d::Zero(),
                  const Vector3d& angular = Vector3d::Zero(),
                  const Quaterniond& orientation = Quaterniond::Identity()) {
  BodyMotion m;
  m.position = position;
  m.orientation = orientation;
  m.linear_velocity = velocity;
  m.angular_velocity = angular;
  return m;
}

/// The pipeline's order for one pair: the window's second step (the moving separating-axis
/// test for translating boxes) inside [first, last], then the narrow phase inside it.
ContactPrediction predict(const MovingBody& a, const MovingBody& b, double first, double last,
                          const NarrowPhase& phase = NarrowPhase()) {
  const ContactWindow window = refineWindow(a.body(), b.body(), TimeInterval{first, last});
  return phase.predict(a.body(), b.body(), window);
}

/// Random box: half extents in [min_half, max_half), centre within +-reach of the origin.
Obb randomBox(Rng& rng, double min_half, double max_half, double reach, const Quaterniond& q) {
  Obb box;
  box.half = rng.vector(min_half, max_half);
  box.pose = makePose(rng.vector(-reach, reach), q);
  return box;
}

/// The box grown (or shrunk, by < 0) by `by` m on every side.
Obb grown(Obb box, double by) {
  box.half.array() += by;
  return box;
}

ShapeDistance boxDistance(const NarrowPhase& phase, const Obb& a, const Obb& b) {
  return phase.distance(Shape::box(a.half), a.pose, Shape::box(b.half), b.pose);
}

// ------------------------------------------------------------------------------------------
// Geometry construction.

TEST(MakeGeometry, DimensionsMatchFclConventions) {
  const auto box = makeFclGeometry(Shape::box(Vector3d(0.1, 0.2, 0.3)));
  ASSERT_EQ(box->getNodeType(), fcl::GEOM_BOX);
  EXPECT_TRUE(static_cast<const fcl::Boxd&>(*box).side.isApprox(Vector3d(0.2, 0.4, 0.6)));

  const auto sphere = makeFclGeometry(Shape::sphere(0.7));
  ASSERT_EQ(sphere->getNodeType(), fcl::GEOM_SPHERE);
  EXPECT_DOUBLE_EQ(static_cast<const fcl::Sphered&>(*sphere).radius, 0.7);

  const auto cylinder = makeFclGeometry(Shape::cylinder(0.3, 2.0));
  ASSERT_EQ(cylinder->getNodeType(), fcl::GEOM_CYLINDER);
  EXPECT_DOUBLE_EQ(static_cast<const fcl::Cylinderd&>(*cylinder).lz, 2.0);

  // Capsule: FCL's local AABB must end at length / 2 + radius along z.
  const auto capsule = makeFclGeometry(Shape::capsule(0.25, 1.0));
  ASSERT_EQ(capsule->getNodeType(), fcl::GEOM_CAPSULE);
  capsule->computeLocalAABB();
  EXPECT_NEAR(capsule->aabb_local.max_.z(), 0.75, 1e-12);
  EXPECT_NEAR(capsule->aabb_local.max_.x(), 0.25, 1e-12);
}

TEST(MakeGeometry, CapsuleTipIsAtHalfLengthPlusRadius) {
  // A sphere on the capsule axis: distance = centre offset - (length / 2 + r) - r_sphere.
  const NarrowPhase phase;
  const ShapeDistance d = phase.distance(Shape::capsule(0.25, 1.0), Isometry3d::Identity(),
                                         Shape::sphere(0.1), makePose(Vector3d(0, 0, 2.0)));
  EXPECT_NEAR(d.distance, 2.0 - 0.75 - 0.1, 1e-9);
}

// ------------------------------------------------------------------------------------------
// Distance against the exact box-box oracle.

void expectOnBoxSurface(const Vector3d& p, const Obb& box, const char* which) {
  EXPECT_LE(pointBoxDistance(p, box), 1e-7) << which << " point off its box";
  EXPECT_LE(pointBoxDepth(p, box), 1e-7) << which << " point inside its box";
}

// A separated pair's answer against the oracle's distance `truth`: the distance within
// `tolerance` (relative above 1 m), witness points on their boxes and `truth` apart, a unit
// normal (within `unit_tolerance`) from a to b once the gap exceeds `direction_floor`.
// Works for ShapeDistance and UprightBoxDistance alike.
template <class Distance>
void expectSeparatedAnswer(const Distance& d, const Obb& a, const Obb& b, double truth,
                           double tolerance, double unit_tolerance, double direction_floor) {
  ASSERT_FALSE(d.overlapping);
  ASSERT_NEAR(d.distance, truth, tolerance * std::max(1.0, truth));
  expectOnBoxSurface(d.point_a, a, "a");
  expectOnBoxSurface(d.point_b, b, "b");
  EXPECT_NEAR((d.point_b - d.point_a).norm(), truth, tolerance * std::max(1.0, truth));
  EXPECT_NEAR(d.normal.norm(), 1.0, unit_tolerance);
  if (truth > direction_floor) {
    EXPECT_GT(d.normal.dot(d.point_b - d.point_a), 0.0);
  }
}

void checkBoxPair(const NarrowPhase& phase, const Obb& a, const Obb& b) {
  const double truth = boxBoxDistance(a, b);
  expectSeparatedAnswer(boxDistance(phase, a, b), a, b, truth, 1e-6, 1e-9, 1e-6);
}

TEST(NarrowPhaseDistance, RandomBoxPairsMatchExactOracle) {
  const NarrowPhase phase;
  Rng rng(7);
  int checked = 0;
  for (int i = 0; i < 6000; ++i) {
    // A third of the pairs share one orientation (face-parallel, the degenerate case behind
    // fcl #508), a third are axis aligned, the rest are random.
    const Quaterniond qa = (i % 3 == 2) ? Quaterniond::Identity() : rng.rotation();
    const Quaterniond qb = (i % 3 == 0) ? rng.rotation() : qa;
    const Obb a = randomBox(rng, 0.02, 1.0, 2.0, qa);
    const Obb b = randomBox(rng, 0.02, 1.0, 2.0, qb);
    if (boxesOverlap(a, b) || boxBoxDistance(a, b) < 1e-6) continue;
    SCOPED_TRACE(i);
    checkBoxPair(phase, a, b);
    if (HasFatalFailure()) return;
    ++checked;
  }
  EXPECT_GT(checked, 4000);
}

TEST(NarrowPhaseDistance, AxisAlignedBoxesFcl508) {
  // fcl #508: GST_LIBCCD returns 3.16228 here instead of 3.
  const NarrowPhase phase;
  for (int axis = 0; axis < 3; ++axis) {
    Obb a, b;
    a.pose = makePose(Vector3d::Unit(axis) * 4.0);
    checkBoxPair(phase, a, b);
  }
}

TEST(NarrowPhaseDistance, RotatedBoxesWhereIndependentGjkStopsEarly) {
  // FCL 0.7's GST_INDEP GJK reports 0.688354 for this pair; the true distance is 0.670478.
  const NarrowPhase phase;
  Obb a, b;
  a.half = Vector3d(0.25176754445820287, 0.34166939730719925, 0.15538420997073749);
  a.pose.linear() << -0.44307439284787464, 0.87505156281713714, 0.19485852512470014,
      0.06470659263167261, 0.24800717969901132, -0.9665947939481887, -0.89414659831175691,
      -0.41566477025245746, -0.16650723557397029;
  a.pose.translation() << 0.45310581000712702, -0.057801282634837303, -0.24780016337820943;
  b.half = Vector3d(0.42574681570892037, 0.9225358832662266, 0.71491766059089212);
  b.pose.linear() << 0.81950931641725855, 0.30995585107356893, -0.48200814380109508,
      0.46219889823264715, 0.13974894941478677, 0.8756953863130662, 0.33878704045143865,
      -0.94042416043119748, -0.028735686862024101;
  b.pose.translation() << 0.82043380947081346, 1.7602442498969277, -0.86313692746468096;
  ASSERT_FALSE(boxesOverlap(a, b));
  EXPECT_NEAR(boxBoxDistance(a, b), 0.67047787938660974, 1e-9);
  checkBoxPair(phase, a, b);
}

TEST(NarrowPhaseDistance, NearestPointsAreInWorldFrame) {
  // Box a rotated 90 deg about z and far from the origin; b is a sphere beside it on +x.
  const NarrowPhase phase;
  const Vector3d centre(100.0, -50.0, 20.0);
  const Quaterniond q(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitZ()));
  const Shape box = Shape::box(Vector3d(1.0, 0.5, 0.25));  // world x extent is 0.5 after q
  const Shape sphere = Shape::sphere(0.2);
  const ShapeDistance d = phase.distance(box, makePose(centre, q), sphere,
                                         makePose(centre + Vector3d(2.0, 0.3, 0.1)));
  EXPECT_NEAR(d.distance, 2.0 - 0.5 - 0.2, 1e-9);
  EXPECT_TRUE(d.point_a.isApprox(centre + Vector3d(0.5, 0.3, 0.1), 1e-9)) << d.point_a;
  EXPECT_TRUE(d.point_b.isApprox(centre + Vector3d(1.8, 0.3, 0.1), 1e-9)) << d.point_b;
  EXPECT_TRUE(d.normal.isApprox(Vector3d::UnitX(), 1e-9));
}

// ------------------------------------------------------------------------------------------
// Analytic distances for the other shapes.

TEST(NarrowPhaseDistance, SphereSphere) {
  const NarrowPhase phase;
  const Shape a = Shape::sphere(0.5);
  const Shape b = Shape::sphere(0.25);
  const Vector3d ca(1.0, 2.0, 3.0), offset(1.2, -0.4, 0.9);
  const ShapeDistance d = phase.distance(a, makePose(ca), b, makePose(ca + offset));
  const Vector3d n = offset.normalized();
  EXPECT_NEAR(d.distance, offset.norm() - 0.75, 1e-12);
  EXPECT_TRUE(d.point_a.isApprox(ca + 0.5 * n, 1e-9));
  EXPECT_TRUE(d.point_b.isApprox(ca + offset - 0.25 * n, 1e-9));
  EXPECT_TRUE(d.normal.isApprox(n, 1e-9));
}

TEST(NarrowPhaseDistance, SphereBoxFacesEdgesCorners) {
  const NarrowPhase phase;
  Rng rng(11);
  Obb box;
  box.half = Vector3d(0.4, 0.7, 0.2);
  box.pose = makePose(Vector3d(0.3, -0.2, 0.5), rng.rotation());
  const Shape gbox = Shape::box(box.half);
  const Shape sphere = Shape::sphere(0.15);
  for (int i = 0; i < 500; ++i) {
    // Local centres spread around the box so faces, edges and corners are all nearest.
    const Vector3d local = rng.vector(-1.5, 1.5);
    const Vector3d centre = box.pose * local;
    const double truth = pointBoxDistance(centre, box) - 0.15;
    if (truth < 1e-3) continue;
    const ShapeDistance d = phase.distance(gbox, box.pose, sphere, makePose(centre));
    ASSERT_NEAR(d.distance, truth, 1e-9) << local.transpose();
    EXPECT_NEAR((d.point_b - centre).norm(), 0.15, 1e-9);
    EXPECT_LE(pointBoxDistance(d.point_a, box), 1e-9);
  }
}

TEST(NarrowPhaseDistance, CapsuleCapsuleParallelAndCrossed) {
  const NarrowPhase phase;
  const Shape a = Shape::capsule(0.1, 1.0);
  const Shape b = Shape::capsule(0.2, 2.0);
  const Quaterniond along_x(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()));
  // Parallel, side by side with overlapping extents: distance between the axes - radii.
  EXPECT_NEAR(
      phase.distance(a, Isometry3d::Identity(), b, makePose(Vector3d(1.0, 0, 0.3))).distance,
      1.0 - 0.3, 1e-9);
  // Parallel and coaxial: end to end.
  EXPECT_NEAR(
      phase.distance(a, Isometry3d::Identity(), b, makePose(Vector3d(0, 0, 3.0))).distance,
      3.0 - 0.5 - 1.0 - 0.3, 1e-9);
  // Crossed: a along z, b along x, offset along y.
  EXPECT_NEAR(phase.distance(a, Isometry3d::Identity(), b, makePose(Vector3d(0, 0.8, 0), along_x))
                  .distance,
              0.8 - 0.3, 1e-9);
  // Random poses against the segment-distance oracle.
  Rng rng(5);
  for (int i = 0; i < 500; ++i) {
    const Isometry3d pa = makePose(rng.vector(-1, 1), rng.rotation());
    const Isometry3d pb = makePose(rng.vector(-1, 1), rng.rotation());
    const double truth = segmentDistance(pa * Vector3d(0, 0, -0.5), pa * Vector3d(0, 0, 0.5),
                                         pb * Vector3d(0, 0, -1.0), pb * Vector3d(0, 0, 1.0)) -
                         0.3;
    if (truth < 1e-4) continue;
    const ShapeDistance d = phase.distance(a, pa, b, pb);
    ASSERT_NEAR(d.distance, truth, 1e-8);
    EXPECT_NEAR((d.point_b - d.point_a).norm(), truth, 1e-8);
  }
}

TEST(NarrowPhaseDistance, CylinderBox) {
  const NarrowPhase phase;
  const Shape cylinder = Shape::cylinder(0.3, 1.0);
  const Shape box = Shape::box(Vector3d(0.5, 0.5, 0.5));
  const Isometry3d at_origin = Isometry3d::Identity();
  // Standing on top of the box with a 0.2 m gap (flat face to flat face).
  EXPECT_NEAR(
      phase.distance(box, at_origin, cylinder, makePose(Vector3d(0.1, 0.2, 1.2))).distance, 0.2,
      1e-7);
  // Lying along x above the box: the curved side faces the top face.
  const Quaterniond lying(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitY()));
  EXPECT_NEAR(
      phase.distance(box, at_origin, cylinder, makePose(Vector3d(0.2, 0.0, 1.1), lying)).distance,
      1.1 - 0.5 - 0.3, 1e-7);
  // Standing beside a vertical box edge, diagonally: side of the cylinder to the edge.
  const Vector3d c(1.2, 1.1, 0.1);
  const double truth = Vector3d(c.x() - 0.5, c.y() - 0.5, 0.0).norm() - 0.3;
  const ShapeDistance d = phase.distance(box, at_origin, cylinder, makePose(c));
  EXPECT_NEAR(d.distance, truth, 1e-6);
  EXPECT_TRUE(d.point_a.head<2>().isApprox(Eigen::Vector2d(0.5, 0.5), 1e-6)) << d.point_a;
}

// ------------------------------------------------------------------------------------------
// Overlap.

TEST(NarrowPhaseDistance, OverlappingShapesReportZeroAndUnitNormal) {
  const NarrowPhase phase;
  const std::vector<Shape> shapes = {Shape::box(Vector3d(0.5, 0.4, 0.3)), Shape::sphere(0.5),
                                     Shape::cylinder(0.4, 1.0), Shape::capsule(0.3, 0.8)};
  for (const Shape& sa : shapes) {
    for (const Shape& sb : shapes) {
      const Shape& ga = sa;
      const Shape& gb = sb;
      // b's centre 0.5 m along +x from a's: deep overlap, clearly on a's +x side.
      const ShapeDistance d =
          phase.distance(ga, Isometry3d::Identity(), gb, makePose(Vector3d(0.5, 0.05, -0.05)));
      SCOPED_TRACE(static_cast<int>(sa.type) * 10 + static_cast<int>(sb.type));
      EXPECT_TRUE(d.overlapping);
      EXPECT_EQ(d.distance, 0.0);
      EXPECT_NEAR(d.normal.norm(), 1.0, 1e-9);
      EXPECT_GT(d.normal.x(), 0.7) << d.normal.transpose();  // from a towards b
    }
  }
}

TEST(NarrowPhaseDistance, OverlappingCapsulesNormalPointsFromAToB) {
  // Exact oracle: capsules overlap iff their axis segments are closer than the radii sum,
  // and the way out for b is along the segment from a's closest axis point to b's.
  // (FCL 0.7's GST_INDEP EPA reverses this normal; libccd's MPR is approximate but right.)
  const NarrowPhase phase;
  Rng rng(17);
  int checked = 0;
  for (int i = 0; i < 2000; ++i) {
    const double ra = rng.uniform(0.1, 0.3), rb = rng.uniform(0.1, 0.3);
    const double la = rng.uniform(0.2, 1.2), lb = rng.uniform(0.2, 1.2);
    const Isometry3d pa = makePose(rng.vector(-0.5, 0.5), rng.rotation());
    const Isometry3d pb = makePose(rng.vector(-0.5, 0.5), rng.rotation());
    Vector3d ca, cb;
    segmentClosestPoints(pa * Vector3d(0, 0, -la / 2), pa * Vector3d(0, 0, la / 2),
                         pb * Vector3d(0, 0, -lb / 2), pb * Vector3d(0, 0, lb / 2), &ca, &cb);
    const double axis_gap = (cb - ca).norm();
    if (axis_gap < 0.05 || axis_gap > ra + rb - 0.01) continue;  // clearly overlapping only
    const ShapeDistance d = phase.distance((Shape::capsule(ra, la)), pa,
                                           (Shape::capsule(rb, lb)), pb);
    ASSERT_TRUE(d.overlapping) << i;
    EXPECT_EQ(d.distance, 0.0);
    EXPECT_NEAR(d.normal.norm(), 1.0, 1e-9);
    EXPECT_GT(d.normal.dot(cb - ca), 0.0) << i;
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

TEST(NarrowPhaseDistance, RandomOverlappingBoxesAgreeWithSat) {
  const NarrowPhase phase;
  Rng rng(13);
  int overlapping = 0;
  for (int i = 0; i < 3000; ++i) {
    const Obb a = randomBox(rng, 0.05, 0.8, 0.8, rng.rotation());
    const Obb b = randomBox(rng, 0.05, 0.8, 0.8, rng.rotation());
    // Skip near-touching pairs whose verdict depends on solver tolerance.
    if (boxesOverlap(grown(a, -1e-6), b) != boxesOverlap(grown(a, 1e-6), b)) continue;
    const ShapeDistance d =
        phase.distance(Shape::box(a.half), a.pose, Shape::box(b.half), b.pose);
    ASSERT_EQ(d.overlapping, boxesOverlap(a, b)) << i;
    if (!d.overlapping) continue;
    ++overlapping;
    EXPECT_EQ(d.distance, 0.0);
    EXPECT_NEAR(d.normal.norm(), 1.0, 1e-9);
    // Moving b along the normal must be the way out: the normal never points into a.
    EXPECT_GE(d.normal.dot(b.pose.translation() - a.pose.translation()), -1e-9);
  }
  EXPECT_GT(overlapping, 500);
}

// ------------------------------------------------------------------------------------------
// Upright boxes (turned about z only): the closed form against the exact oracle and FCL.


/// Random upright box pose: any yaw, a quarter of them also flipped upside down (still
/// upright: z stays vertical).
Quaterniond uprightRotation(Rng& rng, int i) {
  const Quaterniond q = yaw(rng.uniform(-M_PI, M_PI));
  return (i % 4 == 3) ? q * Quaterniond(0, 1, 0, 0) : q;  // exactly half a turn about x
}

TEST(UprightBoxes, IsUprightAcceptsYawOnly) {
  for (double a : {0.0, 0.3, -2.0, M_PI}) {
    EXPECT_TRUE(isUpright(yaw(a).toRotationMatrix())) << a;
    EXPECT_TRUE(isUpright(makePose(Vector3d::Zero(), yaw(a)).linear())) << a;
  }
  EXPECT_TRUE(isUpright(Eigen::Vector3d(1, -1, -1).asDiagonal().toDenseMatrix()));  // flipped
  EXPECT_TRUE(isUpright((yaw(0.3) * Quaterniond(0, 1, 0, 0)).toRotationMatrix()));
  EXPECT_FALSE(isUpright(Eigen::AngleAxisd(1e-9, Vector3d::UnitX()).toRotationMatrix()));
  EXPECT_FALSE(isUpright(Eigen::AngleAxisd(0.5, Vector3d(0, 1, 1).normalized()).toRotationMatrix()));
  // A yawing body stays exactly upright along its motion (what the narrow phase relies on).
  const BodyMotion m = motion(Vector3d(1, 2, 3), Vector3d(0.5, 0, 0), Vector3d(0, 0, 1.7), yaw(0.4));
  for (double t : {0.1, 0.77, 3.0}) {
    EXPECT_TRUE(isUpright(m.poseAt(t).linear())) << t;
    EXPECT_TRUE(isUpright(m.advanced(t).poseAt(0.0).linear())) << t;
  }
}

TEST(UprightBoxes, RandomPairsMatchExactOracleAndFcl) {
  // Every pair is solved in closed form; the exact vertex/edge oracle and FCL's GJK (called
  // directly, not through the narrow phase) must agree with it.
  Rng rng(71);
  int separated = 0, stacked = 0;
  for (int i = 0; i < 8000; ++i) {
    Obb a, b;
    a.half = rng.vector(0.02, 1.0);
    b.half = rng.vector(0.02, 1.0);
    // Every fifth pair stands on top of the other: footprints overlap, heights do not.
    const bool stack = i % 5 == 0;
    const Vector3d pb = stack ? Vector3d(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3),
                                         a.half.z() + b.half.z() + rng.uniform(-0.2, 1.0))
                              : rng.vector(-2.5, 2.5);
    a.pose = makePose(Vector3d::Zero(), uprightRotation(rng, i));
    b.pose = makePose(pb, (i % 7 == 0) ? Quaterniond(a.pose.linear()) : uprightRotation(rng, i + 1));
    const bool overlap = boxesOverlap(a, b);
    const UprightBoxDistance d = uprightBoxDistance(a.pose, a.half, b.pose, b.half);
    ASSERT_TRUE(d.solved) << i;
    SCOPED_TRACE(i);
    if (overlap) {
      ASSERT_TRUE(d.overlapping || d.distance < 1e-12);
      continue;
    }
    const double truth = boxBoxDistance(a, b);
    if (truth < 1e-9) continue;  // touching: either verdict is right
    ASSERT_NO_FATAL_FAILURE(expectSeparatedAnswer(d, a, b, truth, 1e-9, 1e-12, 0.0));
    // FCL's GJK, straight: agrees within its own tolerance.
    fcl::DistanceRequestd request(true, false, 0.0, 0.0, 1e-9, fcl::GST_INDEP);
    fcl::DistanceResultd result;
    fcl::distance(makeFclGeometry(Shape::box(a.half)).get(), a.pose,
                  makeFclGeometry(Shape::box(b.half)).get(), b.pose, request, result);
    EXPECT_LE(d.distance, result.min_distance + 1e-7);
    // And the narrow phase answers the same through its public interface.
    const ShapeDistance nd =
        NarrowPhase().distance(Shape::box(a.half), a.pose, Shape::box(b.half), b.pose);
    EXPECT_EQ(nd.distance, d.distance);
    separated += 1;
    stacked += stack;
    if (HasFailure()) return;
  }
  EXPECT_GT(separated, 5000);
  EXPECT_GT(stacked, 800);
}

TEST(UprightBoxes, OverlappingPairsGiveAPointInBothAndAWayOut) {
  Rng rng(73);
  int overlapping = 0;
  for (int i = 0; i < 4000; ++i) {
    const Obb a = randomBox(rng, 0.05, 0.8, 0.8, uprightRotation(rng, i));
    const Obb b = randomBox(rng, 0.05, 0.8, 0.8, uprightRotation(rng, i + 2));
    if (!boxesOverlap(grown(a, -1e-6), b)) continue;  // clearly overlapping
    SCOPED_TRACE(i);
    const UprightBoxDistance d = uprightBoxDistance(a.pose, a.half, b.pose, b.half);
    ASSERT_TRUE(d.solved);
    ASSERT_TRUE(d.overlapping);
    ++overlapping;
    EXPECT_LE(pointBoxDistance(d.point_a, a), 1e-9);
    EXPECT_LE(pointBoxDistance(d.point_a, b), 1e-9);
    EXPECT_NEAR(d.normal.norm(), 1.0, 1e-12);
    EXPECT_GE(d.normal.dot(b.pose.translation() - a.pose.translation()), -1e-12);
    // The normal is the least-penetration axis: pushing b out along it by the overlap on
    // that axis (plus a hair) separates the boxes, and no shorter push along any of the
    // 15 separating-axis candidates (brute force over directions here) does better.
    auto projectedOverlap = [&](const Vector3d& n) {
      double ra = 0.0, rb = 0.0;
      for (int k = 0; k < 3; ++k) {
        ra += a.half[k] * std::abs(a.pose.linear().col(k).dot(n));
        rb += b.half[k] * std::abs(b.pose.linear().col(k).dot(n));
      }
      return ra + rb - std::abs(n.dot(b.pose.translation() - a.pose.translation()));
    };
    const double depth = projectedOverlap(d.normal);
    Obb pushed = b;
    pushed.pose.translation() += d.normal * (depth + 1e-6);
    EXPECT_FALSE(boxesOverlap(a, pushed));
    for (int k = 0; k < 200; ++k) {
      const Vector3d n = rng.rotation() * Vector3d::UnitX();
      EXPECT_GE(projectedOverlap(n), depth - 1e-9);
    }
    const ShapeDistance nd =
        NarrowPhase().distance(Shape::box(a.half), a.pose, Shape::box(b.half), b.pose);
    EXPECT_TRUE(nd.overlapping);
    EXPECT_EQ(nd.distance, 0.0);
    if (HasFailure()) return;
  }
  EXPECT_GT(overlapping, 1000);
}

// ------------------------------------------------------------------------------------------
// predict(): translation only, closed form.

// The first contact never later than `first` + `slack` and at most `tolerance` earlier; the
// separation never earlier than `last` - `slack` and at most `tolerance` later (s).
void expectContactWindow(const ContactPrediction& p, double first, double last, double tolerance,
                         double slack = 1e-12) {
  EXPECT_LE(p.time_to_contact, first + slack);
  EXPECT_GE(p.time_to_contact, first - tolerance);
  EXPECT_GE(p.time_to_separation, last - slack);
  EXPECT_LE(p.time_to_separation, last + tolerance);
}

TEST(NarrowPhasePredict, HeadOnBoxesExactContactAndSeparation) {
  // Unit cubes 3 m apart closing at 0.7 + 0.6 m/s: gap 2 m, contact at 2 / 1.3 s; they pass
  // through each other and separate when the gap on the far side is 0 again: 4 / 1.3 s.
  const MovingBody a(Shape::box(Vector3d::Constant(0.5)),
                     motion(Vector3d(0, 0, 0), Vector3d(0.7, 0, 0)));
  const MovingBody b(Shape::box(Vector3d::Constant(0.5)),
                     motion(Vector3d(3, 0, 0), Vector3d(-0.6, 0, 0)));
  const ContactPrediction p = predict(a, b, 0.0, 10.0);
  const double truth_contact = 2.0 / 1.3, truth_separation = 4.0 / 1.3;
  ASSERT_TRUE(p.contact);
  expectContactWindow(p, truth_contact, truth_separation, 1e-5);
  EXPECT_NEAR(p.distance, 2.0, 1e-9);
  EXPECT_NEAR(p.closing_speed, 1.3, 1e-9);
  EXPECT_TRUE(p.normal.isApprox(Vector3d::UnitX(), 1e-9));
  EXPECT_GT(p.iterations, 0);
}

TEST(NarrowPhasePredict, ObliqueApproachConvergesWithinAMillisecond) {
  // a static; b slides in diagonally. Per axis: y overlaps from t = 1 s to 11 s, x from
  // t = 2 s (b's left face 2.5 - t reaches 0.5) to 4 s. Contact 2 s to 4 s.
  const MovingBody a(Shape::box(Vector3d::Constant(0.5)), motion(Vector3d::Zero()));
  const MovingBody b(Shape::box(Vector3d::Constant(0.5)),
                     motion(Vector3d(3, 1.2, 0), Vector3d(-1, -0.2, 0)));
  const ContactPrediction p = predict(a, b, 0.0, 6.0);
  ASSERT_TRUE(p.contact);
  expectContactWindow(p, 2.0, 4.0, 1e-3);
}

TEST(NarrowPhasePredict, MarginsShiftContactTime) {
  // Margins 0.1 + 0.2 m eat into the 2 m gap: contact at 1.7 / 2 s, separation at 4.3 / 2 s.
  const MovingBody a(Shape::box(Vector3d::Constant(0.5)),
                     motion(Vector3d::Zero(), Vector3d(1, 0, 0)), 0.1);
  const MovingBody b(Shape::box(Vector3d::Constant(0.5)),
                     motion(Vector3d(3, 0, 0), Vector3d(-1, 0, 0)), 0.2);
  const ContactPrediction p = predict(a, b, 0.0, 5.0);
  ASSERT_TRUE(p.contact);
  expectContactWindow(p, 0.85, 2.15, 1e-5);
  EXPECT_NEAR(p.distance, 1.7, 1e-9);  // the inflated gap now
}

TEST(NarrowPhasePredict, NearMissReportsNoContact) {
  // b passes 5 cm beside a.
  const MovingBody a(Shape::box(Vector3d::Constant(0.5)),
                     motion(Vector3d::Zero(), Vector3d(1, 0, 0)));
  const MovingBody b(Shape::box(Vector3d::Constant(0.5)),
                     motion(Vector3d(3, 1.05, 0), Vector3d(-1, 0, 0)));
  const ContactPrediction p = predict(a, b, 0.0, 5.0);
  EXPECT_FALSE(p.contact);
  EXPECT_NEAR(p.distance, Vector3d(2.0, 0.05, 0).norm(), 1e-9);
  // A margin wider than the miss turns it into a contact.
  const MovingBody b_wide(b.shape, b.motion, 0.06);
  EXPECT_TRUE(predict(a, b_wide, 0.0, 5.0).contact);
}

TEST(NarrowPhasePredict, WindowsAreRespected) {
  const MovingBody a(Shape::box(Vector3d::Constant(0.5)),
                     motion(Vector3d::Zero(), Vector3d(1, 0, 0)));
  const MovingBody b(Shape::box(Vector3d::Constant(0.5)),
                     motion(Vector3d(3, 0, 0), Vector3d(-1, 0, 0)));
  // Contact from 1 s to 2 s.
  EXPECT_FALSE(predict(a, b, 0.0, 0.9).contact);
  EXPECT_FALSE(predict(a, b, 2.1, 5.0).contact);
  const ContactPrediction inside = predict(a, b, 1.5, 1.8);
  ASSERT_TRUE(inside.contact);
  EXPECT_EQ(inside.time_to_contact, 1.5);
  EXPECT_EQ(inside.time_to_separation, 1.8);
  const ContactPrediction late = predict(a, b, 0.5, 5.0);
  ASSERT_TRUE(late.contact);
  EXPECT_NEAR(late.time_to_contact, 1.0, 1e-5);
  EXPECT_LE(late.time_to_contact, 1.0 + 1e-12);
  // An empty window predicts nothing but still describes t = 0.
  const ContactPrediction empty = predict(a, b, 1.0, 0.0);
  EXPECT_FALSE(empty.contact);
  EXPECT_NEAR(empty.distance, 2.0, 1e-9);
  EXPECT_NEAR(empty.closing_speed, 2.0, 1e-9);
  EXPECT_TRUE(empty.normal.isApprox(Vector3d::UnitX(), 1e-9));
}

TEST(NarrowPhasePredict, StaticPairs) {
  const MovingBody a(Shape::box(Vector3d::Constant(0.5)), motion(Vector3d::Zero()));
  const MovingBody apart(Shape::sphere(0.5), motion(Vector3d(2, 0, 0)));
  EXPECT_FALSE(predict(a, apart, 0.0, 10.0).contact);
  const MovingBody touching(Shape::sphere(0.5), motion(Vector3d(0.8, 0, 0)));
  const ContactPrediction p = predict(a, touching, 0.0, 10.0);
  ASSERT_TRUE(p.contact);
  EXPECT_EQ(p.time_to_contact, 0.0);
  EXPECT_EQ(p.time_to_separation, 10.0);
  EXPECT_EQ(p.distance, 0.0);
}

TEST(NarrowPhasePredict, ClosingSpeedIncludesRotation) {
  // Sphere a beside the -x face of box b, which spins about z at 1 rad/s. b's nearest point
  // (1.5, 1.5, 0) is 1.5 m off b's axis along y, so it moves at w x r = (-1.5, -0.5, 0):
  // towards a at 1.5 m/s.
  const MovingBody a(Shape::sphere(0.5), motion(Vector3d(0, 1.5, 0)));
  const MovingBody b(Shape::box(Vector3d(0.5, 2.0, 0.5)),
                     motion(Vector3d(2, 0, 0), Vector3d::Zero(), Vector3d(0, 0, 1)));
  const ContactPrediction p = predict(a, b, 0.0, 0.0);
  EXPECT_NEAR(p.distance, 1.0, 1e-9);
  EXPECT_TRUE(p.point_b.isApprox(Vector3d(1.5, 1.5, 0), 1e-9)) << p.point_b;
  EXPECT_NEAR(p.closing_speed, 1.5, 1e-9);
}

// ------------------------------------------------------------------------------------------
// predict() with rotation, against brute-force oracles.

/// Contact oracle for two boxes with margins: SAT overlap, else exact distance <= margins.
std::function<bool(double)> boxContactOracle(const MovingBody& a, const MovingBody& b) {
  return [&a, &b](double t) {
    Obb oa{oracle::poseAt(a.motion, t), a.shape.half_extents};
    Obb ob{oracle::poseAt(b.motion, t), b.shape.half_extents};
    if (boxesOverlap(oa, ob)) return true;
    return a.margin + b.margin > 0.0 && boxBoxDistance(oa, ob) <= a.margin + b.margin;
  };
}

void expectMatchesOracle(const MovingBody& a, const MovingBody& b, double t0, double t1,
                         double max_early) {
  double first = 0.0, last = 0.0;
  ASSERT_TRUE(oracle::contactTimes(boxContactOracle(a, b), t0, t1, 1e-4, &first, &last));
  const ContactPrediction p = predict(a, b, t0, t1);
  ASSERT_TRUE(p.contact);
  expectContactWindow(p, first, last, max_early, 0.0);
}

TEST(NarrowPhasePredict, RotatingBarSweepsIntoBox) {
  // A 2 m bar spinning about z at 1 rad/s around its centre hits a cube at (0.3, 0.8).
  const MovingBody bar(Shape::box(Vector3d(1.0, 0.05, 0.05)),
                       motion(Vector3d::Zero(), Vector3d::Zero(), Vector3d(0, 0, 1)));
  const MovingBody cube(Shape::box(Vector3d::Constant(0.1)), motion(Vector3d(0.3, 0.8, 0)));
  expectMatchesOracle(bar, cube, 0.0, 2.5, 5e-3);
}

TEST(NarrowPhasePredict, TumblingBoxesWithMargins) {
  const MovingBody a(Shape::box(Vector3d(0.6, 0.2, 0.1)),
                     motion(Vector3d(-0.5, 0, 0), Vector3d(0.3, 0.1, 0), Vector3d(0.5, 1.0, 2.0),
                            Quaterniond(Eigen::AngleAxisd(0.4, Vector3d(1, 1, 0).normalized()))),
                     0.05);
  const MovingBody b(Shape::box(Vector3d(0.1, 0.3, 0.4)),
                     motion(Vector3d(1.0, 0.2, 0.1), Vector3d(-0.2, 0, 0), Vector3d(0, -1.5, 0.5)),
                     0.02);
  expectMatchesOracle(a, b, 0.0, 3.0, 5e-3);
}

/// Zero false negatives against a sampled oracle: every millisecond in [0, 1] at which
/// `touching` holds lies in [time_to_contact, time_to_separation]. `any`: some sample touched.
::testing::AssertionResult coversSampledContacts(const ContactPrediction& p,
                                                 const std::function<bool(double)>& touching,
                                                 bool* any) {
  *any = false;
  for (int k = 0; k <= 1000; ++k) {
    const double t = k * 1e-3;
    if (!touching(t)) continue;
    *any = true;
    if (!p.contact) return ::testing::AssertionFailure() << "touches at " << t << ", no contact";
    if (p.time_to_contact > t) {
      return ::testing::AssertionFailure()
             << "touches at " << t << ", contact predicted at " << p.time_to_contact;
    }
    if (p.time_to_separation < t) {
      return ::testing::AssertionFailure()
             << "touches at " << t << ", separation predicted at " << p.time_to_separation;
    }
  }
  return ::testing::AssertionSuccess();
}

/// One pair predicted against the oracle: the prediction, whether the oracle saw contact, and
/// then its bisected first and last contact times (s).
struct OracleRun {
  ContactPrediction p;
  bool touches = false;
  double first = 0.0, last = 0.0;
};

/// The pair predicted over [0, 1] against a sampled oracle: every sampled contact covered
/// (zero false negatives). When the oracle sees contact (`run->touches`), `run->first` and
/// `run->last` get its bisected contact times.
::testing::AssertionResult predictAgainstOracle(const NarrowPhase& phase, const MovingBody& a,
                                                const MovingBody& b,
                                                const std::function<bool(double)>& touching,
                                                OracleRun* run) {
  run->p = predict(a, b, 0.0, 1.0, phase);
  const ::testing::AssertionResult covered = coversSampledContacts(run->p, touching, &run->touches);
  if (!covered || !run->touches) return covered;
  if (!oracle::contactTimes(touching, 0.0, 1.0, 1e-3, &run->first, &run->last)) {
    return ::testing::AssertionFailure() << "the oracle's samples and its bisection disagree";
  }
  return ::testing::AssertionSuccess();
}

/// Random moving body: size from `shape_of`, position within 1 m of the origin, speeds up
/// to ~2.6 m/s and 5 rad/s.
template <typename ShapeOf>
MovingBody randomBody(Rng& rng, ShapeOf shape_of, double max_margin) {
  const Shape shape = shape_of(rng);
  const BodyMotion m = wp_test::randomMotion(rng, 1.0, 1.5, 5.0);
  return MovingBody(shape, m, rng.uniform(0.0, max_margin));
}

/// Runs predict() on random pairs and checks it against a sampled + bisected oracle:
/// every sampled contact lies in [time_to_contact, time_to_separation] (zero false
/// negatives), and contact is rarely reported much earlier than the oracle's first contact.
template <typename ShapeOf, typename Oracle>
void checkRandomPairs(unsigned seed, int pairs, ShapeOf shape_of, double max_margin,
                      Oracle make_oracle) {
  const NarrowPhase phase;
  Rng rng(seed);
  int with_contact = 0, tight = 0, false_alarms = 0;
  for (int i = 0; i < pairs; ++i) {
    const MovingBody a = randomBody(rng, shape_of, (i % 2) ? max_margin : 0.0);
    const MovingBody b = randomBody(rng, shape_of, (i % 2) ? max_margin : 0.0);
    OracleRun r;
    ASSERT_TRUE(predictAgainstOracle(phase, a, b, make_oracle(a, b), &r)) << "pair " << i;
    const ContactPrediction& p = r.p;
    const double first = r.first, last = r.last;
    if (!r.touches) {
      false_alarms += p.contact;
      continue;
    }
    ++with_contact;
    EXPECT_LE(p.time_to_contact, first) << "pair " << i;
    EXPECT_GE(p.time_to_separation, last) << "pair " << i;
    tight += p.time_to_contact >= first - 1e-3 && p.time_to_separation <= last + 1e-3;
  }
  EXPECT_GT(with_contact, pairs / 8);
  // Early answers come from grazes between oracle samples or from the iteration cap.
  EXPECT_GE(tight, with_contact * 9 / 10);
  EXPECT_LE(false_alarms, (pairs - with_contact) / 10);
  std::printf("  %d pairs, %d touching, %d within 1 ms, %d false alarms\n", pairs, with_contact,
              tight, false_alarms);
}

TEST(NarrowPhasePredict, RandomBoxMotionsHaveNoFalseNegatives) {
  checkRandomPairs(
      21, 600, [](Rng& rng) { return Shape::box(rng.vector(0.05, 0.6)); }, 0.1,
      [](const MovingBody& a, const MovingBody& b) { return boxContactOracle(a, b); });
}

// Boxes that only translate take the closed-form moving separating-axis path: exact
// without margins; with margins (rounded boxes) its interval is refined for the first
// contact and kept as the (conservative) last contact.
TEST(NarrowPhasePredict, RandomTranslatingBoxesHaveNoFalseNegatives) {
  const NarrowPhase phase;
  Rng rng(57);
  int with_contact = 0, tight_first = 0, exact_both = 0, no_margin = 0;
  for (int i = 0; i < 1500; ++i) {
    auto body = [&](double margin) {
      const BodyMotion m = wp_test::randomMotion(rng, 1.0, 1.5, 0.0);
      return MovingBody(Shape::box(rng.vector(0.05, 0.6)), m, margin);
    };
    const bool margins = i % 2 == 1;
    const MovingBody a = body(margins ? rng.uniform(0.0, 0.2) : 0.0);
    const MovingBody b = body(margins ? rng.uniform(0.0, 0.2) : 0.0);
    OracleRun r;
    ASSERT_TRUE(predictAgainstOracle(phase, a, b, boxContactOracle(a, b), &r)) << "pair " << i;
    const ContactPrediction& p = r.p;
    const double first = r.first, last = r.last;
    if (!r.touches) continue;
    ++with_contact;
    tight_first += p.time_to_contact >= first - 1e-3;
    if (!margins) {
      ++no_margin;
      exact_both += p.time_to_contact >= first - 1e-3 && p.time_to_separation <= last + 1e-3;
    }
  }
  EXPECT_GT(with_contact, 150);
  EXPECT_GE(tight_first, with_contact * 95 / 100);
  EXPECT_GE(exact_both, no_margin * 95 / 100);  // misses only grazes between samples
  std::printf("  %d touching, %d first contacts within 1 ms, %d of %d exact without margins\n",
              with_contact, tight_first, exact_both, no_margin);
}

TEST(NarrowPhasePredict, RandomCapsuleMotionsHaveNoFalseNegatives) {
  // Capsules are exact against segment distance, so this covers curved shapes too.
  auto oracle = [](const MovingBody& a, const MovingBody& b) {
    return std::function<bool(double)>([&a, &b](double t) {
      const Isometry3d pa = oracle::poseAt(a.motion, t), pb = oracle::poseAt(b.motion, t);
      const double ha = 0.5 * a.shape.length, hb = 0.5 * b.shape.length;
      return segmentDistance(pa * Vector3d(0, 0, -ha), pa * Vector3d(0, 0, ha),
                             pb * Vector3d(0, 0, -hb), pb * Vector3d(0, 0, hb)) <=
             a.shape.radius + b.shape.radius + a.margin + b.margin;
    });
  };
  checkRandomPairs(
      33, 1000,
      [](Rng& rng) { return Shape::capsule(rng.uniform(0.05, 0.3), rng.uniform(0.0, 1.5)); }, 0.05,
      oracle);
}

TEST(UprightBoxes, RandomYawingAndTranslatingPairsHaveNoFalseNegatives) {
  // Upright bodies turning about z (and translating in 3-D) stay upright, so every distance
  // of the advancement is the closed form; the oracle is the exact box distance.
  auto upright_body = [](Rng& rng, double max_margin) {
    const Shape shape = Shape::box(rng.vector(0.05, 0.6));
    const BodyMotion m = wp_test::randomMotion(rng, 1.0, 1.5, 3.0, true);
    return MovingBody(shape, m, rng.uniform(0.0, max_margin));
  };
  const NarrowPhase phase;
  Rng rng(79);
  int with_contact = 0, tight = 0;
  for (int i = 0; i < 1500; ++i) {
    const double max_margin = (i % 2) ? 0.2 : 0.0;
    MovingBody a = upright_body(rng, max_margin);
    MovingBody b = upright_body(rng, max_margin);
    if (i % 3 == 0) b.motion.angular_velocity.setZero();  // one translating
    if (i % 6 == 0) a.motion.angular_velocity.setZero();  // both: moving axis test + advancement
    OracleRun r;
    ASSERT_TRUE(predictAgainstOracle(phase, a, b, boxContactOracle(a, b), &r)) << "pair " << i;
    if (!r.touches) continue;
    ++with_contact;
    EXPECT_LE(r.p.time_to_contact, r.first) << "pair " << i;
    EXPECT_GE(r.p.time_to_separation, r.last) << "pair " << i;
    tight += r.p.time_to_contact >= r.first - 1e-3;
  }
  EXPECT_GT(with_contact, 200);
  EXPECT_GE(tight, with_contact * 95 / 100);
  std::printf("  %d touching, %d first contacts within 1 ms\n", with_contact, tight);
}

TEST(UprightBoxes, TranslatingWithMarginsFirstContactIsTightAndNeverLate) {
  // Rounded upright boxes that only translate: the exact gap is convex in time, so the
  // narrow phase takes Newton steps. The first contact must never be late and, unlike plain
  // advancement on grazing approaches, lands within 1 ms of the bisected truth every time;
  // a pair whose gap stops shrinking is dropped early, which the oracle must confirm.
  const NarrowPhase phase;
  Rng rng(83);
  int with_contact = 0, tight = 0, queries = 0;
  for (int i = 0; i < 2000; ++i) {
    auto body = [&]() {
      const BodyMotion m = wp_test::randomMotion(rng, 1.5, 1.5, 0.0, true);
      return MovingBody(Shape::box(rng.vector(0.05, 0.6)), m, rng.uniform(0.0, 0.3));
    };
    const MovingBody a = body(), b = body();
    const ContactPrediction p = predict(a, b, 0.0, 1.0, phase);
    queries += p.iterations;
    const std::function<bool(double)> touching = boxContactOracle(a, b);
    double first = 0.0, last = 0.0;
    if (!oracle::contactTimes(touching, 0.0, 1.0, 1e-3, &first, &last)) continue;
    ++with_contact;
    ASSERT_TRUE(p.contact) << "pair " << i << " touches at " << first;
    ASSERT_LE(p.time_to_contact, first) << "pair " << i;
    ASSERT_GE(p.time_to_separation, last) << "pair " << i;
    tight += p.time_to_contact >= first - 1e-3;
  }
  EXPECT_GT(with_contact, 300);
  EXPECT_EQ(tight, with_contact);
  std::printf("  %d touching, %d first contacts within 1 ms, %.2f distance queries per pair\n",
              with_contact, tight, double(queries) / 2000);
}

TEST(UprightBoxes, ExactWindowsReportTheSameAsTheGeneralPathBitForBit) {
  // A pair whose window is exact (rounded upright boxes: roundedUprightInterval) and whose
  // poses now the caller hands over is answered straight from the closed form, skipping the
  // query's set-up. That shortcut must change nothing: the same pair without poses takes the
  // general path (poses built from the motions, evaluate()), compared field by field.
  const NarrowPhase phase;
  Rng rng(89);
  int exact = 0, touching = 0;
  for (int i = 0; i < 3000; ++i) {
    auto body = [&]() {
      BodyMotion m = wp_test::randomMotion(rng, 1.5, 1.5, 0.0, true);
      if (i % 2 == 0) m.position.z() = m.linear_velocity.z() = 0.0;
      return MovingBody(Shape::box(rng.vector(0.05, 0.6)), m, rng.uniform(0.0, 0.3));
    };
    const MovingBody a = body(), b = body();
    const Isometry3d pose_a = a.motion.poseAt(0.0), pose_b = b.motion.poseAt(0.0);
    PairBody with_a = a.body(), with_b = b.body();
    with_a.pose = &pose_a;
    with_b.pose = &pose_b;
    const ContactWindow window = refineWindow(with_a, with_b, TimeInterval{0.0, 1.0});
    exact += window.exact;
    const ContactPrediction fast = phase.predict(with_a, with_b, window);
    const ContactPrediction general = phase.predict(a.body(), b.body(), window);
    touching += fast.contact;
    ASSERT_EQ(fast.contact, general.contact) << "pair " << i;
    EXPECT_EQ(fast.time_to_contact, general.time_to_contact) << "pair " << i;
    EXPECT_EQ(fast.time_to_separation, general.time_to_separation) << "pair " << i;
    EXPECT_EQ(fast.distance, general.distance) << "pair " << i;
    EXPECT_EQ(fast.closing_speed, general.closing_speed) << "pair " << i;
    EXPECT_EQ(fast.iterations, general.iterations) << "pair " << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(fast.point_a[k], general.point_a[k]) << "pair " << i;
      EXPECT_EQ(fast.point_b[k], general.point_b[k]) << "pair " << i;
      EXPECT_EQ(fast.normal[k], general.normal[k]) << "pair " << i;
    }
  }
  EXPECT_GT(exact, 1000);
  EXPECT_GT(touching, 200);
  std::printf("  %d exact windows, %d with contact\n", exact, touching);
}

}  // namespace
}  // namespace workspace_proximity

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
