// The foreign-type decoder against messages serialized by hand (wire_writer.hpp) with known
// values, every byte offset of truncation, wrong md5s, absurd lengths and non-finite values;
// the catalogue against foreign_msgs/ (its md5s and field layouts).

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "wire_writer.hpp"
#include "workspace_proximity/rules/foreign_tracks.hpp"
#include "workspace_proximity/rules/foreign_types.hpp"

namespace wp = workspace_proximity;
using wp::ForeignRefusal;
using wp_test::WireWriter;

namespace {

constexpr double kUnset = 1.0e6;  // above spencer's 99999
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

constexpr const char* kPeopleMd5 = "18722f4b8db20cc2369740732357847b";
constexpr const char* kPositionMd5 = "59c860d40aa739ec920eb3ad24ae019e";
constexpr const char* kSpencerMd5[] = {"fff87da612a8c3a29a0c8975fb284991",
                                       "21c0b1a57c4933e68f39aa3802861828",
                                       "a8d3f58bab50e004b03178ad80cb76ac"};
constexpr const char* kBayesMd5[] = {"748ea76bfa4fbc576a15a2b7a15777db",
                                     "e8903e0f53d53a16b295eae14263c817"};
constexpr const char* kLegMd5 = "7b54bf6148ab21083b85a27eec643002";
constexpr const char* kObjectArrayMd5 = "492c83cd255b9a57845d0c197d7977be";
constexpr const char* kObjectCovArrayMd5 = "59dfdf4ed3407a2558ccbc7f5732bf46";
constexpr const char* kObstaclesMd5 = "043bbf49c7775f8111e850268dbcf2e3";
constexpr const char* kDetection3DMd5 = "05c51d9aea1fb4cfdc8effb94f197b6f";
constexpr const char* kJskMd5[] = {"19cc943fcedfafbf4787a46810f9356a",
                                   "c8f4a8bb1acd18ce778d183912bb472d"};

struct Sample {
  std::string type;
  std::string md5;
  std::vector<std::uint8_t> bytes;
};

// A 6x6 covariance with the given diagonal and one x-y correlation.
std::vector<double> cov6(std::initializer_list<double> diagonal, double xy) {
  std::vector<double> c(36, 0.0);
  int i = 0;
  for (double d : diagonal) {
    c[i * 7] = d;
    ++i;
  }
  c[1] = c[6] = xy;
  return c;
}

// Three spencer tracks: (7) planar, z and orientation unset; (8) everything set; (9) no
// velocity (its variances above the bound). `version` 1..3.
Sample spencer(int version, const char* type = "spencer_tracking_msgs/TrackedPersons") {
  WireWriter w;
  w.header(11, 100, 250, "map");
  w.u32(3);
  struct T {
    std::uint64_t id;
    double p[3];
    double q[4];
    std::vector<double> pose_cov;
    double v[3];
    std::vector<double> twist_cov;
  };
  const T tracks[] = {
      {7, {1, 2, kNaN}, {0, 0, 0.3, 0.2}, cov6({0.04, 0.09, kUnset, kUnset, kUnset, kUnset}, 0.01),
       {0.5, -0.25, 3.0}, cov6({0.16, 0.25, kUnset, kUnset, kUnset, kUnset}, 0.02)},
      {8, {-3, 4, 0.9}, {0, 0, 0.6, 0.8}, cov6({0.01, 0.02, 0.03, 0.04, 0.05, 0.06}, 0.0),
       {1, 0, 0.2}, cov6({0.11, 0.12, 0.13, 0.14, 0.15, 0.16}, -0.01)},
      {9, {5, 6, 0}, {0, 0, 0, 1}, cov6({1, 1, 1, 1, 1, 1}, 0.0), {9, 9, 9},
       cov6({1e5, 1e5, 1e5, 1e5, 1e5, 1e5}, 0.0)},
  };
  for (const T& t : tracks) {
    w.u64(t.id);
    w.u8(1);                          // is_occluded
    if (version >= 2) w.u8(0);        // is_matched
    w.u64(1000 + t.id);               // detection_id
    if (version == 3) {
      w.u32(2);
      w.u64(1);
      w.u64(2);
    }
    w.i32(3);  // age
    w.i32(0);
    w.vec3(t.p[0], t.p[1], t.p[2]);
    w.quat(t.q[0], t.q[1], t.q[2], t.q[3]);
    w.f64s(t.pose_cov.data(), 36);
    w.vec3(t.v[0], t.v[1], t.v[2]);
    w.vec3(0.1, 0.2, 0.3);
    w.f64s(t.twist_cov.data(), 36);
  }
  return {type, kSpencerMd5[version - 1], w.bytes};
}

Sample people() {
  WireWriter w;
  w.header(1, 20, 5, "odom");
  w.u32(2);
  w.str("alice");
  w.vec3(1, 2, 0);
  w.vec3(0.5, 0, 0);
  w.f64(0.9);
  w.u32(1);
  w.str("tag");
  w.u32(1);
  w.str("value");
  w.str("bob");
  w.vec3(-1, 0, 0.1);
  w.vec3(0, -0.3, 0);
  w.f64(0.4);
  w.u32(0);
  w.u32(0);
  return {"people_msgs/People", kPeopleMd5, w.bytes};
}

Sample positionMeasurements() {
  WireWriter w;
  w.header(2, 30, 0, "base_laser");
  w.u32(2);
  w.header(0, 31, 7, "laser_a");
  w.str("leg_detector");
  w.str("Person3");
  w.vec3(2, 1, 0);
  w.f64(0.7);
  w.f64s({0.1, 0.01, 0, 0.01, 0.2, 0, 0, 0, 0.3});
  w.u8(1);
  w.header(0, 0, 0, "");  // no own header: the array's applies
  w.str("leg_detector");
  w.str("Person4");
  w.vec3(3, -1, 0);
  w.f64(0.5);
  w.f64s({0.4, 0, 0, 0, 0.4, 0, 0, 0, 0.4});
  w.u8(0);
  w.u32(2);  // cooccurrence
  w.f32(0.5f);
  w.f32(0.25f);
  return {"people_msgs/PositionMeasurementArray", kPositionMd5, w.bytes};
}

Sample bayes(int version) {
  WireWriter w;
  w.header(3, 40, 1, "map");
  w.u32(2);
  w.str("uuid-a");
  w.str("uuid-b");
  w.u32(2);
  w.vec3(1, 1, 0);
  w.quat(0, 0, 0, 1);
  w.vec3(2, 2, 0);
  w.quat(0, 0, 1, 0);
  if (version == 2) {
    w.u32(2);
    w.vec3(0.1, 0.2, 0);
    w.vec3(-0.3, 0, 0);
  }
  w.u32(2);
  w.f64s({1.4, 2.8});
  w.u32(2);
  w.f64s({0.7, 0.7});
  w.f64(1.4);
  w.f64(0.7);
  return {"bayes_people_tracker/PeopleTracker", kBayesMd5[version - 1], w.bytes};
}

Sample legTracker() {
  WireWriter w;
  w.header(4, 50, 2, "odom");
  w.u32(2);
  w.vec3(1, -1, 0);
  w.quat(0, 0, 0, 1);
  w.u32(12);
  w.vec3(0.5, 0.5, 0);
  w.quat(0, 0, 0, 1);
  w.u32(13);
  return {"leg_tracker/PersonArray", kLegMd5, w.bytes};
}

// Two objects: 21 tracked, classified pedestrian, a cylinder; 22 only detected (its twist is
// not valid), unclassified (its classification says car, which is not to be believed), a box.
Sample derivedObjects(bool covariance) {
  WireWriter w;
  w.header(5, 60, 3, "base_link");
  w.u32(2);
  for (int k = 0; k < 2; ++k) {
    const bool first = k == 0;
    w.header(0, first ? 61 : 0, 0, first ? "radar" : "");
    w.u32(first ? 21 : 22);
    w.u8(first ? 1 : 0);  // detection_level
    w.u8(first ? 1 : 0);  // object_classified
    w.vec3(first ? 4 : 6, first ? 1 : -2, 0.9);
    w.quat(0, 0, 0, 1);
    if (covariance) w.f64s(cov6({0.2, 0.3, 0.4, 0.01, 0.01, 0.01}, 0.05).data(), 36);
    w.vec3(first ? -1 : 3, 0.5, 0);  // twist linear
    w.vec3(0, 0, 0.1);
    if (covariance) w.f64s(cov6({0.5, 0.6, 0.7, 0.01, 0.01, 0.01}, 0.0).data(), 36);
    w.vec3(0, 0, 0);  // accel
    w.vec3(0, 0, 0);
    if (covariance) w.f64s(std::vector<double>(36, 0.0).data(), 36);
    w.u32(2);  // polygon: two Point32
    for (int p = 0; p < 6; ++p) w.f32(static_cast<float>(p));
    w.u8(first ? 3 : 1);  // CYLINDER or BOX
    if (first) {
      w.u32(2);
      w.f64s({1.8, 0.3});
    } else {
      w.u32(3);
      w.f64s({1, 2, 3});
    }
    if (covariance) {
      w.u32(1);
      w.f64(0.01);
    }
    w.u8(first ? 4 : 6);  // PEDESTRIAN, CAR
    w.u8(200);
    w.u32(5);
  }
  return {covariance ? "derived_object_msgs/ObjectWithCovarianceArray"
                     : "derived_object_msgs/ObjectArray",
          covariance ? kObjectCovArrayMd5 : kObjectArrayMd5, w.bytes};
}

Sample obstacles() {
  WireWriter w;
  w.header(6, 70, 0, "map");
  w.u32(1);
  w.vec3(0, 0, 0);
  w.vec3(1, 0, 0);
  w.u32(2);
  w.vec3(2, 3, 0);
  w.vec3(0.4, 0, 0);
  w.f64(0.5);
  w.f64(0.3);
  w.vec3(-2, 1, 0);
  w.vec3(0, 0, 0);
  w.f64(0.8);
  w.f64(0.6);
  return {"obstacle_detector/Obstacles", kObstaclesMd5, w.bytes};
}

void pointCloud(WireWriter& w) {
  w.header(0, 0, 0, "cam");
  w.u32(1);
  w.u32(1);
  w.u32(1);  // one PointField
  w.str("x");
  w.u32(0);
  w.u8(7);
  w.u32(1);
  w.u8(0);
  w.u32(4);
  w.u32(4);
  w.u32(4);  // data
  for (int i = 0; i < 4; ++i) w.u8(static_cast<std::uint8_t>(i));
  w.u8(1);
}

Sample detections3D() {
  WireWriter w;
  w.header(7, 80, 9, "camera");
  w.u32(2);
  w.header(0, 81, 0, "");
  w.u32(2);
  w.i64(3);
  w.f64(0.2);
  w.vec3(0, 0, 0);
  w.quat(0, 0, 0, 1);
  w.f64s(std::vector<double>(36, 1.0).data(), 36);  // not the best hypothesis: not read
  w.i64(5);
  w.f64(0.9);
  w.vec3(0, 0, 0);
  w.quat(0, 0, 0, 1);
  std::vector<double> covariance(36, 0.0);
  covariance[0] = 0.04;
  covariance[7] = 0.01;
  covariance[14] = 0.09;
  covariance[35] = 7.0;  // a rotation's: not a position's
  w.f64s(covariance.data(), 36);
  w.vec3(1, 2, 3);  // bbox centre
  w.quat(0, 0, 0.6, 0.8);
  w.vec3(0.5, 0.6, 1.7);
  pointCloud(w);
  w.header(0, 0, 0, "");
  w.u32(0);  // no results
  w.vec3(-1, -2, 0.5);
  w.quat(0, 0, 0, 1);
  w.vec3(0.4, 0.4, 0.4);
  pointCloud(w);
  return {"vision_msgs/Detection3DArray", kDetection3DMd5, w.bytes};
}

Sample jsk(int version) {
  WireWriter w;
  w.header(8, 90, 0, "base");
  w.u32(2);
  for (int k = 0; k < 2; ++k) {
    w.header(0, 90, 0, k == 0 ? "velodyne" : "");
    w.vec3(k, 2 * k, 0.8);
    w.quat(0, 0, 0, 1);
    w.vec3(0.6, 0.6, 1.8 + k);
    if (version == 2) {
      w.f32(0.75f);
      w.u32(40 + k);
    }
  }
  return {"jsk_recognition_msgs/BoundingBoxArray", kJskMd5[version - 1], w.bytes};
}

std::vector<Sample> allSamples() {
  return {spencer(1),
          spencer(2),
          spencer(3),
          spencer(1, "pedsim_msgs/TrackedPersons"),
          spencer(2, "pedsim_msgs/TrackedPersons"),
          people(),
          positionMeasurements(),
          bayes(1),
          bayes(2),
          legTracker(),
          derivedObjects(false),
          derivedObjects(true),
          obstacles(),
          detections3D(),
          jsk(1),
          jsk(2)};
}

ForeignRefusal decode(const Sample& s, wp::ForeignTrackArray* out,
                      std::string_view definition = {}) {
  return wp::decodeForeignTracks(s.type, s.md5, s.bytes.data(), s.bytes.size(), out,
                                 definition);
}
// The tracks view the message's bytes: a temporary sample would leave them dangling.
ForeignRefusal decode(const Sample&& s, wp::ForeignTrackArray* out,
                      std::string_view definition = {}) = delete;

// Whether `s` is read whole into `count` tracks (else the refusal and its detail).
::testing::AssertionResult decodesTracks(const Sample& s, std::size_t count,
                                         wp::ForeignTrackArray* out) {
  const ForeignRefusal r = decode(s, out);
  if (r != ForeignRefusal::kNone) {
    return ::testing::AssertionFailure() << wp::foreignRefusalName(r) << ": " << out->detail;
  }
  if (out->tracks.size() != count) {
    return ::testing::AssertionFailure() << out->tracks.size() << " tracks, not " << count;
  }
  return ::testing::AssertionSuccess();
}
::testing::AssertionResult decodesTracks(const Sample&& s, std::size_t count,
                                         wp::ForeignTrackArray* out) = delete;

// The first `cut` bytes of a message, decoded from a copy of exactly that size, so that a read
// past them is a read past an allocation.
ForeignRefusal decodePrefix(const std::string& type, const std::string& md5,
                            const std::vector<std::uint8_t>& bytes, std::size_t cut,
                            wp::ForeignTrackArray* out) {
  const std::vector<std::uint8_t> prefix(bytes.begin(), bytes.begin() + cut);
  return wp::decodeForeignTracks(type, md5, prefix.data(), prefix.size(), out);
}

void expectVec(const Eigen::Vector3d& v, double x, double y, double z) {
  EXPECT_DOUBLE_EQ(v.x(), x);
  EXPECT_DOUBLE_EQ(v.y(), y);
  EXPECT_DOUBLE_EQ(v.z(), z);
}

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace

TEST(ForeignDecoder, SpencerAllVersionsHonourUnsetVariances) {
  for (int version = 1; version <= 3; ++version) {
    SCOPED_TRACE(version);
    wp::ForeignTrackArray out;
    const Sample message = spencer(version);
    ASSERT_TRUE(decodesTracks(message, 3u, &out));
    ASSERT_NE(out.version, nullptr);
    EXPECT_EQ(out.version->version, "v" + std::to_string(version));
    EXPECT_EQ(out.stamp, 100 * 1000000000LL + 250);
    EXPECT_EQ(out.frame_id, "map");

    const wp::ForeignTrack& a = out.tracks[0];
    EXPECT_EQ(a.id_kind, wp::ForeignIdKind::kNumber);
    EXPECT_EQ(a.id_number, 7u);
    EXPECT_EQ(a.label, "person");
    EXPECT_EQ(a.frame_id, "map");
    EXPECT_EQ(a.position_axes, wp::kAxesXY);
    expectVec(a.position, 1, 2, 0);  // z (NaN) is unset: read as 0, not refused
    EXPECT_FALSE(a.has_orientation);
    EXPECT_EQ(a.quaternion, Eigen::Vector4d(0, 0, 0, 1));
    EXPECT_EQ(a.velocity_axes, wp::kAxesXY);
    expectVec(a.velocity, 0.5, -0.25, 0);
    ASSERT_TRUE(a.has_position_covariance);
    Eigen::Matrix3d pc;
    pc << 0.04, 0.01, 0, 0.01, 0.09, 0, 0, 0, 0;
    EXPECT_TRUE(a.position_covariance.isApprox(pc));
    ASSERT_TRUE(a.has_velocity_covariance);
    Eigen::Matrix3d vc;
    vc << 0.16, 0.02, 0, 0.02, 0.25, 0, 0, 0, 0;
    EXPECT_TRUE(a.velocity_covariance.isApprox(vc));
    EXPECT_EQ(a.dimension_axes, wp::kAxesNone);

    const wp::ForeignTrack& b = out.tracks[1];
    EXPECT_EQ(b.id_number, 8u);
    EXPECT_EQ(b.position_axes, wp::kAxesAll);
    expectVec(b.position, -3, 4, 0.9);
    EXPECT_TRUE(b.has_orientation);
    EXPECT_EQ(b.quaternion, Eigen::Vector4d(0, 0, 0.6, 0.8));
    EXPECT_EQ(b.velocity_axes, wp::kAxesAll);
    expectVec(b.velocity, 1, 0, 0.2);
    EXPECT_EQ(b.position_covariance.diagonal(), Eigen::Vector3d(0.01, 0.02, 0.03));
    EXPECT_EQ(b.velocity_covariance.diagonal(), Eigen::Vector3d(0.11, 0.12, 0.13));
    EXPECT_DOUBLE_EQ(b.velocity_covariance(0, 1), -0.01);

    const wp::ForeignTrack& c = out.tracks[2];
    EXPECT_EQ(c.id_number, 9u);
    EXPECT_EQ(c.velocity_axes, wp::kAxesNone);  // 1e5 > 99999: no velocity
    EXPECT_FALSE(c.has_velocity_covariance);
    expectVec(c.velocity, 0, 0, 0);
    EXPECT_TRUE(c.has_orientation);
  }
}

TEST(ForeignDecoder, PedsimReadsAsSpencer) {
  wp::ForeignTrackArray out;
  const Sample message = spencer(1, "pedsim_msgs/TrackedPersons");
  ASSERT_TRUE(decodesTracks(message, 3u, &out));
  EXPECT_EQ(out.version->type, "pedsim_msgs/TrackedPersons");
  EXPECT_EQ(out.tracks[1].id_number, 8u);
  expectVec(out.tracks[1].velocity, 1, 0, 0.2);
}

TEST(ForeignDecoder, People) {
  wp::ForeignTrackArray out;
  const Sample message = people();
  ASSERT_TRUE(decodesTracks(message, 2u, &out));
  EXPECT_EQ(out.stamp, 20 * 1000000000LL + 5);
  EXPECT_EQ(out.frame_id, "odom");
  EXPECT_EQ(out.tracks[0].id_kind, wp::ForeignIdKind::kText);
  EXPECT_EQ(out.tracks[0].id_text, "alice");
  EXPECT_EQ(out.tracks[0].label, "person");
  expectVec(out.tracks[0].position, 1, 2, 0);
  expectVec(out.tracks[0].velocity, 0.5, 0, 0);
  EXPECT_EQ(out.tracks[0].velocity_axes, wp::kAxesAll);
  EXPECT_FALSE(out.tracks[0].has_orientation);
  EXPECT_FALSE(out.tracks[0].has_position_covariance);
  EXPECT_EQ(out.tracks[1].id_text, "bob");
  expectVec(out.tracks[1].position, -1, 0, 0.1);
  expectVec(out.tracks[1].velocity, 0, -0.3, 0);
}

TEST(ForeignDecoder, PositionMeasurementArray) {
  wp::ForeignTrackArray out;
  const Sample message = positionMeasurements();
  ASSERT_TRUE(decodesTracks(message, 2u, &out));
  const wp::ForeignTrack& a = out.tracks[0];
  EXPECT_EQ(a.id_text, "Person3");
  EXPECT_EQ(a.frame_id, "laser_a");  // its own header
  EXPECT_EQ(a.stamp, 31 * 1000000000LL + 7);
  expectVec(a.position, 2, 1, 0);
  EXPECT_EQ(a.velocity_axes, wp::kAxesNone);
  ASSERT_TRUE(a.has_position_covariance);
  Eigen::Matrix3d pc;
  pc << 0.1, 0.01, 0, 0.01, 0.2, 0, 0, 0, 0.3;
  EXPECT_EQ(a.position_covariance, pc);
  const wp::ForeignTrack& b = out.tracks[1];
  EXPECT_EQ(b.id_text, "Person4");
  EXPECT_EQ(b.frame_id, "base_laser");  // the array's
  EXPECT_EQ(b.stamp, 30 * 1000000000LL);
  EXPECT_EQ(b.position_covariance, Eigen::Matrix3d::Identity() * 0.4);
}

TEST(ForeignDecoder, BayesPeopleTrackerBothVersions) {
  for (int version = 1; version <= 2; ++version) {
    SCOPED_TRACE(version);
    wp::ForeignTrackArray out;
    const Sample message = bayes(version);
    ASSERT_TRUE(decodesTracks(message, 2u, &out));
    EXPECT_EQ(out.tracks[0].id_text, "uuid-a");
    EXPECT_EQ(out.tracks[1].id_text, "uuid-b");
    expectVec(out.tracks[1].position, 2, 2, 0);
    EXPECT_EQ(out.tracks[1].quaternion, Eigen::Vector4d(0, 0, 1, 0));
    if (version == 1) {
      EXPECT_EQ(out.tracks[0].velocity_axes, wp::kAxesNone);
    } else {
      EXPECT_EQ(out.tracks[0].velocity_axes, wp::kAxesAll);
      expectVec(out.tracks[0].velocity, 0.1, 0.2, 0);
      expectVec(out.tracks[1].velocity, -0.3, 0, 0);
    }
  }
}

TEST(ForeignDecoder, BayesParallelArraysMustMatch) {
  WireWriter w;
  w.header(3, 40, 1, "map");
  w.u32(2);
  w.str("a");
  w.str("b");
  w.u32(1);  // one pose for two uuids
  w.vec3(1, 1, 0);
  w.quat(0, 0, 0, 1);
  w.u32(0);
  w.u32(0);
  w.u32(0);
  w.f64(0);
  w.f64(0);
  wp::ForeignTrackArray out;
  const Sample message = {"bayes_people_tracker/PeopleTracker", kBayesMd5[1], w.bytes};
  EXPECT_EQ(decode(message, &out), ForeignRefusal::kArrayMismatch);
  EXPECT_NE(out.detail.find("2 uuids but 1 poses"), std::string::npos) << out.detail;
  EXPECT_TRUE(out.tracks.empty());
}

TEST(ForeignDecoder, LegTracker) {
  wp::ForeignTrackArray out;
  const Sample message = legTracker();
  ASSERT_TRUE(decodesTracks(message, 2u, &out));
  EXPECT_EQ(out.tracks[0].id_kind, wp::ForeignIdKind::kNumber);
  EXPECT_EQ(out.tracks[0].id_number, 12u);
  EXPECT_EQ(out.tracks[1].id_number, 13u);
  expectVec(out.tracks[0].position, 1, -1, 0);
  EXPECT_EQ(out.tracks[0].velocity_axes, wp::kAxesNone);
  EXPECT_EQ(out.tracks[0].label, "person");
}

// This package's TrackedBoxArray before the per-box errors (issue 23): every field as written,
// the label as given, the twist (linear and angular) known, the errors left at 0.
TEST(ForeignDecoder, TrackedBoxArrayV1) {
  WireWriter w;
  w.header(3, 50, 7, "world");
  w.u32(2);
  w.str("a");
  w.str("pedestrian");  // not renamed: the monitor's own labels
  w.vec3(1.0, 2.0, 0.9);
  w.quat(0.0, 0.0, 0.6, 0.8);
  w.vec3(0.6, 0.5, 1.8);
  w.vec3(-0.25, 0.5, 0.0);
  w.vec3(0.0, 0.0, 0.75);
  w.str("b");
  w.str("");
  w.vec3(-1.0, 0.0, 0.5);
  w.quat(0.0, 0.0, 0.0, 1.0);
  w.vec3(1.0, 1.0, 1.0);
  w.vec3(0.0, 0.0, 0.0);
  w.vec3(0.0, 0.0, 0.0);
  const Sample message = {"workspace_proximity/TrackedBoxArray", "d56a591380bdbf88ec37ec86270fc893",
                          w.bytes};
  wp::ForeignTrackArray out;
  ASSERT_TRUE(decodesTracks(message, 2u, &out));
  EXPECT_EQ(out.version->version, "v1");
  EXPECT_EQ(out.stamp, wp::Stamp{50} * 1000000000 + 7);
  EXPECT_EQ(out.frame_id, "world");
  const wp::ForeignTrack& a = out.tracks[0];
  EXPECT_EQ(a.id_kind, wp::ForeignIdKind::kText);
  EXPECT_EQ(a.id_text, "a");
  EXPECT_EQ(a.label, "pedestrian");
  expectVec(a.position, 1.0, 2.0, 0.9);
  EXPECT_TRUE(a.has_orientation);
  EXPECT_EQ(a.quaternion, Eigen::Vector4d(0.0, 0.0, 0.6, 0.8));
  expectVec(a.dimensions, 0.6, 0.5, 1.8);
  EXPECT_EQ(a.dimension_axes, wp::kAxesAll);
  expectVec(a.velocity, -0.25, 0.5, 0.0);
  EXPECT_EQ(a.velocity_axes, wp::kAxesAll);
  expectVec(a.angular_velocity, 0.0, 0.0, 0.75);
  EXPECT_FALSE(a.has_position_covariance);
  EXPECT_FALSE(a.has_velocity_covariance);
  EXPECT_EQ(out.tracks[1].id_text, "b");
  EXPECT_EQ(out.tracks[1].label, "");
  for (std::size_t cut = 0; cut < message.bytes.size(); ++cut) {
    EXPECT_NE(decodePrefix(message.type, message.md5, message.bytes, cut, &out),
              ForeignRefusal::kNone)
        << "cut at " << cut;
  }
}

TEST(ForeignDecoder, DerivedObjectsHonourDetectionLevelAndClassified) {
  for (bool covariance : {false, true}) {
    SCOPED_TRACE(covariance);
    wp::ForeignTrackArray out;
    const Sample message = derivedObjects(covariance);
    ASSERT_TRUE(decodesTracks(message, 2u, &out));
    const wp::ForeignTrack& a = out.tracks[0];
    EXPECT_EQ(a.id_number, 21u);
    EXPECT_EQ(a.frame_id, "radar");
    EXPECT_EQ(a.stamp, 61 * 1000000000LL);
    EXPECT_EQ(a.label, "pedestrian");
    expectVec(a.position, 4, 1, 0.9);
    EXPECT_EQ(a.velocity_axes, wp::kAxesAll);
    expectVec(a.velocity, -1, 0.5, 0);
    EXPECT_EQ(a.dimension_axes, wp::kAxesAll);
    expectVec(a.dimensions, 0.6, 0.6, 1.8);  // cylinder: height 1.8, radius 0.3
    const wp::ForeignTrack& b = out.tracks[1];
    EXPECT_EQ(b.id_number, 22u);
    EXPECT_EQ(b.frame_id, "base_link");
    EXPECT_EQ(b.label, "unknown");          // not classified: its "car" is not believed
    EXPECT_EQ(b.velocity_axes, wp::kAxesNone);  // OBJECT_DETECTED: twist not valid
    expectVec(b.velocity, 0, 0, 0);
    expectVec(b.dimensions, 1, 2, 3);
    EXPECT_EQ(a.has_position_covariance, covariance);
    EXPECT_EQ(a.has_velocity_covariance, covariance);
    EXPECT_FALSE(b.has_velocity_covariance);
    if (covariance) {
      Eigen::Matrix3d pc;
      pc << 0.2, 0.05, 0, 0.05, 0.3, 0, 0, 0, 0.4;
      EXPECT_EQ(a.position_covariance, pc);
      EXPECT_EQ(a.velocity_covariance.diagonal(), Eigen::Vector3d(0.5, 0.6, 0.7));
    }
  }
}

// obstacle_detector: the segment (0,0)-(1,0) and two circles (radius 0.5 with true_radius
// 0.3; radius 0.8 with true_radius 0.6). Tracks in wire order: segments, then circles.
TEST(ForeignDecoder, ObstacleSegmentsAndCircles) {
  wp::ForeignTrackArray out;
  const Sample message = obstacles();
  ASSERT_TRUE(decodesTracks(message, 3u, &out));
  EXPECT_EQ(out.version->family, wp::ForeignFamily::kDetections);  // no ids: the tracker's
  EXPECT_EQ(out.ignored, 0u);
  const wp::ForeignTrack& s = out.tracks[0];
  EXPECT_EQ(s.id_kind, wp::ForeignIdKind::kNone);
  EXPECT_EQ(s.label, "segment");
  expectVec(s.position, 0.5, 0, 0);  // the midpoint
  EXPECT_EQ(s.position_axes, wp::kAxesXY);  // no z: obstacle_detector writes x and y
  EXPECT_EQ(s.quaternion, Eigen::Vector4d(0, 0, 0, 1));  // along x: yaw 0
  EXPECT_NEAR(s.dimensions.x(), 1.0, 1e-15);
  EXPECT_EQ(s.dimension_axes, 0b001);  // the length only: thickness, height the label's
  EXPECT_EQ(s.velocity_axes, wp::kAxesNone);
  const wp::ForeignTrack& c = out.tracks[1];
  EXPECT_EQ(c.id_kind, wp::ForeignIdKind::kNone);
  EXPECT_TRUE(c.label.empty());
  expectVec(c.position, 2, 3, 0);
  EXPECT_EQ(c.position_axes, wp::kAxesXY);
  // The message says 0.4 m/s, which obstacle_detector cannot tell from "not measured": unknown.
  EXPECT_EQ(c.velocity_axes, wp::kAxesNone);
  expectVec(c.velocity, 0, 0, 0);
  expectVec(c.dimensions, 0.6, 0.6, 0);  // the true radius, not the margin's
  EXPECT_EQ(c.dimension_axes, wp::kAxesXY);
  expectVec(out.tracks[2].dimensions, 1.2, 1.2, 0);
}

// A segment's yaw and length, and the circle's radius where true_radius is not in (0, radius].
TEST(ForeignDecoder, ObstacleSegmentYawAndInconsistentRadii) {
  WireWriter w;
  w.header(1, 2, 0, "map");
  w.u32(1);
  w.vec3(1, 1, 0);
  w.vec3(1, 3, 0);  // along +y: yaw pi/2, length 2
  w.u32(2);
  w.vec3(0, 0, 0);
  w.vec3(0, 0, 0);
  w.f64(0.5);
  w.f64(0.0);  // no true radius: the radius
  w.vec3(0, 0, 0);
  w.vec3(0, 0, 0);
  w.f64(0.5);
  w.f64(0.7);  // larger than radius: the radius
  wp::ForeignTrackArray out;
  const Sample message{"obstacle_detector/Obstacles", kObstaclesMd5, w.bytes};
  ASSERT_TRUE(decodesTracks(message, 3u, &out));
  expectVec(out.tracks[0].position, 1, 2, 0);
  const double h = std::sqrt(0.5);
  EXPECT_NEAR(out.tracks[0].quaternion.z(), h, 1e-15);
  EXPECT_NEAR(out.tracks[0].quaternion.w(), h, 1e-15);
  EXPECT_NEAR(out.tracks[0].dimensions.x(), 2.0, 1e-15);
  expectVec(out.tracks[1].dimensions, 1.0, 1.0, 0);
  expectVec(out.tracks[2].dimensions, 1.0, 1.0, 0);
}

TEST(ForeignDecoder, Detection3DArray) {
  wp::ForeignTrackArray out;
  const Sample message = detections3D();
  ASSERT_TRUE(decodesTracks(message, 2u, &out));
  const wp::ForeignTrack& a = out.tracks[0];
  EXPECT_EQ(a.id_kind, wp::ForeignIdKind::kNone);  // results[].id is no track id
  ASSERT_TRUE(a.has_label_number);
  EXPECT_EQ(a.label_number, 5);  // the best score's
  ASSERT_TRUE(a.has_position_covariance);  // and its pose's covariance, the position block
  EXPECT_EQ(a.position_covariance, Eigen::Vector3d(0.04, 0.01, 0.09).asDiagonal().toDenseMatrix());
  EXPECT_EQ(a.stamp, 81 * 1000000000LL);
  EXPECT_EQ(a.frame_id, "camera");
  expectVec(a.position, 1, 2, 3);
  EXPECT_EQ(a.quaternion, Eigen::Vector4d(0, 0, 0.6, 0.8));
  expectVec(a.dimensions, 0.5, 0.6, 1.7);
  EXPECT_EQ(a.velocity_axes, wp::kAxesNone);
  EXPECT_FALSE(out.tracks[1].has_label_number);
  EXPECT_FALSE(out.tracks[1].has_position_covariance);
  expectVec(out.tracks[1].position, -1, -2, 0.5);
}

TEST(ForeignDecoder, JskBoxesBothVersions) {
  for (int version = 1; version <= 2; ++version) {
    SCOPED_TRACE(version);
    wp::ForeignTrackArray out;
    const Sample message = jsk(version);
    ASSERT_TRUE(decodesTracks(message, 2u, &out));
    EXPECT_EQ(out.tracks[0].frame_id, "velodyne");
    EXPECT_EQ(out.tracks[1].frame_id, "base");
    expectVec(out.tracks[1].position, 1, 2, 0.8);
    expectVec(out.tracks[1].dimensions, 0.6, 0.6, 2.8);
    EXPECT_EQ(out.tracks[1].has_label_number, version == 2);
    if (version == 2) {
      EXPECT_EQ(out.tracks[1].label_number, 41);
    }
  }
}

TEST(ForeignDecoder, EveryTruncationIsRefusedByName) {
  for (const Sample& s : allSamples()) {
    SCOPED_TRACE(s.type + " " + s.md5);
    wp::ForeignTrackArray out;
    ASSERT_EQ(decode(s, &out), ForeignRefusal::kNone) << out.detail;
    for (std::size_t cut = 0; cut < s.bytes.size(); ++cut) {
      const ForeignRefusal r = decodePrefix(s.type, s.md5, s.bytes, cut, &out);
      EXPECT_TRUE(r == ForeignRefusal::kTruncated || r == ForeignRefusal::kBadLength)
          << "cut at " << cut << ": " << wp::foreignRefusalName(r);
      EXPECT_FALSE(out.detail.empty());
      EXPECT_TRUE(out.tracks.empty());
    }
    std::vector<std::uint8_t> longer = s.bytes;
    longer.push_back(0);
    EXPECT_EQ(wp::decodeForeignTracks(s.type, s.md5, longer.data(), longer.size(), &out),
              ForeignRefusal::kOverlong);
    EXPECT_NE(out.detail.find("1 bytes after"), std::string::npos) << out.detail;
  }
}

TEST(ForeignDecoder, UnknownTypeAndMd5AreRefusedByName) {
  wp::ForeignTrackArray out;
  Sample s = spencer(2);
  s.type = "my_msgs/Persons";
  EXPECT_EQ(decode(s, &out), ForeignRefusal::kUnknownType);
  EXPECT_NE(out.detail.find("my_msgs/Persons"), std::string::npos);
  EXPECT_STREQ(wp::foreignRefusalName(out.refusal), "unknown_type");

  s = spencer(2);
  s.md5 = "0123456789abcdef0123456789abcdef";
  EXPECT_EQ(decode(s, &out), ForeignRefusal::kUnknownMd5);
  EXPECT_TRUE(out.tracks.empty());
  EXPECT_EQ(out.version, nullptr);
  for (const char* part : {"spencer_tracking_msgs/TrackedPersons", "0123456789abcdef",
                           "none of the 3 known versions", "v1 fff87da6", "v2 21c0b1a5",
                           "v3 a8d3f58b", "no message definition"}) {
    EXPECT_NE(out.detail.find(part), std::string::npos) << part << " in " << out.detail;
  }
  // The md5 of one version with another's bytes is still only that version: v3's md5 on v2's
  // bytes misreads nothing, it is refused (bad length or overlong, never read).
  s = spencer(2);
  s.md5 = kSpencerMd5[2];
  EXPECT_NE(decode(s, &out), ForeignRefusal::kNone);
}

TEST(ForeignDecoder, UnknownMd5NamesTheNearestVersionAndTheDifference) {
  // What a publisher's connection header would carry: its full definition, here spencer v2
  // with one more field.
  const std::string definition =
      "# Message with all currently tracked persons\n"
      "std_msgs/Header header\n"
      "TrackedPerson[] tracks\n"
      "================================================================================\n"
      "MSG: std_msgs/Header\n"
      "uint32 seq\ntime stamp\nstring frame_id\n"
      "================================================================================\n"
      "MSG: spencer_tracking_msgs/TrackedPerson\n"
      "uint64 track_id  # unique\n"
      "bool is_occluded\n"
      "bool is_matched\n"
      "uint64 detection_id\n"
      "duration age\n"
      "float32 confidence\n"
      "geometry_msgs/PoseWithCovariance pose\n"
      "geometry_msgs/TwistWithCovariance twist\n";
  Sample s = spencer(2);
  s.md5 = "ffffffffffffffffffffffffffffffff";
  wp::ForeignTrackArray out;
  EXPECT_EQ(decode(s, &out, definition), ForeignRefusal::kUnknownMd5);
  EXPECT_NE(out.detail.find("nearest: v2 (differs in TrackedPerson: extra field 'float32 "
                            "confidence')"),
            std::string::npos)
      << out.detail;

  // v1's fields with an unknown md5: nearest v1, same fields (the change is elsewhere).
  std::string v1 = definition;
  v1.erase(v1.find("bool is_matched\n"), 16);
  v1.erase(v1.find("float32 confidence\n"), 19);
  EXPECT_EQ(decode(s, &out, v1), ForeignRefusal::kUnknownMd5);
  EXPECT_NE(out.detail.find("nearest: v1 (same fields"), std::string::npos) << out.detail;

  // A changed type is named.
  std::string changed = definition;
  changed.replace(changed.find("uint64 track_id"), 15, "uint32 track_id");
  EXPECT_EQ(decode(s, &out, changed), ForeignRefusal::kUnknownMd5);
  EXPECT_NE(out.detail.find("field 'track_id' is uint32, not uint64"), std::string::npos)
      << out.detail;
}

TEST(ForeignDecoder, AbsurdLengthsAreRefused) {
  wp::ForeignTrackArray out;
  WireWriter w;
  w.header(1, 1, 0, "map");
  w.u32(0xffffffffu);  // tracks
  const Sample message = {"spencer_tracking_msgs/TrackedPersons", kSpencerMd5[1], w.bytes};
  EXPECT_EQ(decode(message, &out), ForeignRefusal::kBadLength);
  EXPECT_NE(out.detail.find("length prefix"), std::string::npos) << out.detail;

  // A count the bytes cannot hold whole elements for: 4 tracks claimed, bytes for 3.
  Sample s = spencer(2);
  s.bytes[4 + 8 + 4 + 3] = 4;  // the tracks' count (after seq, stamp, "map"): 3 -> 4
  EXPECT_EQ(decode(s, &out), ForeignRefusal::kBadLength);

  WireWriter p;
  p.header(1, 1, 0, "map");
  p.u32(1);
  p.u32(0x7fffffffu);  // a name longer than the message
  p.vec3(0, 0, 0);
  const Sample long_name = {"people_msgs/People", kPeopleMd5, p.bytes};
  EXPECT_EQ(decode(long_name, &out), ForeignRefusal::kBadLength);
}

TEST(ForeignDecoder, NonFiniteAndNegativeVariancesAreRefused) {
  wp::ForeignTrackArray out;
  WireWriter w;
  w.header(1, 1, 0, "map");
  w.u32(1);
  w.str("x");
  w.vec3(1, kNaN, 0);
  w.vec3(0, 0, 0);
  w.f64(1);
  w.u32(0);
  w.u32(0);
  const Sample message = {"people_msgs/People", kPeopleMd5, w.bytes};
  EXPECT_EQ(decode(message, &out), ForeignRefusal::kNonFinite);
  EXPECT_NE(out.detail.find("track 0: non-finite position"), std::string::npos) << out.detail;

  // A NaN variance is not "unset": refused.
  Sample s = spencer(2);
  wp::ForeignTrackArray ok;
  ASSERT_EQ(decode(s, &ok), ForeignRefusal::kNone);
  // Track 8's velocity x variance: after its fixed part up to the twist covariance.
  const std::size_t header = 4 + 8 + 4 + 3 + 4;
  const std::size_t track = 8 + 1 + 1 + 8 + 8 + 56 + 288 + 48 + 288;
  const std::size_t twist_cov = header + track + (8 + 1 + 1 + 8 + 8 + 56 + 288 + 48);
  double nan = kNaN;
  std::memcpy(&s.bytes[twist_cov], &nan, 8);
  EXPECT_EQ(decode(s, &out), ForeignRefusal::kNonFinite);
  EXPECT_NE(out.detail.find("track 1: non-finite velocity covariance"), std::string::npos)
      << out.detail;
  double negative = -0.5;
  std::memcpy(&s.bytes[twist_cov], &negative, 8);
  EXPECT_EQ(decode(s, &out), ForeignRefusal::kBadCovariance);
  EXPECT_STREQ(wp::foreignRefusalName(out.refusal), "bad_covariance");
}

TEST(ForeignDecoder, CapacityIsNamed) {
  wp::ForeignTrackArray out(2);
  const Sample message = spencer(2);
  EXPECT_EQ(decode(message, &out), ForeignRefusal::kTooManyTracks);
  EXPECT_NE(out.detail.find("3 tracks exceed the capacity of 2"), std::string::npos);
}

TEST(ForeignDecoder, DecodingAllocatesNothingOnceWarm) {
  const std::vector<Sample> samples = allSamples();
  wp::ForeignTrackArray out;
  for (const Sample& s : samples) ASSERT_EQ(decode(s, &out), ForeignRefusal::kNone);
  const long before = wp_test::allocationCount();
  std::size_t tracks = 0;
  for (int round = 0; round < 3; ++round) {
    for (const Sample& s : samples) {
      decode(s, &out);
      tracks += out.tracks.size();
    }
  }
  EXPECT_EQ(wp_test::allocationCount() - before, 0);
  EXPECT_GT(tracks, 0u);
}

// Messages serialized by genpy (ROS's own Python serializer) from the stored definitions, with
// what they hold (test/foreign/make_fixtures.py wrote both).
TEST(ForeignDecoder, GenpySerializedFixtures) {
  const std::string dir = std::string(WP_SOURCE_DIR) + "/test/foreign/fixtures/";
  const char* names[] = {"spencer_v1", "spencer_v2", "spencer_v3", "pedsim_v1", "people",
                         "position_measurements", "bayes_v1", "bayes_v2", "leg_tracker",
                         "derived_objects", "derived_objects_covariance", "obstacles",
                         "detections3d", "jsk_v1", "jsk_v2"};
  for (const char* name : names) {
    SCOPED_TRACE(name);
    std::istringstream expected(readFile(dir + name + ".txt"));
    std::string word, type, md5;
    expected >> word >> type >> md5;
    ASSERT_EQ(word, "type");
    std::ifstream in(dir + name + ".bin", std::ios::binary);
    const std::vector<std::uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                          std::istreambuf_iterator<char>());
    ASSERT_FALSE(bytes.empty());
    wp::ForeignTrackArray out;
    ASSERT_EQ(wp::decodeForeignTracks(type, md5, bytes.data(), bytes.size(), &out),
              ForeignRefusal::kNone)
        << out.detail;
    std::size_t i = 0;
    while (expected >> word) {
      ASSERT_EQ(word, "track");
      double p[3], v[3];
      int axes = 0;
      expected >> p[0] >> p[1] >> p[2] >> axes >> v[0] >> v[1] >> v[2];
      ASSERT_LT(i, out.tracks.size());
      const wp::ForeignTrack& t = out.tracks[i++];
      expectVec(t.position, p[0], p[1], p[2]);
      EXPECT_EQ(t.velocity_axes, axes);
      expectVec(t.velocity, v[0], v[1], v[2]);
    }
    EXPECT_EQ(i, out.tracks.size());
    EXPECT_GE(i, 2u);
    for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
      EXPECT_NE(decodePrefix(type, md5, bytes, cut, &out), ForeignRefusal::kNone)
          << "cut at " << cut;
    }
  }
}

