// Skeletons as limb capsules as boxes (issue 24 item 4): the capsule's box against analytic
// capsules (every capsule point inside, every face touched), the capsule's velocity bound
// against capsules moved joint by joint, the body parts of real trackers' bone names, the
// converter's ids, radii and unknown velocities, and the jsk and Azure Kinect decoders on
// messages written by hand from the upstream definitions (foreign_msgs/, the driver's source).

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "allocation_counter.hpp"
#include "wire_writer.hpp"
#include "workspace_proximity/rules/foreign_skeletons.hpp"
#include "workspace_proximity/rules/skeleton_capsules.hpp"
#include "workspace_proximity/rules/track_growth.hpp"

namespace wp = workspace_proximity;
using Eigen::Vector3d;

namespace {

constexpr char kJskMd5[] = "4013ce44abe9aafa9055e095797a9d50";
constexpr char kMarkerArrayMd5[] = "d155b9ce5188fbaf89745847fd5882d7";

// Distance from p to the segment a-b: the oracle, written from its definition.
double segmentDistance(const Vector3d& p, const Vector3d& a, const Vector3d& b) {
  const Vector3d d = b - a;
  const double len2 = d.squaredNorm();
  const double s = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + s * d)).norm();
}

Vector3d randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Vector3d u(n(rng), n(rng), n(rng));
  return u.normalized();
}

// A point of the box's frame: the box's rotation transposed times the offset from its centre.
Vector3d local(const Vector3d& p, const Vector3d& centre, const Eigen::Vector4d& q) {
  const Eigen::Quaterniond rotation(q.w(), q.x(), q.y(), q.z());
  return rotation.conjugate() * (p - centre);
}

TEST(CapsuleBox, HoldsEveryCapsulePointAndTouchesEveryFace) {
  std::mt19937 rng(24);
  std::uniform_real_distribution<double> coord(-2.0, 2.0), unit(0.0, 1.0), radius(0.01, 0.3);
  for (int trial = 0; trial < 200; ++trial) {
    wp::Capsule c;
    c.a = Vector3d(coord(rng), coord(rng), coord(rng));
    c.b = trial % 20 == 0 ? c.a : Vector3d(coord(rng), coord(rng), coord(rng));  // some spheres
    c.radius = radius(rng);
    Vector3d centre, dims;
    Eigen::Vector4d q;
    wp::capsuleBox(c, &centre, &q, &dims);
    const Vector3d half = 0.5 * dims;
    // Points on the capsule's surface (and inside): a segment point plus up to r.
    for (int i = 0; i < 2000; ++i) {
      const double s = i < 2 ? i : unit(rng);  // the ends too
      const Vector3d p = c.a + s * (c.b - c.a) + c.radius * randomUnit(rng);
      ASSERT_LE(segmentDistance(p, c.a, c.b), c.radius + 1e-12);
      const Vector3d l = local(p, centre, q);
      for (int k = 0; k < 3; ++k) {
        ASSERT_LE(std::abs(l[k]), half[k] + 1e-9) << "trial " << trial << " axis " << k;
      }
    }
    // Tight: along each of its axes, both ways, the capsule's support point (the farther end
    // joint plus r along the axis, a capsule point by the oracle) lies on the box's face.
    const Eigen::Quaterniond rotation(q.w(), q.x(), q.y(), q.z());
    for (int k = 0; k < 3; ++k) {
      for (double sign : {-1.0, 1.0}) {
        const Vector3d e = sign * rotation.toRotationMatrix().col(k);
        const Vector3d end = (c.a.dot(e) >= c.b.dot(e)) ? c.a : c.b;
        const Vector3d support = end + c.radius * e;
        EXPECT_NEAR(segmentDistance(support, c.a, c.b), c.radius, 1e-9);
        EXPECT_NEAR(sign * local(support, centre, q)[k], half[k], 1e-9) << trial << " " << k;
      }
    }
    const double length = (c.b - c.a).norm();
    EXPECT_NEAR(dims.x(), 2.0 * c.radius, 1e-12);
    EXPECT_NEAR(dims.y(), 2.0 * c.radius, 1e-12);
    EXPECT_NEAR(dims.z(), length + 2.0 * c.radius, 1e-12);
  }
}

