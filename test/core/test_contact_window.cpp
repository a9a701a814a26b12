// The contact-window stage against independent oracles (test/shared/oracles.hpp): every
// instant at which two random boxes touch, sampled every millisecond with a separating-axis
// test (or the exact box distance, with margins), lies in the window; for margin-free
// translating boxes the window is the exact contact interval (within the bisected oracle's
// 1e-3 s), and it says so.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "oracles.hpp"
#include "random.hpp"
#include "scenes.hpp"
#include "workspace_proximity/contact_window.hpp"
#include "workspace_proximity/swept_bounds.hpp"

namespace wp = workspace_proximity;

namespace {

constexpr double kHorizon = 1.0;

struct Body {
  wp::Shape shape;
  wp::BodyMotion motion;
  double margin = 0.0;

  wp::PairBody pair() const {
    wp::PairBody b;
    b.shape = &shape;
    b.motion = &motion;
    b.margin = margin;
    b.half = wp::rotationHalfExtents(shape, motion, margin, kHorizon);
    return b;
  }
};

// Box oracle: the boxes overlap (SAT), or with margins their exact distance is within them.
std::function<bool(double)> touching(const Body& a, const Body& b) {
  return [&a, &b](double t) {
    const oracle::Obb oa{oracle::poseAt(a.motion, t), a.shape.half_extents};
    const oracle::Obb ob{oracle::poseAt(b.motion, t), b.shape.half_extents};
    if (oracle::overlaps(oa, ob)) return true;
    return a.margin + b.margin > 0.0 && oracle::boxBoxDistance(oa, ob) <= a.margin + b.margin;
  };
}

// Every sampled contact in [0, horizon] lies in `window`; `any` says whether there was one.
::testing::AssertionResult covers(const wp::TimeInterval& window,
                                  const std::function<bool(double)>& touch, bool* any) {
  *any = false;
  for (int k = 0; k <= 1000; ++k) {
    const double t = k * kHorizon / 1000;
    if (!touch(t)) continue;
    *any = true;
    if (window.empty() || t < window.first || t > window.last) {
      return ::testing::AssertionFailure() << "touches at " << t << ", window [" << window.first
                                           << ", " << window.last << "]";
    }
  }
  return ::testing::AssertionSuccess();
}

Body randomBox(wp_test::Rng& rng, double spin, double max_margin, bool upright = false) {
  Body b;
  b.shape = wp::Shape::box(rng.vector(0.05, 0.6));
  b.motion = wp_test::randomMotion(rng, 1.0, 1.5, spin, upright);
  b.margin = max_margin > 0.0 ? rng.uniform(0.0, max_margin) : 0.0;
  return b;
}

}  // namespace

TEST(ContactWindow, TranslatingBoxesWithoutMarginsGetTheExactInterval) {
  wp_test::Rng rng(101);
  int touching_pairs = 0, tight = 0;
  for (int i = 0; i < 1500; ++i) {
    const Body a = randomBox(rng, 0.0, 0.0), b = randomBox(rng, 0.0, 0.0);
    const wp::ContactWindow w = wp::contactWindow(a.pair(), b.pair(), kHorizon);
    bool any = false;
    ASSERT_TRUE(covers(w.interval, touching(a, b), &any)) << "pair " << i;
    if (w.axis.empty()) continue;  // (the axis window must contain the interval)
    EXPECT_TRUE(w.exact) << "pair " << i;
    EXPECT_TRUE(w.last_known) << "pair " << i;
    if (!w.empty()) {
      EXPECT_GE(w.interval.first, w.axis.first);
      EXPECT_LE(w.interval.last, w.axis.last);
    }
    if (!any) continue;
    ++touching_pairs;
    double first = 0.0, last = 0.0;
    ASSERT_TRUE(oracle::contactTimes(touching(a, b), 0.0, kHorizon, 1e-3, &first, &last));
    tight += w.interval.first >= first - 1e-3 && w.interval.last <= last + 1e-3;
  }
  EXPECT_GT(touching_pairs, 200);
  EXPECT_GE(tight, touching_pairs * 95 / 100);  // misses only grazes between samples
  std::printf("  %d touching, %d within 1 ms\n", touching_pairs, tight);
}

