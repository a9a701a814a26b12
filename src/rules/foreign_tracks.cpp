#include "workspace_proximity/rules/foreign_tracks.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <sstream>

#include "workspace_proximity/rules/ros1_wire.hpp"

namespace workspace_proximity {
namespace {

namespace ws = wire_size;

// Minimal wire sizes of the elements of each array (every fixed field, empty strings and
// arrays): a length prefix larger than the bytes left allow is refused before anything is read.
constexpr std::size_t kPersonMin = 4 + 24 + 24 + 8 + 4 + 4;  // people_msgs/Person
constexpr std::size_t kPositionMeasurementMin = ws::kHeaderMin + 4 + 4 + 24 + 8 + 72 + 1;
constexpr std::size_t kLegPersonMin = ws::kPose + 4;
constexpr std::size_t kObjectMin =
    ws::kHeaderMin + 4 + 1 + 1 + ws::kPose + ws::kTwist + ws::kTwist + 4 + (1 + 4) + 1 + 1 + 4;
constexpr std::size_t kObjectWithCovarianceMin = ws::kHeaderMin + 4 + 1 + 1 +
                                                 ws::kPoseWithCovariance +
                                                 2 * ws::kTwistWithCovariance + 4 +
                                                 (1 + 4 + 4) + 1 + 1 + 4;
constexpr std::size_t kSegmentBytes = 2 * ws::kPoint;
constexpr std::size_t kCircleBytes = 2 * ws::kPoint + 8 + 8;
constexpr std::size_t kHypothesisBytes = 8 + 8 + ws::kPoseWithCovariance;
constexpr std::size_t kPointCloud2Min = ws::kHeaderMin + 4 + 4 + 4 + 1 + 4 + 4 + 4 + 1;
constexpr std::size_t kPointFieldMin = 4 + 4 + 1 + 4;
constexpr std::size_t kDetection3DMin = ws::kHeaderMin + 4 + (ws::kPose + ws::kPoint) +
                                        kPointCloud2Min;
constexpr std::size_t kJskBoxV1Min = ws::kHeaderMin + ws::kPose + ws::kPoint;
constexpr std::size_t kJskBoxV2Min = kJskBoxV1Min + 4 + 4;
// visualization_msgs/Marker: header, ns, id, type, action, pose, scale, color, lifetime,
// frame_locked, points[], colors[], text, mesh_resource, mesh_use_embedded_materials.
constexpr std::size_t kMarkerMin =
    ws::kHeaderMin + 4 + 4 + 4 + 4 + ws::kPose + ws::kPoint + 16 + 8 + 1 + 4 + 4 + 4 + 4 + 1;
// workspace_proximity/TrackedBox v1: id, label, pose, dimensions, twist.
constexpr std::size_t kTrackedBoxV1Min = 4 + 4 + ws::kPose + ws::kPoint + ws::kTwist;
constexpr std::int32_t kMarkerCube = 1, kMarkerSphere = 2, kMarkerCylinder = 3;
constexpr std::int32_t kMarkerAdd = 0;  // ADD and MODIFY

constexpr std::string_view kPerson = "person";
constexpr std::uint8_t kObjectTracked = 1;  // derived_object_msgs OBJECT_TRACKED

// derived_object_msgs/Object's CLASSIFICATION_* constants, in value order.
constexpr std::string_view kClassifications[] = {
    "unknown", "unknown_small", "unknown_medium", "unknown_big", "pedestrian", "bike", "car",
    "truck", "motorcycle", "other_vehicle", "barrier", "sign"};

template <typename... Parts>
std::string explain(const Parts&... parts) {
  std::ostringstream why;
  (why << ... << parts);
  return why.str();
}

ForeignRefusal refuse(ForeignTrackArray* out, ForeignRefusal reason, std::string text) {
  out->refusal = reason;
  out->detail = std::move(text);
  out->tracks.clear();
  return reason;
}

void readHeader(WireReader& r, Stamp* stamp, std::string_view* frame_id) {
  r.u32();  // seq
  *stamp = r.time();
  *frame_id = r.string();
}

// A new track stamped with the array's header (an element's own header may replace it).
ForeignTrack& newTrack(ForeignTrackArray* out) {
  ForeignTrack& t = out->tracks.emplace_back();
  t.stamp = out->stamp;
  t.frame_id = out->frame_id;
  return t;
}

void readElementHeader(WireReader& r, ForeignTrack* t) {
  Stamp stamp = 0;
  std::string_view frame_id;
  readHeader(r, &stamp, &frame_id);
  if (stamp != 0) t->stamp = stamp;
  if (!frame_id.empty()) t->frame_id = frame_id;
}

bool fits(std::uint32_t count, ForeignTrackArray* out) {
  if (count <= out->max_tracks) return true;
  refuse(out, ForeignRefusal::kTooManyTracks,
         explain(count, " tracks exceed the capacity of ", out->max_tracks));
  return false;
}

// The array of tracks every decoder reads: its length is checked against the bytes left (at
// least `element_min` each) and the capacity before anything is read, then `read_element` reads
// each element into a new track.
template <typename ReadElement>
ForeignRefusal readTracks(WireReader& r, ForeignTrackArray* out, std::size_t element_min,
                          ReadElement read_element) {
  const std::uint32_t n = r.arrayLength(element_min);
  if (!fits(n, out)) return out->refusal;
  for (std::uint32_t i = 0; i < n && r.ok(); ++i) read_element(newTrack(out));
  return ForeignRefusal::kNone;
}

// geometry_msgs/Pose: a track's position and orientation.
void readPose(WireReader& r, ForeignTrack* t) {
  t->position = r.vector3();
  t->quaternion = r.quaternion();
  t->has_orientation = true;
}

// A box as vision_msgs/BoundingBox3D and jsk_recognition_msgs/BoundingBox hold it: its pose,
// then its full extents.
void readBox(WireReader& r, ForeignTrack* t) {
  readPose(r, t);
  t->dimensions = r.vector3();
  t->dimension_axes = kAxesAll;
}

Eigen::Matrix3d block3(const double* cov, int stride) {
  Eigen::Matrix3d m;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m(i, j) = cov[i * stride + j];
  }
  return m;
}

// Rows and columns of the axes a mask leaves out become 0 (they say nothing).
void keepAxes(std::uint8_t axes, Eigen::Vector3d* v, Eigen::Matrix3d* cov) {
  for (int i = 0; i < 3; ++i) {
    if (axes & (1u << i)) continue;
    (*v)[i] = 0.0;
    cov->row(i).setZero();
    cov->col(i).setZero();
  }
}

// spencer_tracking_msgs: "z value and orientation [rotational velocities] might not be set,
// check if corresponding variance on diagonal is > 99999". Applied to every axis; a NaN
// variance counts as set, so the finiteness check refuses it.
std::uint8_t setAxes(const double* cov6) {
  std::uint8_t axes = 0;
  for (int i = 0; i < 3; ++i) {
    if (!(cov6[i * 7] > kSpencerUnsetVariance)) axes |= static_cast<std::uint8_t>(1u << i);
  }
  return axes;
}

void applySpencerCovariances(const double* pose_cov, const double* twist_cov, ForeignTrack* t) {
  t->position_axes = setAxes(pose_cov);
  t->has_orientation = setAxes(pose_cov + 21) == kAxesAll;  // rows 3..5: rotations
  if (!t->has_orientation) t->quaternion = Eigen::Vector4d(0, 0, 0, 1);
  t->velocity_axes = setAxes(twist_cov);
  t->position_covariance = block3(pose_cov, 6);
  t->velocity_covariance = block3(twist_cov, 6);
  keepAxes(t->position_axes, &t->position, &t->position_covariance);
  keepAxes(t->velocity_axes, &t->velocity, &t->velocity_covariance);
  t->has_position_covariance = t->position_axes != kAxesNone;
  t->has_velocity_covariance = t->velocity_axes != kAxesNone;
}

// shape_msgs/SolidPrimitive (and derived_object_msgs' copy) as full extents: BOX x, y, z;
// SPHERE radius; CYLINDER and CONE height, radius. Anything else leaves the size unknown.
void readShape(WireReader& r, bool with_covariance, ForeignTrack* t) {
  const std::uint8_t type = r.u8();
  const std::uint32_t n = r.arrayLength(8);
  double d[3] = {0.0, 0.0, 0.0};
  for (std::uint32_t i = 0; i < n && r.ok(); ++i) {
    const double v = r.f64();
    if (i < 3) d[i] = v;
  }
  if (with_covariance) r.skipArray(8);
  if (type == 1 && n == 3) {
    t->dimensions = Eigen::Vector3d(d[0], d[1], d[2]);
  } else if (type == 2 && n == 1) {
    t->dimensions = Eigen::Vector3d::Constant(2.0 * d[0]);
  } else if ((type == 3 || type == 4) && n == 2) {
    t->dimensions = Eigen::Vector3d(2.0 * d[1], 2.0 * d[1], d[0]);
  } else {
    return;
  }
  t->dimension_axes = kAxesAll;
}

ForeignRefusal decodePeople(WireReader& r, ForeignTrackArray* out) {
  readHeader(r, &out->stamp, &out->frame_id);
  return readTracks(r, out, kPersonMin, [&](ForeignTrack& t) {
    t.id_kind = ForeignIdKind::kText;
    t.id_text = r.string();
    t.label = kPerson;
    t.position = r.vector3();
    t.velocity = r.vector3();
    t.velocity_axes = kAxesAll;
    r.f64();  // reliability
    r.skipStringArray();  // tagnames
    r.skipStringArray();  // tags
  });
}

ForeignRefusal decodePositionMeasurements(WireReader& r, ForeignTrackArray* out) {
  readHeader(r, &out->stamp, &out->frame_id);
  const ForeignRefusal refusal =
      readTracks(r, out, kPositionMeasurementMin, [&](ForeignTrack& t) {
        readElementHeader(r, &t);
        r.string();  // name: the detector's
        t.id_kind = ForeignIdKind::kText;
        t.id_text = r.string();  // object_id
        t.label = kPerson;
        t.position = r.vector3();
        r.f64();  // reliability
        double cov[9];
        r.f64s(cov, 9);
        t.position_covariance = block3(cov, 3);
        t.has_position_covariance = true;
        r.u8();  // initialization
      });
  if (refusal != ForeignRefusal::kNone) return refusal;
  r.skipArray(4);  // cooccurrence
  return ForeignRefusal::kNone;
}

ForeignRefusal decodeSpencer(WireReader& r, ForeignTrackArray* out, int version) {
  readHeader(r, &out->stamp, &out->frame_id);
  const std::size_t min = 8 + 1 + (version >= 2 ? 1 : 0) + 8 + (version == 3 ? 4 : 0) + 8 +
                          ws::kPoseWithCovariance + ws::kTwistWithCovariance;
  return readTracks(r, out, min, [&](ForeignTrack& t) {
    t.id_kind = ForeignIdKind::kNumber;
    t.id_number = r.u64();
    t.label = kPerson;
    r.boolean();                   // is_occluded: the track is still predicted
    if (version >= 2) r.boolean();  // is_matched
    r.u64();                       // detection_id
    if (version == 3) r.skipArray(8);  // detection_ids
    r.duration();                  // age
    t.position = r.vector3();
    t.quaternion = r.quaternion();
    double pose_cov[36];
    r.f64s(pose_cov, 36);
    t.velocity = r.vector3();
    r.vector3();  // angular velocity
    double twist_cov[36];
    r.f64s(twist_cov, 36);
    applySpencerCovariances(pose_cov, twist_cov, &t);  // and whether the orientation is set
  });
}

// Parallel arrays must match the uuids' count.
bool sameLength(std::uint32_t n, std::uint32_t m, const char* what, ForeignTrackArray* out,
                const WireReader& r) {
  if (!r.ok() || m == n) return true;
  refuse(out, ForeignRefusal::kArrayMismatch,
         explain(n, " uuids but ", m, " ", what, " (the arrays are parallel)"));
  return false;
}

ForeignRefusal decodeBayes(WireReader& r, ForeignTrackArray* out, bool with_velocities) {
  readHeader(r, &out->stamp, &out->frame_id);
  const ForeignRefusal refusal = readTracks(r, out, 4, [&](ForeignTrack& t) {
    t.id_kind = ForeignIdKind::kText;
    t.id_text = r.string();
    t.label = kPerson;
  });
  if (refusal != ForeignRefusal::kNone) return refusal;
  // One track per uuid read (all of them unless the reader failed, and then sameLength passes
  // and the message is refused as truncated or of a bad length).
  const auto n = static_cast<std::uint32_t>(out->tracks.size());
  const std::uint32_t poses = r.arrayLength(ws::kPose);
  if (!sameLength(n, poses, "poses", out, r)) return out->refusal;
  for (std::uint32_t i = 0; i < poses && r.ok(); ++i) readPose(r, &out->tracks[i]);
  if (with_velocities) {
    const std::uint32_t velocities = r.arrayLength(ws::kPoint);
    if (!sameLength(n, velocities, "velocities", out, r)) return out->refusal;
    for (std::uint32_t i = 0; i < velocities && r.ok(); ++i) {
      out->tracks[i].velocity = r.vector3();
      out->tracks[i].velocity_axes = kAxesAll;
    }
  }
  const std::uint32_t distances = r.arrayLength(8);
  if (!sameLength(n, distances, "distances", out, r)) return out->refusal;
  r.skip(std::size_t{distances} * 8);
  const std::uint32_t angles = r.arrayLength(8);
  if (!sameLength(n, angles, "angles", out, r)) return out->refusal;
  r.skip(std::size_t{angles} * 8);
  r.f64();  // min_distance
  r.f64();  // min_distance_angle
  return ForeignRefusal::kNone;
}

ForeignRefusal decodeLegTracker(WireReader& r, ForeignTrackArray* out) {
  readHeader(r, &out->stamp, &out->frame_id);
  return readTracks(r, out, kLegPersonMin, [&](ForeignTrack& t) {
    t.label = kPerson;
    readPose(r, &t);
    t.id_kind = ForeignIdKind::kNumber;
    t.id_number = r.u32();
  });
}

ForeignRefusal decodeDerivedObjects(WireReader& r, ForeignTrackArray* out, bool covariance) {
  readHeader(r, &out->stamp, &out->frame_id);
  const std::size_t min = covariance ? kObjectWithCovarianceMin : kObjectMin;
  return readTracks(r, out, min, [&](ForeignTrack& t) {
    readElementHeader(r, &t);
    t.id_kind = ForeignIdKind::kNumber;
    t.id_number = r.u32();
    // "An object which is tracked should also be assumed to have valid twist and accel
    // properties": a merely detected one (or an unknown level) has no velocity.
    const bool tracked = r.u8() == kObjectTracked;
    const bool classified = r.boolean();
    readPose(r, &t);
    double pose_cov[36];
    if (covariance) r.f64s(pose_cov, 36);
    t.velocity = r.vector3();
    r.vector3();  // angular
    double twist_cov[36];
    if (covariance) r.f64s(twist_cov, 36);
    r.skip(ws::kTwist + (covariance ? 288 : 0));  // accel
    r.skipArray(12);                              // polygon: Point32[]
    readShape(r, covariance, &t);
    const std::uint8_t classification = r.u8();
    r.u8();   // classification_certainty
    r.u32();  // classification_age
    t.label = classified && classification < std::size(kClassifications)
                  ? kClassifications[classification]
                  : kClassifications[0];
    if (covariance) {
      t.position_covariance = block3(pose_cov, 6);
      t.has_position_covariance = true;
    }
    if (tracked) {
      t.velocity_axes = kAxesAll;
      if (covariance) {
        t.velocity_covariance = block3(twist_cov, 6);
        t.has_velocity_covariance = true;
      }
    } else {
      t.velocity.setZero();
    }
  });
}

// obstacle_detector (tysik/obstacle_detector, a 2-D laser's obstacles): segments, then circles,
// neither with an id, so both go through the multi-object tracker (the detections family).
// Read: a segment's two points, as its midpoint, its yaw about z and its length; a circle's
// centre and true_radius (radius adds obstacle_detector's own margin, radius_enlargement or
// radius_margin: the monitor adds its own; where true_radius is not within (0, radius] the
// larger radius). Not read, as the upstream source shows (msg/, src/obstacle_extractor.cpp,
// src/obstacle_tracker.cpp at bd59d405): z (the extractor writes x and y only, so the frame's
// z = 0, "map" by default, is where the object stands) and the circles' velocity (the
// extractor writes 0 for "not measured", the tracker's output is the same type with no flag,
// a new tracked circle starts at velocity 0, and no covariance is published: 0 cannot be told
// from "unknown", so the velocity is unknown until this monitor's tracker measures it).
constexpr std::string_view kSegmentLabel = "segment";

ForeignRefusal decodeObstacles(WireReader& r, ForeignTrackArray* out) {
  readHeader(r, &out->stamp, &out->frame_id);
  const ForeignRefusal refusal = readTracks(r, out, kSegmentBytes, [&](ForeignTrack& t) {
    t.label = kSegmentLabel;
    const Eigen::Vector3d first = r.vector3();
    const Eigen::Vector3d last = r.vector3();
    const Eigen::Vector2d along = (last - first).head<2>();
    t.position = 0.5 * (first + last);
    t.position_axes = kAxesXY;
    const double yaw = std::atan2(along.y(), along.x());
    t.quaternion = Eigen::Vector4d(0.0, 0.0, std::sin(0.5 * yaw), std::cos(0.5 * yaw));
    t.has_orientation = true;
    t.dimensions = Eigen::Vector3d(along.norm(), 0.0, 0.0);  // its thickness, height: the label's
    t.dimension_axes = 0b001;
  });
  if (refusal != ForeignRefusal::kNone) return refusal;
  const std::size_t segments = out->tracks.size();
  const std::uint32_t circles = r.arrayLength(kCircleBytes);
  const std::size_t total = std::min<std::size_t>(segments + circles, UINT32_MAX);
  if (!fits(static_cast<std::uint32_t>(total), out)) return out->refusal;
  for (std::uint32_t i = 0; i < circles && r.ok(); ++i) {
    ForeignTrack& t = newTrack(out);
    t.label = {};  // the detections' own label (unknown)
    t.position = r.vector3();
    t.position_axes = kAxesXY;
    r.vector3();  // velocity: see above
    const double radius = r.f64();
    const double true_radius = r.f64();
    // A non-finite true_radius is kept, so that the message is refused as non_finite.
    const bool consistent = true_radius > 0.0 && true_radius <= radius;
    const double used = consistent || !std::isfinite(true_radius) ? true_radius : radius;
    t.dimensions = Eigen::Vector3d(2.0 * used, 2.0 * used, 0.0);
    t.dimension_axes = kAxesXY;
  }
  return ForeignRefusal::kNone;
}

void skipPointCloud2(WireReader& r) {
  Stamp stamp = 0;
  std::string_view frame_id;
  readHeader(r, &stamp, &frame_id);
  r.u32();  // height
  r.u32();  // width
  const std::uint32_t fields = r.arrayLength(kPointFieldMin);
  for (std::uint32_t i = 0; i < fields && r.ok(); ++i) {
    r.string();
    r.skip(4 + 1 + 4);  // offset, datatype, count
  }
  r.u8();   // is_bigendian
  r.u32();  // point_step
  r.u32();  // row_step
  r.skipArray(1);  // data
  r.u8();   // is_dense
}

ForeignRefusal decodeDetections3D(WireReader& r, ForeignTrackArray* out) {
  readHeader(r, &out->stamp, &out->frame_id);
  return readTracks(r, out, kDetection3DMin, [&](ForeignTrack& t) {
    readElementHeader(r, &t);
    // results[].id is a class id (and users overload it): a label number, never a track id.
    // The best hypothesis' pose covariance is the detection's position covariance (its
    // measurement noise in the tracker; all zeros, as many publishers leave it: the default).
    const std::uint32_t results = r.arrayLength(kHypothesisBytes);
    double best = 0.0;
    double covariance[36];
    for (std::uint32_t k = 0; k < results && r.ok(); ++k) {
      const std::int64_t id = r.i64();
      const double score = r.f64();
      r.skip(ws::kPose);
      r.f64s(covariance, 36);
      if (!t.has_label_number || score > best) {
        t.has_label_number = true;
        t.label_number = id;
        t.position_covariance = block3(covariance, 6);
        t.has_position_covariance = true;
        best = score;
      }
    }
    readBox(r, &t);  // bbox
    skipPointCloud2(r);
  });
}

ForeignRefusal decodeJskBoxes(WireReader& r, ForeignTrackArray* out, bool with_label) {
  readHeader(r, &out->stamp, &out->frame_id);
  return readTracks(r, out, with_label ? kJskBoxV2Min : kJskBoxV1Min, [&](ForeignTrack& t) {
    readElementHeader(r, &t);
    readBox(r, &t);
    if (with_label) {
      r.f32();  // value
      t.has_label_number = true;
      t.label_number = r.u32();
    }
  });
}

// Solid markers being added (CUBE, SPHERE, CYLINDER: their scale is their full extents) are
// detections; every other marker (arrows, text, lines, deletions) is ignored and counted. A
// MarkerArray has no header: the first solid marker's stamp and frame are the array's, and a
// solid marker in another frame is ignored too (one transform per message).
ForeignRefusal decodeMarkers(WireReader& r, ForeignTrackArray* out) {
  const std::uint32_t n = r.arrayLength(kMarkerMin);
  bool first = true;
  for (std::uint32_t i = 0; i < n && r.ok(); ++i) {
    Stamp stamp = 0;
    std::string_view frame_id;
    readHeader(r, &stamp, &frame_id);
    r.string();  // ns
    r.i32();     // id: rviz's handle, never a track id
    const std::int32_t type = r.i32();
    const std::int32_t action = r.i32();
    ForeignTrack t;
    readBox(r, &t);  // pose, then scale: the full extents of these three shapes
    r.skip(16);      // color
    r.duration();    // lifetime
    r.u8();          // frame_locked
    r.skipArray(ws::kPoint);  // points
    r.skipArray(16);          // colors
    r.string();               // text
    r.string();               // mesh_resource
    r.u8();                   // mesh_use_embedded_materials
    const bool solid = type == kMarkerCube || type == kMarkerSphere || type == kMarkerCylinder;
    if (first && solid && action == kMarkerAdd) {
      out->stamp = stamp;
      out->frame_id = frame_id;
      first = false;
    }
    if (!solid || action != kMarkerAdd || frame_id != out->frame_id) {
      ++out->ignored;
      continue;
    }
    if (!fits(static_cast<std::uint32_t>(out->tracks.size() + 1), out)) return out->refusal;
    ForeignTrack& kept = newTrack(out);
    kept.position = t.position;
    kept.quaternion = t.quaternion;
    kept.has_orientation = true;
    kept.dimensions = t.dimensions;
    kept.dimension_axes = kAxesAll;
  }
  return ForeignRefusal::kNone;
}

// geometry_msgs/PoseArray: poses only (no size, no class, no id).
ForeignRefusal decodePoses(WireReader& r, ForeignTrackArray* out) {
  readHeader(r, &out->stamp, &out->frame_id);
  return readTracks(r, out, ws::kPose, [&](ForeignTrack& t) { readPose(r, &t); });
}

// This package's TrackedBoxArray before per-box errors (v1): every field as the current
// message's, the errors left at "the label's" and the velocity known, as v1 publishers meant.
ForeignRefusal decodeTrackedBoxesV1(WireReader& r, ForeignTrackArray* out) {
  readHeader(r, &out->stamp, &out->frame_id);
  return readTracks(r, out, kTrackedBoxV1Min, [&](ForeignTrack& t) {
    t.id_kind = ForeignIdKind::kText;
    t.id_text = r.string();
    t.label = r.string();
    readBox(r, &t);
    t.velocity = r.vector3();
    t.velocity_axes = kAxesAll;
    t.angular_velocity = r.vector3();
  });
}

ForeignRefusal decodeFormat(ForeignFormat format, WireReader& r, ForeignTrackArray* out) {
  switch (format) {
    case ForeignFormat::kPeople: return decodePeople(r, out);
    case ForeignFormat::kPositionMeasurementArray: return decodePositionMeasurements(r, out);
    case ForeignFormat::kSpencerV1: return decodeSpencer(r, out, 1);
    case ForeignFormat::kSpencerV2: return decodeSpencer(r, out, 2);
    case ForeignFormat::kSpencerV3: return decodeSpencer(r, out, 3);
    case ForeignFormat::kBayesV1: return decodeBayes(r, out, false);
    case ForeignFormat::kBayesV2: return decodeBayes(r, out, true);
    case ForeignFormat::kLegTrackerPersonArray: return decodeLegTracker(r, out);
    case ForeignFormat::kDerivedObjectArray: return decodeDerivedObjects(r, out, false);
    case ForeignFormat::kDerivedObjectWithCovarianceArray:
      return decodeDerivedObjects(r, out, true);
    case ForeignFormat::kObstacles: return decodeObstacles(r, out);
    case ForeignFormat::kDetection3DArray: return decodeDetections3D(r, out);
    case ForeignFormat::kJskBoxArrayV1: return decodeJskBoxes(r, out, false);
    case ForeignFormat::kJskBoxArrayV2: return decodeJskBoxes(r, out, true);
    case ForeignFormat::kMarkerArray: return decodeMarkers(r, out);
    case ForeignFormat::kPoseArray: return decodePoses(r, out);
    case ForeignFormat::kTrackedBoxArrayV1: return decodeTrackedBoxesV1(r, out);
    case ForeignFormat::kHriIdsList:
      return refuse(out, ForeignRefusal::kUnknownType,
                    "hri_msgs/IdsList lists REP-155 bodies: read by decodeHriIds "
                    "(foreign_skeletons.hpp) and tf, not as tracks");
    case ForeignFormat::kJskHumanSkeletonArray:
      // Bones, not tracks: decodeJskSkeletons reads them (the input bridge dispatches first).
      return refuse(out, ForeignRefusal::kUnknownType,
                    "jsk_recognition_msgs/HumanSkeletonArray is a skeleton type: read by "
                    "decodeJskSkeletons (foreign_skeletons.hpp), not as tracks");
  }
  return refuse(out, ForeignRefusal::kUnknownType, "no decoder for this format");
}

// Every value a track carries must be finite, every variance non-negative.
ForeignRefusal checkTracks(ForeignTrackArray* out) {
  for (std::size_t i = 0; i < out->tracks.size(); ++i) {
    const ForeignTrack& t = out->tracks[i];
    const char* bad = nullptr;
    if (!t.position.allFinite()) bad = "position";
    else if (t.has_orientation && !t.quaternion.allFinite()) bad = "orientation";
    else if (!t.velocity.allFinite()) bad = "velocity";
    else if (!t.angular_velocity.allFinite()) bad = "angular velocity";
    else if (!t.dimensions.allFinite()) bad = "dimensions";
    else if (!t.position_covariance.allFinite()) bad = "position covariance";
    else if (!t.velocity_covariance.allFinite()) bad = "velocity covariance";
    if (bad != nullptr) {
      return refuse(out, ForeignRefusal::kNonFinite,
                    explain("track ", i, ": non-finite ", bad));
    }
    if ((t.position_covariance.diagonal().array() < 0.0).any() ||
        (t.velocity_covariance.diagonal().array() < 0.0).any()) {
      return refuse(out, ForeignRefusal::kBadCovariance,
                    explain("track ", i, ": negative variance"));
    }
  }
  return ForeignRefusal::kNone;
}

}  // namespace