// fuzz_skeletons' first finding: a shin hanging almost straight down (along -z) got a
// quaternion 8e-9 off unit length (Quaterniond::FromTwoVectors: 1 + cos cancels). Oracle: the
// box's z axis is the bone's direction, both joints lie on it at -+ length / 2. Its second
// (session 20's campaign): a bone tilted by 2e-159 m off -z, whose quaternion's components
// squared fell among the denormals (19 bits left): 1.9e-8 off unit length; the tilts down to the
// smallest denormal are asked too.
TEST(CapsuleBox, BonesAlmostAlongEveryAxisKeepAUnitQuaternion) {
  for (double tilt : {0.0, 1e-12, 1e-9, 1e-7, 1.5e-5, 1e-3, 1e-150, 2.2761049594727193e-159, 1e-162,
                      1e-200, 1e-310, 1.0685098434731138e-317, std::numeric_limits<double>::denorm_min()}) {
    for (int axis = 0; axis < 3; ++axis) {
      for (double sign : {-1.0, 1.0}) {
        Vector3d along = Vector3d::Zero();
        along[axis] = sign * 0.45;
        along[(axis + 1) % 3] = tilt;
        const wp::Capsule c{Vector3d(0.0, 0.1, 0.5), Vector3d(0.0, 0.1, 0.5) + along, 0.06};
        Vector3d centre, dims;
        Eigen::Vector4d q;
        wp::capsuleBox(c, &centre, &q, &dims);
        EXPECT_NEAR(q.norm(), 1.0, 1e-14) << tilt << " " << axis << " " << sign;
        // The shortest rotation from z: about an axis in the xy plane (the box's roll about
        // the bone is part of the box; the rostests' reference boxes use this one).
        EXPECT_EQ(q.z(), 0.0) << tilt << " " << axis << " " << sign;
        const Eigen::Quaterniond rotation(q.w(), q.x(), q.y(), q.z());
        const Vector3d z = rotation.toRotationMatrix().col(2);
        EXPECT_LT((z - along.normalized()).norm(), 1e-14) << tilt << " " << axis << " " << sign;
        const double half = 0.5 * along.norm();
        EXPECT_LT((local(c.a, centre, q) - Vector3d(0, 0, -half)).norm(), 1e-14);
        EXPECT_LT((local(c.b, centre, q) - Vector3d(0, 0, half)).norm(), 1e-14);
      }
    }
  }
}

// Two joints off -z by denormals on two axes at once (CI's fuzz_skeletons, session 20): the
// quaternion's largest component is itself denormal, so dividing by (largest x norm), as
// Eigen's stableNormalized does, rounds that product and left it 3.8e-8 off unit length.
TEST(CapsuleBox, BonesOffAxisByDenormalsOnTwoAxesKeepAUnitQuaternion) {
  const double tiny = std::numeric_limits<double>::denorm_min();
  const std::vector<std::pair<double, double>> offsets{
      {1.2951634466340773e-318, 1.0685098434731138e-317},  // the CI's input
      {1e-310, 3e-311}, {tiny, tiny}, {7 * tiny, 3 * tiny}, {1e-300, 1e-320}, {2.5e-320, 9.9e-319}};
  for (const auto& [dx, dy] : offsets) {
    for (int axis = 0; axis < 3; ++axis) {
      for (double sign : {-1.0, 1.0}) {
        // Off the axis the joints sit at 0, where a denormal offset is not lost to rounding.
        Vector3d a = Vector3d::Zero(), b = Vector3d::Zero();
        a[axis] = 1.0;
        b[axis] = 1.0 + sign * 0.5;
        a[(axis + 1) % 3] = dx;
        b[(axis + 2) % 3] = dy;
        const wp::Capsule c{a, b, 0.06};
        Vector3d centre, dims;
        Eigen::Vector4d q;
        wp::capsuleBox(c, &centre, &q, &dims);
        EXPECT_NEAR(q.norm(), 1.0, 1e-14) << dx << " " << dy << " " << axis << " " << sign;
        const Eigen::Quaterniond rotation(q.w(), q.x(), q.y(), q.z());
        const Vector3d z = rotation.toRotationMatrix().col(2);
        EXPECT_LT((z - (b - a).normalized()).norm(), 1e-14)
            << dx << " " << dy << " " << axis << " " << sign;
        EXPECT_LT((local(c.a, centre, q) - Vector3d(0, 0, -0.25)).norm(), 1e-14);
        EXPECT_LT((local(c.b, centre, q) - Vector3d(0, 0, 0.25)).norm(), 1e-14);
      }
    }
  }
  // The CI's joints exactly as they came (a above b: the bone points down).
  const wp::Capsule ci{Vector3d(1.2951634466340773e-318, 0.0, 1.5),
                       Vector3d(0.0, 1.0685098434731138e-317, 1.0), 0.06};
  Vector3d centre, dims;
  Eigen::Vector4d q;
  wp::capsuleBox(ci, &centre, &q, &dims);
  EXPECT_NEAR(q.norm(), 1.0, 1e-14);
}