TEST(ContactWindow, UprightTranslatingBoxesGetTheExactIntervalFromTheirFootprints) {
  // Boxes turned about the vertical only (yaw; every fourth one also upside down): the
  // window's own five-axis path for vertical prisms. Without margins it is exact; with margins
  // it still holds every sampled contact.
  wp_test::Rng rng(107);
  int touching_pairs = 0, tight = 0, rounded_touching = 0;
  const Eigen::Quaterniond flip(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()));
  for (int i = 0; i < 2000; ++i) {
    const bool rounded = i % 3 == 2;
    Body a = randomBox(rng, 0.0, rounded ? 0.2 : 0.0, true);
    Body b = randomBox(rng, 0.0, rounded ? 0.2 : 0.0, true);
    if (i % 4 == 1) b.motion.orientation = b.motion.orientation * flip;
    const wp::ContactWindow w = wp::contactWindow(a.pair(), b.pair(), kHorizon);
    bool any = false;
    ASSERT_TRUE(covers(w.interval, touching(a, b), &any)) << "pair " << i;
    if (!any) continue;
    if (rounded) {
      ++rounded_touching;
      continue;
    }
    ++touching_pairs;
    EXPECT_TRUE(w.exact) << "pair " << i;
    double first = 0.0, last = 0.0;
    ASSERT_TRUE(oracle::contactTimes(touching(a, b), 0.0, kHorizon, 1e-3, &first, &last));
    tight += w.interval.first >= first - 1e-3 && w.interval.last <= last + 1e-3;
  }
  EXPECT_GT(touching_pairs, 200);
  EXPECT_GT(rounded_touching, 100);
  EXPECT_GE(tight, touching_pairs * 95 / 100);  // misses only grazes between samples
  std::printf("  %d touching (%d with margins), %d within 1 ms\n", touching_pairs,
              rounded_touching, tight);
}

TEST(ContactWindow, RoundedTranslatingBoxesKnowTheirLastContact) {
  wp_test::Rng rng(103);
  int touching_pairs = 0;
  for (int i = 0; i < 500; ++i) {
    const Body a = randomBox(rng, 0.0, 0.2), b = randomBox(rng, 0.0, 0.2);
    const wp::ContactWindow w = wp::contactWindow(a.pair(), b.pair(), kHorizon);
    bool any = false;
    ASSERT_TRUE(covers(w.interval, touching(a, b), &any)) << "pair " << i;
    touching_pairs += any;
    if (w.axis.empty()) continue;
    EXPECT_EQ(w.exact, a.margin + b.margin == 0.0) << "pair " << i;
    EXPECT_TRUE(w.last_known) << "pair " << i;
  }
  EXPECT_GT(touching_pairs, 100);
  std::printf("  %d touching\n", touching_pairs);
}

