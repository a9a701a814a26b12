// Foreign detections through the multi-object tracker (rules/foreign_detections.hpp), on
// sequences serialized by genpy from the stored upstream definitions
// (test/foreign/make_detection_fixtures.py): two people walk past each other, the detections'
// order alternates and vision_msgs' results[0].id is overloaded as a "track id" that swaps
// between them every frame. The tracks must keep their own ids, follow the true positions
// and converge to the true velocities, whatever those ids say.

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "allocation_counter.hpp"  // test/shared
#include "workspace_proximity/rules/foreign_detections.hpp"

namespace wp = workspace_proximity;

namespace {

struct Truth {
  Eigen::Vector3d position, velocity;
};

struct Frame {
  wp::Stamp stamp = 0;
  std::vector<std::uint8_t> bytes;
  std::map<std::string, Truth> truth;
};

struct Sequence {
  std::string type, md5;
  std::vector<Frame> frames;
};

Sequence readSequence(const std::string& name) {
  const std::string dir = std::string(WP_SOURCE_DIR) + "/test/foreign/fixtures/";
  Sequence s;
  std::ifstream text(dir + name + ".txt");
  std::string word;
  text >> word >> s.type >> s.md5;
  EXPECT_EQ(word, "type");
  while (text >> word) {
    if (word == "frame") {
      long long secs = 0, nsecs = 0;
      int count = 0;
      text >> secs >> nsecs >> count;
      s.frames.emplace_back();
      s.frames.back().stamp = secs * 1000000000LL + nsecs;
    } else {
      EXPECT_EQ(word, "truth");
      std::string who;
      Truth t;
      text >> who >> t.position.x() >> t.position.y() >> t.position.z() >> t.velocity.x() >>
          t.velocity.y() >> t.velocity.z();
      s.frames.back().truth[who] = t;
    }
  }
  std::ifstream in(dir + name + ".bin", std::ios::binary);
  const std::vector<std::uint8_t> all((std::istreambuf_iterator<char>(in)),
                                      std::istreambuf_iterator<char>());
  std::size_t at = 0;
  for (Frame& f : s.frames) {
    std::uint32_t length = 0;
    EXPECT_LE(at + 4, all.size());
    std::memcpy(&length, all.data() + at, 4);  // little-endian, as the machines here are
    at += 4;
    f.bytes.assign(all.begin() + static_cast<long>(at), all.begin() + static_cast<long>(at + length));
    at += length;
  }
  EXPECT_EQ(at, all.size());
  EXPECT_EQ(s.frames.size(), 30u);
  return s;
}

wp::ForeignDetectionParams params() {
  wp::ForeignDetectionParams p;
  p.tracker.confirm_hits = 2;
  return p;
}

// Every frame through the decoder and the tracker: from the second frame on two tracks, each
// with one id for the whole walk, at its person's true place; the velocity converges.
void walk(const std::string& name, const Eigen::Isometry3d& fixed_from_camera,
          double expected_height) {
  SCOPED_TRACE(name);
  const Sequence s = readSequence(name);
  wp::ForeignDetections detections(params());
  wp::ForeignTrackArray array;
  std::map<std::string, std::string> id_of;  // person -> track id
  for (std::size_t k = 0; k < s.frames.size(); ++k) {
    const Frame& f = s.frames[k];
    ASSERT_EQ(wp::decodeForeignTracks(s.type, s.md5, f.bytes.data(), f.bytes.size(), &array),
              wp::ForeignRefusal::kNone)
        << array.detail;
    EXPECT_EQ(array.stamp, f.stamp);
    ASSERT_EQ(detections.ingest(array, fixed_from_camera), wp::DetectionRefusal::kNone);
    const std::vector<wp::BoxObservation>& tracks = detections.tracks();
    if (k == 0) {
      EXPECT_TRUE(tracks.empty()) << "tentative after one detection";
      continue;
    }
    ASSERT_EQ(tracks.size(), 2u) << "frame " << k;
    for (const wp::BoxObservation& b : tracks) {
      // Its person: the nearer truth (they are at least 0.8 m apart throughout).
      std::string person;
      double best = 1e9;
      for (const auto& [who, t] : f.truth) {
        const double d = (b.position - fixed_from_camera * t.position).norm();
        if (d < best) {
          best = d;
          person = who;
        }
      }
      EXPECT_LT(best, 0.05) << "frame " << k;
      std::string& id = id_of[person];
      if (id.empty()) id = std::string(b.id);
      EXPECT_EQ(std::string(b.id), id) << "frame " << k << ": " << person << " changed id";
      EXPECT_EQ(b.label, "unknown");
      EXPECT_NEAR(b.dimensions.z(), expected_height, 1e-12);
      std::string why;
      EXPECT_EQ(wp::checkBox(b, wp::BoxLimits(), &why), wp::Drop::kCount) << why;
      if (k + 1 == s.frames.size()) {
        const Eigen::Vector3d v = fixed_from_camera.linear() * f.truth.at(person).velocity;
        EXPECT_LT((b.linear_velocity - v).norm(), 0.05) << person << " " << b.linear_velocity.transpose();
        EXPECT_TRUE(b.velocity_known);
      }
    }
  }
  ASSERT_EQ(id_of.size(), 2u);
  EXPECT_NE(id_of["A"], id_of["B"]);
}

}  // namespace