TEST(CapsuleVelocity, MovedCapsuleStaysWithinTheGrownTranslatedCapsule) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coord(-1.0, 1.0), speed(-2.5, 2.5), unit(0.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vector3d a(coord(rng), coord(rng), coord(rng)), b(coord(rng), coord(rng), coord(rng));
    const Vector3d va(speed(rng), speed(rng), speed(rng)), vb(speed(rng), speed(rng), speed(rng));
    const double r = 0.05 + 0.1 * unit(rng);
    Vector3d v;
    double spread = 0.0;
    wp::capsuleVelocity(va, vb, &v, &spread);
    for (double t : {0.05, 0.3, 1.0}) {
      const Vector3d a1 = a + va * t, b1 = b + vb * t;  // the joints, each at its own velocity
      for (int i = 0; i < 500; ++i) {
        const Vector3d p = a1 + unit(rng) * (b1 - a1) + r * unit(rng) * randomUnit(rng);
        ASSERT_LE(segmentDistance(p, a + v * t, b + v * t), r + spread * t + 1e-9);
      }
      // Attained: the end joints are exactly spread t from their translated places.
      EXPECT_NEAR((a1 - (a + v * t)).norm(), spread * t, 1e-9);
      EXPECT_NEAR((b1 - (b + v * t)).norm(), spread * t, 1e-9);
    }
    // Never more than the larger endpoint speed plus the half difference.
    EXPECT_LE(v.norm() + spread, std::max(va.norm(), vb.norm()) + spread + 1e-12);
  }
}

wp::BodyPart partOf(std::string_view a, std::string_view b) {
  wp::BodyPart part = wp::BodyPart::kCount;
  EXPECT_TRUE(wp::bodyPartOfBone(a, b, &part)) << a << "->" << b;
  return part;
}

TEST(BodyParts, CocoK4abtAndRos4hriNames) {
  using P = wp::BodyPart;
  // jsk's people_pose_estimation_2d (OpenPose COCO joints).
  EXPECT_EQ(partOf("Neck", "Nose"), P::kHead);
  EXPECT_EQ(partOf("Nose", "REye"), P::kHead);
  EXPECT_EQ(partOf("REye", "REar"), P::kHead);
  EXPECT_EQ(partOf("Neck", "RShoulder"), P::kTorso);
  EXPECT_EQ(partOf("Neck", "LHip"), P::kTorso);
  EXPECT_EQ(partOf("RShoulder", "RElbow"), P::kArm);
  EXPECT_EQ(partOf("RElbow", "RWrist"), P::kArm);
  EXPECT_EQ(partOf("RHip", "RKnee"), P::kLeg);
  EXPECT_EQ(partOf("RKnee", "RAnkle"), P::kLeg);
  // The Azure Kinect ROS driver's joint names (K4ABT).
  EXPECT_EQ(partOf("Pelvis", "Spine_Naval"), P::kTorso);
  EXPECT_EQ(partOf("Spine_Chest", "Clavicle_left"), P::kTorso);
  EXPECT_EQ(partOf("Clavicle_left", "Shoulder_left"), P::kTorso);
  EXPECT_EQ(partOf("Elbow_left", "Wrist_left"), P::kArm);
  EXPECT_EQ(partOf("Wrist_left", "Hand_left"), P::kHand);
  EXPECT_EQ(partOf("Hand_left", "Handtip_left"), P::kHand);
  EXPECT_EQ(partOf("Wrist_right", "Thumb_right"), P::kHand);
  EXPECT_EQ(partOf("Ankle_right", "Foot_right"), P::kLeg);
  EXPECT_EQ(partOf("Neck", "Head"), P::kHead);
  EXPECT_EQ(partOf("Head", "Ear_left"), P::kHead);
  // REP-155 link names.
  EXPECT_EQ(partOf("r_y_shoulder", "r_elbow"), P::kArm);
  EXPECT_EQ(partOf("l_wrist", "l_hand"), P::kHand);
  wp::BodyPart part;
  EXPECT_FALSE(wp::bodyPartOfBone("Bkg", "Tail", &part));
  EXPECT_EQ(wp::bodyPartLabel(P::kHand), "person/hand");
}