TEST(ContactWindow, RoundedUprightTranslatingBoxesGetTheExactInterval) {
  // Rounded upright boxes (trackers' people and vehicles with margins): the footprints' corners
  // make the interval exact wherever the heights overlap throughout it. Checked against the
  // sampled and bisected exact box distance, not against the separating-axis interval. Every
  // other pair stands on the floor (same z, no vertical speed: always decided); the rest move
  // in 3-D, so some must leave it to the narrow phase (contact could start at a rim).
  wp_test::Rng rng(109);
  int decided = 0, undecided = 0, floor_undecided = 0, touching_pairs = 0, corners_moved = 0;
  int missed_corners = 0;
  for (int i = 0; i < 4000; ++i) {
    const bool floor = i % 2 == 0;
    Body a = randomBox(rng, 0.0, 0.3, true), b = randomBox(rng, 0.0, 0.3, true);
    a.margin += 0.01;
    b.margin += 0.01;
    if (floor) {
      a.motion.position.z() = b.motion.position.z() = 0.0;
      a.motion.linear_velocity.z() = b.motion.linear_velocity.z() = 0.0;
    }
    if (i % 7 == 4) {
      // Parallel footprints (the same heading, or a quarter turn apart): edges that face
      // each other whole.
      b.motion.orientation =
          a.motion.orientation * Eigen::Quaterniond(Eigen::AngleAxisd((i % 4) * M_PI / 2,
                                                                      Eigen::Vector3d::UnitZ()));
      b.motion.orientation.x() = b.motion.orientation.y() = 0.0;  // exactly upright
    } else if (i % 5 == 3) {
      // Upside down, exactly (a quaternion (0, x, y, 0) leaves z and x-y uncoupled).
      const double heading = rng.uniform(-M_PI, M_PI);
      b.motion.orientation = Eigen::Quaterniond(0.0, std::cos(heading), std::sin(heading), 0.0);
    }
    const wp::ContactWindow w = wp::contactWindow(a.pair(), b.pair(), kHorizon);
    bool any = false;
    ASSERT_TRUE(covers(w.interval, touching(a, b), &any)) << "pair " << i;
    touching_pairs += any;
    // What the separating axes alone give (the interval before the corners).
    const wp::TimeInterval sat = wp::movingBoxInterval(
        oracle::poseAt(a.motion, 0.0), a.shape.half_extents, a.motion.linear_velocity,
        oracle::poseAt(b.motion, 0.0), b.shape.half_extents, b.motion.linear_velocity,
        a.margin + b.margin, w.axis);
    if (sat.empty()) continue;
    if (!w.exact) {
      ++undecided;
      floor_undecided += floor;
      continue;
    }
    ++decided;
    if (w.empty()) {
      ++missed_corners;  // the square bounds meet, the rounded corners never do
      EXPECT_FALSE(any) << "pair " << i;
      continue;
    }
    corners_moved += w.interval.first > sat.first || w.interval.last < sat.last;
    double first = 0.0, last = 0.0;
    if (!oracle::contactTimes(touching(a, b), 0.0, kHorizon, 1e-3, &first, &last)) {
      // Only a graze shorter than the sampling step can hide from the oracle.
      EXPECT_LT(w.interval.last - w.interval.first, 1e-3) << "pair " << i;
      continue;
    }
    // Exact: within a microsecond of the bisected boundaries (never later at the start or
    // earlier at the end: covers() above).
    EXPECT_NEAR(w.interval.first, first, 1e-6) << "pair " << i;
    EXPECT_NEAR(w.interval.last, last, 1e-6) << "pair " << i;
  }
  EXPECT_EQ(floor_undecided, 0);
  EXPECT_GT(decided, 1000);
  EXPECT_GT(corners_moved, 200);
  EXPECT_GT(missed_corners, 4);
  std::printf("  %d touching; %d decided (%d moved at the corners, %d never meet), %d left to the "
              "narrow phase\n",
              touching_pairs, decided, corners_moved, missed_corners, undecided);
}

