// libFuzzer harness over the foreign-message read path (issue 24), ROS-free: arbitrary bytes
// as one serialized message of a catalogue entry, through decodeForeignTracks(), then the
// tracks family through ForeignObservations and checkBox() (as the input bridge does), the
// detections family through ForeignDetections and its tracker, each twice (the same message
// 0.1 s later: finite differences and track confirmation run).
//
// Input: byte 0 picks the catalogue entry (foreignVersions(), in its order; index count: a
// known type with an unknown md5, the rest of the input as the publisher's definition; index
// count + 1: an unknown type named by the rest of the input); the rest is the message.
//
// Checks: a refused message has a named reason and an explanation and no tracks; a read one
// has its version, at most max_tracks tracks, finite values, non-negative variances, axis
// masks of three bits and text that views the input; the same bytes with one byte more are
// refused as overlong, with one byte less as truncated or of a bad length; every observation
// is either refused by checkBox() with an explanation or has finite numbers; the detection
// tracker's tracks are finite.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "fuzz_input.hpp"
#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/foreign_detections.hpp"
#include "workspace_proximity/rules/foreign_observations.hpp"
#include "workspace_proximity/rules/foreign_tracks.hpp"
#include "workspace_proximity/rules/foreign_types.hpp"
#include "workspace_proximity/rules/monitor_params.hpp"

namespace wp = workspace_proximity;
using wp::ForeignRefusal;
using wp_fuzz::fail;