wp::MonitorParams partParams() {
  wp::MonitorParams p;
  p.track_timeout = 0.5;
  wp::LabelSettings arm;
  arm.size_x = arm.size_y = 0.12;
  arm.max_speed = 2.0;
  p.labels["person/arm"] = arm;
  return p;
}

// fuzz_skeletons' second finding: a bone named twice in one message (here body 7's forearm
// at two places, as a MarkerArray with a body's joints in two runs gives) was differenced
// against the other sighting's joints. Now neither gets a velocity, nor does the bone in the
// next message (its last sighting is ambiguous); two clean messages in a row give one again.
TEST(SkeletonCapsules, ABoneNamedTwiceInAMessageHasNoVelocity) {
  const wp::MonitorParams params = partParams();
  wp::SkeletonCapsules capsules(8);
  wp::SkeletonFrame frame(8);
  std::vector<wp::BoxObservation> out;
  auto forearm = [&](double x) {
    wp::SkeletonBone& bone = frame.bones.emplace_back();
    bone.body = 7;
    bone.name = "RElbow->RWrist";
    bone.part = wp::BodyPart::kArm;
    bone.a = Vector3d(x, 0.0, 1.0);
    bone.b = Vector3d(x + 0.3, 0.0, 1.0);
  };
  const double twice[][2] = {{1.0, 2.0}, {1.01, 2.01}};
  for (int k = 0; k < 2; ++k) {
    frame.stamp = 1'000'000'000 + 100'000'000LL * k;
    frame.bones.clear();
    forearm(twice[k][0]);
    forearm(twice[k][1]);
    capsules.convert(frame, params, &out);
    ASSERT_EQ(out.size(), 2u);
    EXPECT_FALSE(out[0].velocity_known) << k;
    EXPECT_FALSE(out[1].velocity_known) << k;
  }
  for (int k = 2; k < 4; ++k) {
    frame.stamp = 1'000'000'000 + 100'000'000LL * k;
    frame.bones.clear();
    forearm(1.0 + 0.01 * k);
    capsules.convert(frame, params, &out);
    ASSERT_EQ(out.size(), 1u);
    // k = 2: the last sighting was ambiguous; k = 3: 0.01 m in 0.1 s since k = 2.
    EXPECT_EQ(out[0].velocity_known, k == 3) << k;
    if (k == 3) {
      EXPECT_TRUE(out[0].linear_velocity.isApprox(Vector3d(0.1, 0.0, 0.0), 1e-9));
    }
  }
}

TEST(SkeletonCapsules, IdsRadiiAndVelocitiesFromTheJoints) {
  const wp::MonitorParams params = partParams();
  wp::SkeletonCapsules capsules(8);
  wp::SkeletonFrame frame(8);
  frame.stamp = 1'000'000'000;
  wp::SkeletonBone& bone = frame.bones.emplace_back();
  bone.body = 7;
  bone.name = "RElbow->RWrist";
  bone.part = wp::BodyPart::kArm;
  bone.a = Vector3d(1.0, 0.0, 1.0);
  bone.b = Vector3d(1.3, 0.0, 1.0);
  std::vector<wp::BoxObservation> out;
  capsules.convert(frame, params, &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].id, "7/RElbow->RWrist");
  EXPECT_EQ(out[0].label, "person/arm");
  EXPECT_FALSE(out[0].velocity_known);  // one sighting: no velocity yet
  EXPECT_NEAR(out[0].dimensions.x(), 0.12, 1e-12);
  EXPECT_NEAR(out[0].dimensions.z(), 0.3 + 0.12, 1e-12);
  EXPECT_TRUE(out[0].position.isApprox(Vector3d(1.15, 0.0, 1.0)));

  // 0.1 s later the elbow moved 0.05 m in x, the wrist 0.15 m in y (the forearm turned).
  frame.stamp += 100'000'000;
  frame.bones[0].a += Vector3d(0.05, 0.0, 0.0);
  frame.bones[0].b += Vector3d(0.0, 0.15, 0.0);
  capsules.convert(frame, params, &out);
  ASSERT_EQ(out.size(), 1u);
  ASSERT_TRUE(out[0].velocity_known);
  const Vector3d va(0.5, 0.0, 0.0), vb(0.0, 1.5, 0.0);
  EXPECT_TRUE(out[0].linear_velocity.isApprox(0.5 * (va + vb), 1e-9));
  EXPECT_NEAR(out[0].velocity_error, 0.5 * (vb - va).norm(), 1e-9);

  // A body without a stable id (jsk's empty human_ids) never gets a difference.
  frame.stamp += 100'000'000;
  frame.bones[0].body_id_stable = false;
  capsules.convert(frame, params, &out);
  EXPECT_FALSE(out[0].velocity_known);

  // Sightings older than track_timeout are no velocity either.
  frame.bones[0].body_id_stable = true;
  capsules.convert(frame, params, &out);
  frame.stamp += 600'000'000;
  capsules.convert(frame, params, &out);
  EXPECT_FALSE(out[0].velocity_known);

  // A limb stretching faster than the label's unknown-velocity speed: unknown, not believed.
  frame.stamp += 100'000'000;
  frame.bones[0].b += Vector3d(0.0, 0.0, 1.0);  // 10 m/s at the wrist
  capsules.convert(frame, params, &out);
  EXPECT_GT(5.0, wp::unknownVelocitySpeed(params.label("person/arm")));
  EXPECT_FALSE(out[0].velocity_known);
}