TEST(ContactWindow, RoundedCornersMeetWhereTheirDistanceSaysNotWhereTheSquareBoundsDo) {
  // Unit cubes with 0.1 m margins each, b coming along the diagonal at (1, 1, 0) m/s from
  // (-3, -3, 0): the nearest corners are sqrt(2) (2 - t) apart until the cubes overlap, so
  // contact starts at t = 2 - 0.2 / sqrt(2); it ends symmetrically at 4 + 0.2 / sqrt(2). The
  // separating axes alone say [1.8, 4.2].
  Body a, b;
  a.shape = b.shape = wp::Shape::box({0.5, 0.5, 0.5});
  a.margin = b.margin = 0.1;
  b.motion.position = {-3, -3, 0};
  b.motion.linear_velocity = {1, 1, 0};
  const wp::ContactWindow w = wp::contactWindow(a.pair(), b.pair(), 5.0);
  EXPECT_TRUE(w.exact);
  EXPECT_NEAR(w.interval.first, 2.0 - 0.2 / std::sqrt(2.0), 1e-8);
  EXPECT_NEAR(w.interval.last, 4.0 + 0.2 / std::sqrt(2.0), 1e-8);
  EXPECT_LE(w.interval.first, 2.0 - 0.2 / std::sqrt(2.0));
  EXPECT_GE(w.interval.last, 4.0 + 0.2 / std::sqrt(2.0));

  // b's corner passes a's at 0.25 m, going along (1, -1): the square bounds (0.2 m of
  // margins on each axis) meet around t = 2, the rounded corners never do.
  const double c = 0.25 / std::sqrt(2.0), s = 1.0 / std::sqrt(2.0);
  b.motion.position = {1.0 + c - 2.0 * s, 1.0 + c + 2.0 * s, 0.0};
  b.motion.linear_velocity = {s, -s, 0.0};
  const wp::ContactWindow miss = wp::contactWindow(a.pair(), b.pair(), 5.0);
  EXPECT_FALSE(miss.axis.empty());
  EXPECT_TRUE(miss.exact);
  EXPECT_TRUE(miss.empty());
  // 0.3 m of margins instead: the corners come within reach, 0.25 m apart at t = 2.
  b.margin = 0.2;
  const wp::ContactWindow hit = wp::contactWindow(a.pair(), b.pair(), 5.0);
  EXPECT_TRUE(hit.exact);
  const double half_chord = std::sqrt(0.3 * 0.3 - 0.25 * 0.25);  // m, at 1 m/s
  EXPECT_NEAR(hit.interval.first, 2.0 - half_chord, 1e-8);
  EXPECT_NEAR(hit.interval.last, 2.0 + half_chord, 1e-8);
}

TEST(ContactWindow, TurningBodiesKeepTheAxisWindowForTheNarrowPhase) {
  wp_test::Rng rng(107);
  int touching_pairs = 0;
  for (int i = 0; i < 500; ++i) {
    const Body a = randomBox(rng, 4.0, (i % 2) ? 0.1 : 0.0), b = randomBox(rng, 0.0, 0.0);
    const wp::ContactWindow w = wp::contactWindow(a.pair(), b.pair(), kHorizon);
    bool any = false;
    ASSERT_TRUE(covers(w.interval, touching(a, b), &any)) << "pair " << i;
    touching_pairs += any;
    EXPECT_FALSE(w.exact);
    EXPECT_FALSE(w.last_known);
    if (!w.axis.empty()) {
      EXPECT_EQ(w.interval.first, w.axis.first);
      EXPECT_EQ(w.interval.last, w.axis.last);
    }
  }
  EXPECT_GT(touching_pairs, 70);
  std::printf("  %d touching\n", touching_pairs);
}