const char* foreignRefusalName(ForeignRefusal refusal) {
  switch (refusal) {
    case ForeignRefusal::kNone: return "none";
    case ForeignRefusal::kUnknownType: return "unknown_type";
    case ForeignRefusal::kUnknownMd5: return "unknown_md5";
    case ForeignRefusal::kTruncated: return "truncated";
    case ForeignRefusal::kBadLength: return "bad_length";
    case ForeignRefusal::kOverlong: return "overlong";
    case ForeignRefusal::kNonFinite: return "non_finite";
    case ForeignRefusal::kBadCovariance: return "bad_covariance";
    case ForeignRefusal::kArrayMismatch: return "array_mismatch";
    case ForeignRefusal::kTooManyTracks: return "too_many_tracks";
  }
  return "unknown_refusal";
}

ForeignRefusal decodeForeignTracks(std::string_view type, std::string_view md5,
                                   const std::uint8_t* data, std::size_t size,
                                   ForeignTrackArray* out, std::string_view definition) {
  out->version = nullptr;
  out->stamp = 0;
  out->frame_id = {};
  out->tracks.clear();
  if (out->tracks.capacity() < out->max_tracks) out->tracks.reserve(out->max_tracks);
  out->ignored = 0;
  out->refusal = ForeignRefusal::kNone;
  out->detail.clear();

  const ForeignVersion* version = findForeignVersion(type, md5);
  if (version == nullptr) {
    if (!isKnownForeignType(type)) {
      return refuse(out, ForeignRefusal::kUnknownType, describeUnknownType(type));
    }
    return refuse(out, ForeignRefusal::kUnknownMd5, describeUnknownMd5(type, md5, definition));
  }
  out->version = version;
  WireReader r(data, size);
  if (decodeFormat(version->format, r, out) != ForeignRefusal::kNone) return out->refusal;
  if (!r.ok()) {
    const ForeignRefusal reason = r.error() == WireError::kTruncated
                                      ? ForeignRefusal::kTruncated
                                      : ForeignRefusal::kBadLength;
    return refuse(out, reason,
                  explain(type, " ", version->version, ": ", r.errorText(), " (at byte ",
                          r.offset(), " of ", size, ")"));
  }
  if (r.remaining() != 0) {
    return refuse(out, ForeignRefusal::kOverlong,
                  explain(type, " ", version->version, ": ", r.remaining(),
                          " bytes after the message's end (", size, " bytes)"));
  }
  return checkTracks(out);
}

}  // namespace workspace_proximity