TEST(ForeignDetections, Detection3DArrayIdsAreTheTrackersNotTheMessages) {
  walk("walk_detections3d", Eigen::Isometry3d::Identity(), 1.7);
}

TEST(ForeignDetections, JskBoxesWithoutHeightTakeTheDefault) {
  walk("walk_jsk", Eigen::Isometry3d::Identity(), 1.8);
}

TEST(ForeignDetections, MarkerArraySolidMarkersAreDetections) {
  walk("walk_markers", Eigen::Isometry3d::Identity(), 1.7);
}

TEST(ForeignDetections, PoseArrayPosesTakeTheDefaultSize) {
  walk("walk_poses", Eigen::Isometry3d::Identity(), 1.8);
}

TEST(ForeignDetections, TheDebianTypesDecodeAsGenpyWroteThem) {
  // MarkerArray: per person a CYLINDER (read), a TEXT_VIEW_FACING and an ARROW (ignored), and
  // a DELETE (ignored); no header of its own: the first solid marker's stamp and frame.
  // PoseArray: its poses, without sizes. Every shorter prefix is refused.
  for (const char* name : {"walk_markers", "walk_poses"}) {
    SCOPED_TRACE(name);
    const Sequence s = readSequence(name);
    const bool markers = std::string(name) == "walk_markers";
    wp::ForeignTrackArray array;
    for (const Frame& f : s.frames) {
      ASSERT_EQ(wp::decodeForeignTracks(s.type, s.md5, f.bytes.data(), f.bytes.size(), &array),
                wp::ForeignRefusal::kNone)
          << array.detail;
      ASSERT_EQ(array.tracks.size(), 2u);
      EXPECT_EQ(array.ignored, markers ? 5u : 0u);
      EXPECT_EQ(array.stamp, f.stamp);
      EXPECT_EQ(array.frame_id, "camera");
      EXPECT_EQ(array.version->family, wp::ForeignFamily::kDetections);
      for (const wp::ForeignTrack& t : array.tracks) {
        EXPECT_EQ(t.id_kind, wp::ForeignIdKind::kNone);
        EXPECT_EQ(t.dimension_axes, markers ? wp::kAxesAll : wp::kAxesNone);
        bool someone = false;
        for (const auto& [who, truth] : f.truth) {
          someone = someone || (t.position - truth.position).norm() < 1e-12;
        }
        EXPECT_TRUE(someone) << t.position.transpose();
      }
    }
    const std::vector<std::uint8_t>& bytes = s.frames[3].bytes;
    for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
      wp::decodeForeignTracks(s.type, s.md5, bytes.data(), cut, &array);
      EXPECT_NE(array.refusal, wp::ForeignRefusal::kNone) << "cut at " << cut;
    }
  }
}