TEST(ContactWindow, OtherShapesKeepTheAxisWindow) {
  Body a, b;
  a.shape = wp::Shape::sphere(0.5);
  a.motion.linear_velocity = {1, 0, 0};
  b.shape = wp::Shape::box({0.5, 0.5, 0.5});
  b.motion.position = {2.5, 0, 0};
  // Faces 1.5 m apart closing at 1 m/s; the axis window is [1.5, horizon 2].
  const wp::ContactWindow w = wp::contactWindow(a.pair(), b.pair(), 2.0);
  EXPECT_NEAR(w.axis.first, 1.5, 1e-9);
  EXPECT_EQ(w.axis.last, 2.0);
  EXPECT_EQ(w.interval.first, w.axis.first);
  EXPECT_EQ(w.interval.last, w.axis.last);
  EXPECT_FALSE(w.exact);
  EXPECT_FALSE(w.last_known);
  // Out of reach within the horizon: both steps empty.
  const wp::ContactWindow none = wp::contactWindow(a.pair(), b.pair(), 1.0);
  EXPECT_TRUE(none.axis.empty());
  EXPECT_TRUE(none.empty());
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

// A piece of a body's first segment takes its rotation from the body's pose now (PairBody::pose)
// when the body does not turn, and PairPieces remembers its pieces' axis windows: the poses and
// windows must be bit for bit those the segment's motion and pieceAxisWindow build,
// and a turning body, a later segment or a segment whose orientation differs from the body's
// must build their own.
TEST(ContactWindow, PiecePosesAndWindowsFromWhatThePairKnowsEqualThePiecesOwn) {
  wp_test::Rng rng(131);
  for (int trial = 0; trial < 500; ++trial) {
    Body a = randomBox(rng, trial % 3 == 0 ? 1.0 : 0.0, 0.1);
    Body b = randomBox(rng, 0.0, 0.1);
    wp::MarginGrowth growth;
    growth.velocity_error = 0.3;
    growth.max_accel = 4.0;
    growth.age = rng.uniform(0.0, 0.03);
    const Eigen::Isometry3d pose_a = a.motion.poseAt(0.0), pose_b = b.motion.poseAt(0.0);
    wp::PairBody pa = a.pair(), pb = b.pair();
    pa.pose = &pose_a;
    pb.pose = &pose_b;
    pa.growth = &growth;
    const wp::PairPieces pieces(pa, pb, kHorizon);
    ASSERT_GE(pieces.size(), 1);
    for (int i = 0; i < pieces.size(); ++i) {
      const wp::Piece piece = pieces.piece(i);
      // The remembered axis window is the piece's, the first time and later.
      const wp::TimeInterval w = wp::pieceAxisWindow(piece);
      for (int ask = 0; ask < 2; ++ask) {
        const wp::TimeInterval got = pieces.axisWindowOf(i, piece);
        ASSERT_TRUE((got.first == w.first || (std::isnan(got.first) && std::isnan(w.first))) &&
                    (got.last == w.last || (std::isnan(got.last) && std::isnan(w.last))));
      }
      for (const wp::PieceBody* body : {&piece.a, &piece.b}) {
        for (int k = 0; k <= 10; ++k) {
          const double t = piece.u0 + (piece.u1 - piece.u0) * k / 10.0;
          const Eigen::Isometry3d own = body->segment->motion.poseAt(t - body->segment->start);
          const Eigen::Isometry3d got = body->poseAt(t);
          ASSERT_EQ(got.matrix(), own.matrix()) << "trial " << trial << " piece " << i << " t " << t;
        }
      }
    }
  }
  // A path whose first segment's orientation is not the body's (a caller breaking
  // PairBody::segments' rule): the pieces build that segment's own poses, not the pose now's.
  Body c = randomBox(rng, 0.0, 0.1), d = randomBox(rng, 0.0, 0.1);
  const Eigen::Isometry3d pose_c = c.motion.poseAt(0.0);
  wp::PathSegment segment;
  segment.motion = c.motion;
  segment.motion.orientation = wp_test::randomMotion(rng, 1.0, 1.5, 0.0, false).orientation;
  wp::preparePath(c.shape, c.margin, wp::MarginGrowth(), kHorizon, &segment, 1);
  wp::PairBody pc = c.pair(), pd = d.pair();
  pc.pose = &pose_c;
  pc.segments = &segment;
  pc.segment_count = 1;
  const wp::PairPieces pieces(pc, pd, kHorizon);
  ASSERT_EQ(pieces.size(), 1);
  const wp::Piece piece = pieces.piece(0);
  EXPECT_EQ(piece.a.poseAt(0.5).matrix(), segment.motion.poseAt(0.5).matrix());
  EXPECT_NE(piece.a.poseAt(0.5).linear(), pose_c.linear());
}