// A bone the tracker lost while it still tracks its body (an occluded wrist) is unknown, never
// clear: its last box goes out again, velocity unknown, its position error the label's plus
// v_u x its age, for as long as the body is in the messages. Checked against the definition:
// the bone's capsule moved anywhere within v_u x age (random directions) lies inside the box
// grown by that error; a body that left takes its bones with it.
TEST(SkeletonCapsules, AMissingBoneOfABodyStillTrackedGrowsFromItsLastSighting) {
  wp::MonitorParams params = partParams();
  params.labels["person/arm"].position_error = 0.05;
  const double vu = wp::unknownVelocitySpeed(params.label("person/arm"));  // 2.0 m/s
  wp::SkeletonCapsules capsules(8);
  wp::SkeletonFrame frame(8);
  frame.stamp = 1'000'000'000;
  wp::SkeletonBone torso;
  torso.body = 7;
  torso.name = "Neck->Pelvis";
  torso.part = wp::BodyPart::kTorso;
  torso.a = Vector3d(0.0, 0.0, 1.5);
  torso.b = Vector3d(0.0, 0.0, 1.0);
  wp::SkeletonBone arm;
  arm.body = 7;
  arm.name = "RElbow->RWrist";
  arm.part = wp::BodyPart::kArm;
  arm.a = Vector3d(0.3, 0.0, 1.2);
  arm.b = Vector3d(0.6, 0.0, 1.2);
  frame.bones = {torso, arm};
  std::vector<wp::BoxObservation> out;
  capsules.convert(frame, params, &out);
  ASSERT_EQ(out.size(), 2u);

  // 0.1 s and 0.3 s later the arm is gone from the messages, the torso is not.
  std::mt19937 rng(24);
  for (const double age : {0.1, 0.3}) {
    SCOPED_TRACE(age);
    frame.stamp = 1'000'000'000 + static_cast<wp::Stamp>(age * 1e9);
    frame.bones = {torso};
    capsules.convert(frame, params, &out);
    ASSERT_EQ(out.size(), 2u);
    const wp::BoxObservation& b = out[1];
    EXPECT_EQ(b.id, "7/RElbow->RWrist");
    EXPECT_EQ(b.label, "person/arm");
    EXPECT_FALSE(b.velocity_known);
    EXPECT_EQ(b.linear_velocity, Vector3d::Zero());
    EXPECT_NEAR(b.position_error, 0.05 + vu * age, 1e-9);
    EXPECT_TRUE(b.position.isApprox(Vector3d(0.45, 0.0, 1.2)));
    // The capsule moved anywhere within vu x age stays inside the box grown by the error.
    const Eigen::Quaterniond q(b.quaternion.w(), b.quaternion.x(), b.quaternion.y(),
                               b.quaternion.z());
    const Vector3d half = 0.5 * b.dimensions + Vector3d::Constant(b.position_error);
    for (int k = 0; k < 200; ++k) {
      const Vector3d d = randomUnit(rng) * vu * age * std::uniform_real_distribution<double>(0, 1)(rng);
      for (const Vector3d& joint : {arm.a, arm.b}) {
        for (int e = 0; e < 6; ++e) {
          Vector3d surface = joint + d;
          surface[e / 2] += (e % 2 == 0 ? 1.0 : -1.0) * 0.06;  // the capsule's radius
          const Vector3d local = q.conjugate() * (surface - b.position);
          EXPECT_TRUE((local.cwiseAbs() - half).maxCoeff() <= 1e-9) << local.transpose();
        }
      }
    }
  }

  // The arm back: its own box again, no carried copy; then the body gone: nothing carried.
  frame.stamp += 100'000'000;
  frame.bones = {torso, arm};
  capsules.convert(frame, params, &out);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].position_error, 0.0);
  wp::SkeletonBone other = torso;
  other.body = 8;
  frame.stamp += 100'000'000;
  frame.bones = {other};
  capsules.convert(frame, params, &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].id, "8/Neck->Pelvis");
  // The same stamp again (a republished message) carries nothing over either.
  frame.bones = {};
  capsules.convert(frame, params, &out);
  EXPECT_TRUE(out.empty());
}