TEST(ForeignDetections, TheTrackerRunsInTheFixedFrame) {
  // A camera 2 m up and turned 90 degrees about z: tracks, their velocities and orientations
  // come out in the fixed frame.
  Eigen::Isometry3d fixed_from_camera = Eigen::Isometry3d::Identity();
  fixed_from_camera.translate(Eigen::Vector3d(1.0, -2.0, 2.0));
  fixed_from_camera.rotate(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  walk("walk_detections3d", fixed_from_camera, 1.7);
}

TEST(ForeignDetections, TracksTypesAndOldMessagesAreRefused) {
  const Sequence s = readSequence("walk_detections3d");
  wp::ForeignDetections detections(params());
  wp::ForeignTrackArray array;
  ASSERT_EQ(wp::decodeForeignTracks(s.type, s.md5, s.frames[5].bytes.data(),
                                    s.frames[5].bytes.size(), &array),
            wp::ForeignRefusal::kNone);
  EXPECT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()), wp::DetectionRefusal::kNone);
  ASSERT_EQ(wp::decodeForeignTracks(s.type, s.md5, s.frames[4].bytes.data(),
                                    s.frames[4].bytes.size(), &array),
            wp::ForeignRefusal::kNone);
  EXPECT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()),
            wp::DetectionRefusal::kOutOfOrder);
  // A refused decode (cut short) and a people tracker's type are not detections.
  wp::decodeForeignTracks(s.type, s.md5, s.frames[6].bytes.data(), 10, &array);
  EXPECT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()),
            wp::DetectionRefusal::kNotDetections);
  std::ifstream in(std::string(WP_SOURCE_DIR) + "/test/foreign/fixtures/spencer_v2.bin",
                   std::ios::binary);
  const std::vector<std::uint8_t> spencer((std::istreambuf_iterator<char>(in)),
                                          std::istreambuf_iterator<char>());
  ASSERT_EQ(wp::decodeForeignTracks("spencer_tracking_msgs/TrackedPersons",
                                    "21c0b1a57c4933e68f39aa3802861828", spencer.data(),
                                    spencer.size(), &array),
            wp::ForeignRefusal::kNone);
  EXPECT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()),
            wp::DetectionRefusal::kNotDetections);
}

TEST(ForeignDetections, ACovarianceSetsTheMeasurementNoise) {
  // One detection with position variances (0.04, 0.01, 0.09) m^2: sigma = 0.3 m, the largest;
  // confirmed at once, its position error is the filter's first 3 sigma = 0.9 m. Without a
  // covariance: the default 0.05 m, 0.15 m.
  const Sequence s = readSequence("walk_detections3d");
  wp::ForeignTrackArray array;
  ASSERT_EQ(wp::decodeForeignTracks(s.type, s.md5, s.frames[0].bytes.data(),
                                    s.frames[0].bytes.size(), &array),
            wp::ForeignRefusal::kNone);
  wp::ForeignDetectionParams p = params();
  p.tracker.confirm_hits = 1;
  wp::ForeignDetections plain(p);
  plain.ingest(array, Eigen::Isometry3d::Identity());
  ASSERT_EQ(plain.tracks().size(), 2u);
  EXPECT_NEAR(plain.tracks()[0].position_error, 0.15, 1e-12);
  EXPECT_FALSE(plain.tracks()[0].velocity_known);
  array.tracks[0].has_position_covariance = true;
  array.tracks[0].position_covariance = Eigen::Vector3d(0.04, 0.01, 0.09).asDiagonal();
  wp::ForeignDetections covariant(p);
  covariant.ingest(array, Eigen::Isometry3d::Identity());
  ASSERT_EQ(covariant.tracks().size(), 2u);
  EXPECT_NEAR(covariant.tracks()[0].position_error, 0.9, 1e-12);
}

TEST(ForeignDetections, NoAllocationOnceWarm) {
  const Sequence s = readSequence("walk_detections3d");
  wp::ForeignDetections detections(params());
  wp::ForeignTrackArray array;
  long before = 0;
  for (int round = 0; round < 3; ++round) {
    if (round == 1) before = wp_test::allocationCount();
    for (const Frame& f : s.frames) {
      wp::decodeForeignTracks(s.type, s.md5, f.bytes.data(), f.bytes.size(), &array);
      array.stamp += round * 3000000000LL;  // later rounds later in time
      ASSERT_EQ(detections.ingest(array, Eigen::Isometry3d::Identity()),
                wp::DetectionRefusal::kNone);
    }
  }
  EXPECT_EQ(wp_test::allocationCount() - before, 0);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