namespace {

constexpr std::size_t kMaxTracks = 64;
constexpr wp::Stamp kLater = 100000000;  // ns: the second pass, 0.1 s after the message

bool inside(std::string_view s, const std::uint8_t* data, std::size_t size) {
  if (s.empty()) return true;
  const auto* p = reinterpret_cast<const std::uint8_t*>(s.data());
  return p >= data && p + s.size() <= data + size;
}

void checkDecoded(const wp::ForeignTrackArray& a, ForeignRefusal r, std::string_view md5,
                  const std::uint8_t* data, std::size_t size) {
  WP_FUZZ_CHECK(r == a.refusal, wp::foreignRefusalName(r));
  if (r != ForeignRefusal::kNone) {
    const std::string name = wp::foreignRefusalName(r);
    WP_FUZZ_CHECK(name != "unknown_refusal" && name != "none", name);
    WP_FUZZ_CHECK(!a.detail.empty(), name);
    WP_FUZZ_CHECK(a.tracks.empty(), name);
    return;
  }
  WP_FUZZ_CHECK(a.version != nullptr && a.version->md5 == md5, std::string(md5));
  WP_FUZZ_CHECK(a.detail.empty(), a.detail);
  WP_FUZZ_CHECK(a.tracks.size() <= a.max_tracks, std::to_string(a.tracks.size()));
  WP_FUZZ_CHECK(inside(a.frame_id, data, size), "array frame_id");
  for (std::size_t i = 0; i < a.tracks.size(); ++i) {
    const wp::ForeignTrack& t = a.tracks[i];
    const std::string at = "track " + std::to_string(i);
    WP_FUZZ_CHECK(t.position.allFinite() && t.velocity.allFinite() && t.dimensions.allFinite(),
                  at);
    WP_FUZZ_CHECK(!t.has_orientation || t.quaternion.allFinite(), at);
    WP_FUZZ_CHECK(t.position_covariance.allFinite() && t.velocity_covariance.allFinite(), at);
    WP_FUZZ_CHECK((t.position_covariance.diagonal().array() >= 0.0).all() &&
                      (t.velocity_covariance.diagonal().array() >= 0.0).all(),
                  at);
    WP_FUZZ_CHECK(t.position_axes <= wp::kAxesAll && t.velocity_axes <= wp::kAxesAll &&
                      t.dimension_axes <= wp::kAxesAll,
                  at);
    WP_FUZZ_CHECK(inside(t.frame_id, data, size), at + " frame_id");
    WP_FUZZ_CHECK(t.id_kind != wp::ForeignIdKind::kText || inside(t.id_text, data, size),
                  at + " id_text");
  }
}

bool finiteObservation(const wp::BoxObservation& b) {
  return b.position.allFinite() && b.quaternion.allFinite() && b.dimensions.allFinite() &&
         b.linear_velocity.allFinite() && b.angular_velocity.allFinite() &&
         std::isfinite(b.position_error) && b.position_error >= 0.0 &&
         std::isfinite(b.velocity_error) && b.velocity_error >= 0.0;
}

void checkObservations(const std::vector<wp::BoxObservation>& boxes) {
  const wp::BoxLimits limits;
  std::string detail;
  for (const wp::BoxObservation& b : boxes) {
    detail.clear();
    const wp::Drop drop = wp::checkBox(b, limits, &detail);
    if (drop != wp::Drop::kCount) {
      WP_FUZZ_CHECK(!detail.empty(), wp::dropName(drop));
      continue;
    }
    WP_FUZZ_CHECK(finiteObservation(b), "accepted observation " + std::string(b.id));
  }
}

void runTracks(const wp::ForeignTrackArray& a) {
  static const wp::MonitorParams params;
  wp::ForeignObservations conv(kMaxTracks);
  std::vector<wp::BoxObservation> boxes;
  boxes.reserve(kMaxTracks);
  conv.convert(a, a.frame_id, params, &boxes);
  WP_FUZZ_CHECK(boxes.size() + conv.skippedFrame() + conv.skippedPosition() == a.tracks.size(),
                "converted + skipped != tracks");
  checkObservations(boxes);
  // The same tracks 0.1 s later: velocities by finite differences where none was given.
  wp::ForeignTrackArray later = a;
  later.stamp += kLater;
  for (wp::ForeignTrack& t : later.tracks) t.stamp += kLater;
  conv.convert(later, later.frame_id, params, &boxes);
  checkObservations(boxes);
}

void runDetections(const wp::ForeignTrackArray& a) {
  static const wp::ForeignDetectionParams params = [] {
    wp::ForeignDetectionParams p;
    p.tracker.max_detections = static_cast<int>(kMaxTracks);
    p.tracker.capacity = static_cast<int>(kMaxTracks);
    return p;
  }();
  wp::ForeignDetections detections(params);
  // The message's frame 30 degrees about z and 1 m, 2 m off the fixed frame's origin.
  Eigen::Isometry3d fixed_from_frame = Eigen::Isometry3d::Identity();
  fixed_from_frame.rotate(Eigen::AngleAxisd(M_PI / 6, Eigen::Vector3d::UnitZ()));
  fixed_from_frame.pretranslate(Eigen::Vector3d(1.0, 2.0, 0.0));
  const bool is_detections = a.refusal == ForeignRefusal::kNone && a.version != nullptr &&
                             a.version->family == wp::ForeignFamily::kDetections;
  wp::ForeignTrackArray later = a;
  later.stamp += kLater;
  const wp::ForeignTrackArray* frames[] = {&a, &later};
  for (const wp::ForeignTrackArray* frame : frames) {
    const wp::DetectionRefusal r = detections.ingest(*frame, fixed_from_frame);
    if (!is_detections) {
      WP_FUZZ_CHECK(r == wp::DetectionRefusal::kNotDetections, "tracks family ingested");
      return;
    }
    WP_FUZZ_CHECK(r == wp::DetectionRefusal::kNone, "in-order detections refused");
    for (const wp::BoxObservation& b : detections.tracks()) {
      WP_FUZZ_CHECK(finiteObservation(b), "tracker track " + std::string(b.id));
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  std::size_t count = 0;
  const wp::ForeignVersion* versions = wp::foreignVersions(&count);
  const std::size_t pick = data[0] % (count + 2);
  const std::uint8_t* msg = data + 1;
  const std::size_t n = size - 1;
  const std::string_view rest(reinterpret_cast<const char*>(msg), n);

  std::string_view type = versions[pick % count].type;
  std::string_view md5 = versions[pick % count].md5;
  std::string_view definition;
  if (pick == count) {
    md5 = "00000000000000000000000000000000";
    definition = rest;
  } else if (pick == count + 1) {
    type = rest.substr(0, 64);
  }

  wp::ForeignTrackArray a(kMaxTracks);
  const ForeignRefusal r = wp::decodeForeignTracks(type, md5, msg, n, &a, definition);
  checkDecoded(a, r, md5, msg, n);
  // The made-up type may spell the catalogue's type of the md5 it is paired with (a campaign
  // found "people_msgs/PositionMeasurementArray" beside its own md5): then it is known.
  bool catalogued = false;
  for (std::size_t v = 0; v < count; ++v) catalogued |= versions[v].type == type && versions[v].md5 == md5;
  if (pick >= count && !catalogued) {
    WP_FUZZ_CHECK(r == ForeignRefusal::kUnknownMd5 || r == ForeignRefusal::kUnknownType,
                  wp::foreignRefusalName(r));
  }

  if (r == ForeignRefusal::kNone) {
    // Documented: bytes after the last field are refused; a message cut short never reads.
    std::vector<std::uint8_t> copy(msg, msg + n);
    copy.push_back(0);
    wp::ForeignTrackArray other(kMaxTracks);
    const ForeignRefusal longer =
        wp::decodeForeignTracks(type, md5, copy.data(), copy.size(), &other, definition);
    checkDecoded(other, longer, md5, copy.data(), copy.size());
    WP_FUZZ_CHECK(longer == ForeignRefusal::kOverlong, wp::foreignRefusalName(longer));
    if (n > 0) {
      const ForeignRefusal shorter =
          wp::decodeForeignTracks(type, md5, copy.data(), n - 1, &other, definition);
      checkDecoded(other, shorter, md5, copy.data(), n - 1);
      WP_FUZZ_CHECK(shorter == ForeignRefusal::kTruncated || shorter == ForeignRefusal::kBadLength,
                    wp::foreignRefusalName(shorter));
    }
    if (a.version->family == wp::ForeignFamily::kTracks) runTracks(a);
  }
  runDetections(a);
  return 0;
}