// jsk_recognition_msgs/HumanSkeletonArray as upstream defines it (foreign_msgs/).
std::vector<std::uint8_t> jskMessage(bool with_ids, bool mismatch) {
  wp_test::WireWriter w;
  w.header(1, 100, 0, "camera");
  w.u32(with_ids ? 1 : 0);  // std_msgs/Int32[] human_ids
  if (with_ids) w.i32(42);
  w.u32(1);  // skeletons
  w.header(1, 100, 0, "camera");
  const char* names[] = {"Neck->RShoulder", "RElbow->RWrist", "Bkg"};
  w.u32(3);
  for (const char* n : names) w.str(n);
  w.u32(mismatch ? 2 : 3);
  for (int i = 0; i < (mismatch ? 2 : 3); ++i) {
    w.vec3(0.1 * i, 0.0, 1.0);
    w.vec3(0.1 * i, 0.2, 1.0);
  }
  return w.bytes;
}

TEST(JskSkeletons, BonesPartsIdsAndRefusals) {
  wp::SkeletonFrame frame(16);
  wp::SkeletonDecode result;
  std::vector<std::uint8_t> m = jskMessage(true, false);
  ASSERT_EQ(wp::decodeJskSkeletons(kJskMd5, m.data(), m.size(), &frame, &result),
            wp::ForeignRefusal::kNone)
      << result.detail;
  EXPECT_EQ(frame.frame_id, "camera");
  EXPECT_EQ(frame.stamp, 100'000'000'000);
  ASSERT_EQ(frame.bones.size(), 2u);
  EXPECT_EQ(result.unread, 1u);  // "Bkg" names no joints
  EXPECT_EQ(frame.bones[0].name, "Neck->RShoulder");
  EXPECT_EQ(frame.bones[0].part, wp::BodyPart::kTorso);
  EXPECT_EQ(frame.bones[1].part, wp::BodyPart::kArm);
  EXPECT_EQ(frame.bones[1].body, 42u);
  EXPECT_TRUE(frame.bones[1].body_id_stable);
  EXPECT_TRUE(frame.bones[1].b.isApprox(Vector3d(0.1, 0.2, 1.0)));

  m = jskMessage(false, false);
  ASSERT_EQ(wp::decodeJskSkeletons(kJskMd5, m.data(), m.size(), &frame, &result),
            wp::ForeignRefusal::kNone);
  EXPECT_FALSE(frame.bones[0].body_id_stable);

  m = jskMessage(true, true);
  EXPECT_EQ(wp::decodeJskSkeletons(kJskMd5, m.data(), m.size(), &frame, &result),
            wp::ForeignRefusal::kArrayMismatch);
  EXPECT_TRUE(frame.bones.empty());

  m = jskMessage(true, false);
  EXPECT_EQ(wp::decodeJskSkeletons("00000000000000000000000000000000", m.data(), m.size(), &frame,
                                   &result),
            wp::ForeignRefusal::kUnknownMd5);
  EXPECT_NE(result.detail.find("HumanSkeletonArray"), std::string::npos);
  // Cut inside the last segment: the bones' length prefix asks for more than is left.
  EXPECT_EQ(wp::decodeJskSkeletons(kJskMd5, m.data(), m.size() - 3, &frame, &result),
            wp::ForeignRefusal::kBadLength);
  EXPECT_EQ(wp::decodeJskSkeletons(kJskMd5, m.data(), 10, &frame, &result),
            wp::ForeignRefusal::kTruncated);
  m.push_back(0);
  EXPECT_EQ(wp::decodeJskSkeletons(kJskMd5, m.data(), m.size(), &frame, &result),
            wp::ForeignRefusal::kOverlong);
}

// One visualization_msgs/Marker as the Azure Kinect ROS driver's getBodyMarker fills it.
void marker(wp_test::WireWriter* w, int id, int type, const Vector3d& p) {
  w->header(0, 200, 0, "depth_camera_link");
  w->str("");  // ns
  w->i32(id);
  w->i32(type);
  w->i32(0);  // ADD
  w->vec3(p.x(), p.y(), p.z());
  w->quat(0, 0, 0, 1);
  w->vec3(0.05, 0.05, 0.05);
  w->f32(1);
  w->f32(0);
  w->f32(0);
  w->f32(1);
  w->i32(0);
  w->i32(250'000'000);  // lifetime 0.25 s
  w->u8(0);
  w->u32(0);
  w->u32(0);
  w->str("");
  w->str("");
  w->u8(0);
}

Vector3d jointAt(int body, int j) { return Vector3d(0.1 * j, body, 1.0); }

std::vector<std::uint8_t> k4abtMessage(int skip_joint, int bad_type_at) {
  wp_test::WireWriter w;
  w.u32(2 * wp::kK4abtJointCount - (skip_joint >= 0 ? 1 : 0));
  for (int body : {3, 5}) {
    for (int j = 0; j < wp::kK4abtJointCount; ++j) {
      if (body == 3 && j == skip_joint) continue;
      marker(&w, body * 100 + j, body * 100 + j == bad_type_at ? 1 : 2, jointAt(body, j));
    }
  }
  return w.bytes;
}

TEST(K4abtMarkers, BonesOfEveryBodyInTheDriversLayout) {
  wp::SkeletonFrame frame(128);
  wp::SkeletonDecode result;
  std::vector<std::uint8_t> m = k4abtMessage(-1, -1);
  ASSERT_EQ(wp::decodeK4abtMarkers(kMarkerArrayMd5, m.data(), m.size(), &frame, &result),
            wp::ForeignRefusal::kNone)
      << result.detail;
  EXPECT_EQ(frame.frame_id, "depth_camera_link");
  ASSERT_EQ(frame.bones.size(), 2u * (wp::kK4abtJointCount - 1));  // a tree: joints - 1 bones
  int arms = 0, hands = 0, legs = 0, heads = 0, torsos = 0;
  for (const wp::SkeletonBone& b : frame.bones) {
    EXPECT_TRUE(b.body == 3 || b.body == 5);
    arms += b.part == wp::BodyPart::kArm;
    hands += b.part == wp::BodyPart::kHand;
    legs += b.part == wp::BodyPart::kLeg;
    heads += b.part == wp::BodyPart::kHead;
    torsos += b.part == wp::BodyPart::kTorso;
    if (b.name == "Elbow_left->Wrist_left") {
      EXPECT_TRUE(b.a.isApprox(jointAt(static_cast<int>(b.body), 6)));
      EXPECT_TRUE(b.b.isApprox(jointAt(static_cast<int>(b.body), 7)));
    }
  }
  // Per body: 2 x (shoulder-elbow, elbow-wrist) arms; 2 x (wrist-hand, hand-tip, wrist-thumb)
  // hands; 2 x (hip-knee, knee-ankle, ankle-foot) legs; neck-head and 5 face bones; the rest.
  EXPECT_EQ(arms, 2 * 4);
  EXPECT_EQ(hands, 2 * 6);
  EXPECT_EQ(legs, 2 * 6);
  EXPECT_EQ(heads, 2 * 6);
  EXPECT_EQ(torsos, 2 * (31 - 4 - 6 - 6 - 6));

  // A joint missing (the left hand of body 3): its two bones are not read, the rest are.
  m = k4abtMessage(8, -1);
  ASSERT_EQ(wp::decodeK4abtMarkers(kMarkerArrayMd5, m.data(), m.size(), &frame, &result),
            wp::ForeignRefusal::kNone);
  EXPECT_EQ(frame.bones.size(), 2u * 31 - 2);
  EXPECT_EQ(result.unread, 2u);

  // A topic declared a K4ABT skeleton that carries a CUBE: refused by name, not half read.
  m = k4abtMessage(-1, 507);
  EXPECT_EQ(wp::decodeK4abtMarkers(kMarkerArrayMd5, m.data(), m.size(), &frame, &result),
            wp::ForeignRefusal::kArrayMismatch);
  EXPECT_NE(result.detail.find("id 507"), std::string::npos) << result.detail;
  EXPECT_TRUE(frame.bones.empty());
}

TEST(Rep155, IdsAndTheBonesOfHumanDescriptionsFrames) {
  wp_test::WireWriter w;
  w.header(3, 50, 0, "");
  w.u32(2);
  w.str("abcde");
  w.str("fghij");
  wp::HriIds ids(4);
  wp::SkeletonDecode result;
  const char* md5 = "84a63f55b5676f78b625e8a8bb809fe5";
  ASSERT_EQ(wp::decodeHriIds(md5, w.bytes.data(), w.bytes.size(), &ids, &result),
            wp::ForeignRefusal::kNone)
      << result.detail;
  ASSERT_EQ(ids.ids.size(), 2u);
  EXPECT_EQ(ids.ids[1], "fghij");
  EXPECT_EQ(ids.stamp, 50'000'000'000);
  EXPECT_EQ(wp::decodeHriIds("ffffffffffffffffffffffffffffffff", w.bytes.data(), w.bytes.size(),
                             &ids, &result),
            wp::ForeignRefusal::kUnknownMd5);
  wp_test::WireWriter bad;
  bad.header(3, 50, 0, "");
  bad.u32(1);
  bad.str("a/b");
  EXPECT_EQ(wp::decodeHriIds(md5, bad.bytes.data(), bad.bytes.size(), &ids, &result),
            wp::ForeignRefusal::kArrayMismatch);
  EXPECT_NE(result.detail.find("'a/b'"), std::string::npos);

  // The bones form a tree over the 15 links (14 bones), each link listed once, and where the
  // joint names say a part, it is the table's.
  std::set<std::string_view> links;
  for (int i = 0; i < wp::kRep155LinkCount; ++i) links.insert(wp::rep155Link(i));
  EXPECT_EQ(links.size(), static_cast<std::size_t>(wp::kRep155LinkCount));
  std::set<std::string_view> children;
  for (int i = 0; i < wp::kRep155BoneCount; ++i) {
    const wp::Rep155Bone& b = wp::rep155Bone(i);
    EXPECT_TRUE(links.count(b.link_a) && links.count(b.link_b)) << b.name;
    EXPECT_TRUE(children.insert(b.link_b).second) << b.name;
    EXPECT_EQ(b.name, std::string(b.link_a) + "->" + std::string(b.link_b));
    wp::BodyPart part;
    if (wp::bodyPartOfBone(b.link_a, b.link_b, &part)) {
      EXPECT_EQ(part, b.part) << b.name;
    }
  }
  EXPECT_EQ(children.size() + 1, links.size());  // every link but the root "body" is a child
  EXPECT_EQ(children.count("body"), 0u);
}

// Text body ids (REP-155's) name the boxes as number ids do.
TEST(SkeletonCapsules, TextBodyIds) {
  const wp::MonitorParams params = partParams();
  wp::SkeletonCapsules capsules(4);
  wp::SkeletonFrame frame(4);
  wp::SkeletonBone& bone = frame.bones.emplace_back();
  bone.body_name = "abcde";
  bone.name = "l_elbow->l_wrist";
  bone.part = wp::BodyPart::kArm;
  bone.b = Vector3d(0.3, 0, 0);
  std::vector<wp::BoxObservation> out;
  capsules.convert(frame, params, &out);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].id, "abcde/l_elbow->l_wrist");
}