// The catalogue's md5s are md5s.txt's, and its layouts are the stored .msg files' fields.
TEST(ForeignCatalogue, AgreesWithStoredDefinitions) {
  const std::string root = std::string(WP_SOURCE_DIR) + "/foreign_msgs/";
  std::map<std::pair<std::string, std::string>, std::pair<std::string, std::string>> table;
  std::istringstream rows(readFile(root + "md5s.txt"));
  std::string line;
  while (std::getline(rows, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream cells(line);
    std::string type, version, md5, dir;
    cells >> type >> version >> md5 >> dir;
    table[{type, version}] = {md5, dir};
  }
  std::size_t count = 0;
  const wp::ForeignVersion* versions = wp::foreignVersions(&count);
  ASSERT_GE(count, 16u);
  for (std::size_t i = 0; i < count; ++i) {
    const wp::ForeignVersion& v = versions[i];
    const std::string type(v.type);
    SCOPED_TRACE(type + " " + std::string(v.version));
    const auto row = table.find({type, std::string(v.version)});
    ASSERT_NE(row, table.end());
    EXPECT_EQ(row->second.first, v.md5);
    const std::string dir = row->second.second;
    // The definition as ROS would send it: the type's file, then each nested type of the
    // layout after "MSG: package/Type" (the version's folder first, as for genmsg).
    const std::string package = type.substr(0, type.find('/'));
    // A nested type from the top-level type's package when stored there (pedsim's copy of
    // spencer's TrackedPerson), else from the package the layout names.
    auto load = [&](const std::string& nested_package, const std::string& name) {
      // A Debian type (version "debian"): its folder under /usr/share, nested types beside it.
      if (!dir.empty() && dir[0] == '/') return readFile(dir + "/" + name + ".msg");
      const std::string from =
          readFile(root + package + "/" + name + ".msg").empty() ? nested_package : package;
      const std::string text = readFile(root + from + "/" + dir + "/" + name + ".msg");
      return text.empty() ? readFile(root + from + "/" + name + ".msg") : text;
    };
    std::string definition = load(package, type.substr(type.find('/') + 1));
    ASSERT_FALSE(definition.empty());
    std::istringstream layout{std::string(v.layout)};
    while (std::getline(layout, line)) {
      if (line.rfind("MSG: ", 0) != 0) continue;
      const std::string name = line.substr(5);
      definition += "MSG: " + name + "\n" +
                    load(name.substr(0, name.find('/')), name.substr(name.find('/') + 1));
    }
    int differences = -1;
    const std::string text = wp::layoutDifference(definition, v.layout, &differences);
    EXPECT_EQ(differences, 0) << text;
    // And the comparison is not vacuous: the other direction (stored file as the layout).
    EXPECT_EQ(wp::layoutDifference(std::string(v.layout), definition, &differences), "");
  }
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