// The node's steady state: a message decoded and converted allocates nothing once warm.
TEST(SkeletonCapsules, NoAllocationOnceWarm) {
  const wp::MonitorParams params = partParams();
  wp::SkeletonFrame frame(128);
  wp::SkeletonDecode result;
  wp::SkeletonCapsules capsules(128);
  std::vector<wp::BoxObservation> out;
  out.reserve(128);
  const std::vector<std::uint8_t> m = k4abtMessage(-1, -1);
  std::vector<std::uint8_t> j = jskMessage(true, false);
  for (int warm = 0; warm < 2; ++warm) {
    ASSERT_EQ(wp::decodeK4abtMarkers(kMarkerArrayMd5, m.data(), m.size(), &frame, &result),
              wp::ForeignRefusal::kNone);
    frame.stamp += 50'000'000;
    capsules.convert(frame, params, &out);
    ASSERT_EQ(wp::decodeJskSkeletons(kJskMd5, j.data(), j.size(), &frame, &result),
              wp::ForeignRefusal::kNone);
  }
  const long before = wp_test::allocationCount();
  for (int i = 0; i < 10; ++i) {
    wp::decodeK4abtMarkers(kMarkerArrayMd5, m.data(), m.size(), &frame, &result);
    frame.stamp = 1'000'000'000 + 50'000'000 * i;
    capsules.convert(frame, params, &out);
    wp::decodeJskSkeletons(kJskMd5, j.data(), j.size(), &frame, &result);
    capsules.convert(frame, params, &out);
  }
  EXPECT_EQ(wp_test::allocationCount(), before);
  EXPECT_EQ(out.size(), 2u);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
