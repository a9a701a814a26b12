#include "workspace_proximity/rules/foreign_types.hpp"

#include <algorithm>
#include <sstream>
#include <vector>

namespace workspace_proximity {
namespace {

// The layouts below are the field lines of the definitions in foreign_msgs/ (test_foreign_decoder
// compares them with those files, test_foreign_md5s.py the md5s with the files).
constexpr std::string_view kPeople = R"(std_msgs/Header header
people_msgs/Person[] people
MSG: people_msgs/Person
string name
geometry_msgs/Point position
geometry_msgs/Point velocity
float64 reliability
string[] tagnames
string[] tags
)";

constexpr std::string_view kPositionMeasurementArray = R"(std_msgs/Header header
people_msgs/PositionMeasurement[] people
float32[] cooccurrence
MSG: people_msgs/PositionMeasurement
std_msgs/Header header
string name
string object_id
geometry_msgs/Point pos
float64 reliability
float64[9] covariance
byte initialization
)";

constexpr std::string_view kSpencerV1 = R"(Header header
TrackedPerson[] tracks
MSG: spencer_tracking_msgs/TrackedPerson
uint64 track_id
bool is_occluded
uint64 detection_id
duration age
geometry_msgs/PoseWithCovariance pose
geometry_msgs/TwistWithCovariance twist
)";

constexpr std::string_view kSpencerV2 = R"(Header header
TrackedPerson[] tracks
MSG: spencer_tracking_msgs/TrackedPerson
uint64 track_id
bool is_occluded
bool is_matched
uint64 detection_id
duration age
geometry_msgs/PoseWithCovariance pose
geometry_msgs/TwistWithCovariance twist
)";

constexpr std::string_view kSpencerV3 = R"(Header header
TrackedPerson[] tracks
MSG: spencer_tracking_msgs/TrackedPerson
uint64 track_id
bool is_occluded
bool is_matched
uint64 detection_id
uint64[] detection_ids
duration age
geometry_msgs/PoseWithCovariance pose
geometry_msgs/TwistWithCovariance twist
)";

constexpr std::string_view kBayesV1 = R"(std_msgs/Header header
string[] uuids
geometry_msgs/Pose[] poses
float64[] distances
float64[] angles
float64 min_distance
float64 min_distance_angle
)";

constexpr std::string_view kBayesV2 = R"(std_msgs/Header header
string[] uuids
geometry_msgs/Pose[] poses
geometry_msgs/Vector3[] velocities
float64[] distances
float64[] angles
float64 min_distance
float64 min_distance_angle
)";

constexpr std::string_view kLegTracker = R"(std_msgs/Header header
Person[] people
MSG: leg_tracker/Person
geometry_msgs/Pose pose
uint32 id
)";

constexpr std::string_view kDerivedObjectArray = R"(std_msgs/Header header
derived_object_msgs/Object[] objects
MSG: derived_object_msgs/Object
std_msgs/Header header
uint32 id
uint8 detection_level
bool object_classified
geometry_msgs/Pose pose
geometry_msgs/Twist twist
geometry_msgs/Accel accel
geometry_msgs/Polygon polygon
shape_msgs/SolidPrimitive shape
uint8 classification
uint8 classification_certainty
uint32 classification_age
)";

constexpr std::string_view kDerivedObjectWithCovarianceArray = R"(std_msgs/Header header
derived_object_msgs/ObjectWithCovariance[] objects
MSG: derived_object_msgs/ObjectWithCovariance
std_msgs/Header header
uint32 id
uint8 detection_level
bool object_classified
geometry_msgs/PoseWithCovariance pose
geometry_msgs/TwistWithCovariance twist
geometry_msgs/AccelWithCovariance accel
geometry_msgs/Polygon polygon
derived_object_msgs/SolidPrimitiveWithCovariance shape
uint8 classification
uint8 classification_certainty
uint32 classification_age
MSG: derived_object_msgs/SolidPrimitiveWithCovariance
uint8 type
float64[] dimensions
float64[] covariance
)";

constexpr std::string_view kObstacles = R"(Header header
obstacle_detector/SegmentObstacle[] segments
obstacle_detector/CircleObstacle[] circles
MSG: obstacle_detector/SegmentObstacle
geometry_msgs/Point first_point
geometry_msgs/Point last_point
MSG: obstacle_detector/CircleObstacle
geometry_msgs/Point center
geometry_msgs/Vector3 velocity
float64 radius
float64 true_radius
)";

constexpr std::string_view kDetection3DArray = R"(Header header
Detection3D[] detections
MSG: vision_msgs/Detection3D
Header header
ObjectHypothesisWithPose[] results
BoundingBox3D bbox
sensor_msgs/PointCloud2 source_cloud
MSG: vision_msgs/ObjectHypothesisWithPose
int64 id
float64 score
geometry_msgs/PoseWithCovariance pose
MSG: vision_msgs/BoundingBox3D
geometry_msgs/Pose center
geometry_msgs/Vector3 size
)";

constexpr std::string_view kJskV1 = R"(Header header
BoundingBox[] boxes
MSG: jsk_recognition_msgs/BoundingBox
Header header
geometry_msgs/Pose pose
geometry_msgs/Vector3 dimensions
)";

constexpr std::string_view kJskV2 = R"(Header header
BoundingBox[] boxes
MSG: jsk_recognition_msgs/BoundingBox
Header header
geometry_msgs/Pose pose
geometry_msgs/Vector3 dimensions
float32 value
uint32 label
)";

// The two Debian types of issue 24 (their definitions: /usr/share/<package>/msg, md5s.txt's
// "debian" rows).
constexpr std::string_view kMarkerArray = R"(Marker[] markers
MSG: visualization_msgs/Marker
Header header
string ns
int32 id
int32 type
int32 action
geometry_msgs/Pose pose
geometry_msgs/Vector3 scale
std_msgs/ColorRGBA color
duration lifetime
bool frame_locked
geometry_msgs/Point[] points
std_msgs/ColorRGBA[] colors
string text
string mesh_resource
bool mesh_use_embedded_materials
)";

constexpr std::string_view kPoseArray = R"(Header header
Pose[] poses
)";

// This package's own TrackedBoxArray before TrackedBox gained position_error, velocity_error
// and velocity_unknown (foreign_msgs/workspace_proximity/v1): old publishers and recorded bags.
constexpr std::string_view kTrackedBoxArrayV1 = R"(std_msgs/Header header
TrackedBox[] boxes
MSG: workspace_proximity/TrackedBox
string id
string label
geometry_msgs/Pose pose
geometry_msgs/Vector3 dimensions
geometry_msgs/Twist twist
)";

constexpr std::string_view kHriIdsList = R"(Header header
string[] ids
)";

constexpr std::string_view kJskHumanSkeletonArray = R"(std_msgs/Header header
std_msgs/Int32[] human_ids
jsk_recognition_msgs/HumanSkeleton[] skeletons
MSG: jsk_recognition_msgs/HumanSkeleton
std_msgs/Header header
string[] bone_names
jsk_recognition_msgs/Segment[] bones
MSG: jsk_recognition_msgs/Segment
geometry_msgs/Point start_point
geometry_msgs/Point end_point
)";

using F = ForeignFormat;

// What a format carries and its layout: the format decides both, so that type names sharing a
// layout (pedsim_msgs' copy of spencer's) share them too. A switch, so that a format added
// without them is a compiler warning (-Wswitch), not a row with a wrong layout.
struct FormatFacts {
  ForeignFamily family;
  std::string_view layout;
};

constexpr FormatFacts formatFacts(ForeignFormat format) {
  constexpr ForeignFamily kTracks = ForeignFamily::kTracks;
  constexpr ForeignFamily kDetections = ForeignFamily::kDetections;
  switch (format) {
    case F::kPeople: return {kTracks, kPeople};
    case F::kPositionMeasurementArray: return {kTracks, kPositionMeasurementArray};
    case F::kSpencerV1: return {kTracks, kSpencerV1};
    case F::kSpencerV2: return {kTracks, kSpencerV2};
    case F::kSpencerV3: return {kTracks, kSpencerV3};
    case F::kBayesV1: return {kTracks, kBayesV1};
    case F::kBayesV2: return {kTracks, kBayesV2};
    case F::kLegTrackerPersonArray: return {kTracks, kLegTracker};
    case F::kDerivedObjectArray: return {kTracks, kDerivedObjectArray};
    case F::kDerivedObjectWithCovarianceArray: return {kTracks, kDerivedObjectWithCovarianceArray};
    case F::kObstacles: return {kDetections, kObstacles};
    case F::kDetection3DArray: return {kDetections, kDetection3DArray};
    case F::kJskBoxArrayV1: return {kDetections, kJskV1};
    case F::kJskBoxArrayV2: return {kDetections, kJskV2};
    case F::kMarkerArray: return {kDetections, kMarkerArray};
    case F::kPoseArray: return {kDetections, kPoseArray};
    case F::kTrackedBoxArrayV1: return {kTracks, kTrackedBoxArrayV1};
    case F::kJskHumanSkeletonArray: return {ForeignFamily::kSkeletons, kJskHumanSkeletonArray};
    case F::kHriIdsList: return {ForeignFamily::kSkeletons, kHriIdsList};
  }
  return {kTracks, {}};
}

// One row of the catalogue: a type name's version, its md5 and its format.
constexpr ForeignVersion known(std::string_view type, std::string_view version,
                               std::string_view md5, ForeignFormat format) {
  const FormatFacts facts = formatFacts(format);
  return {type, version, md5, format, facts.family, facts.layout};
}

// md5s as foreign_msgs/md5s.txt lists them (test_foreign_decoder checks the two agree).
constexpr ForeignVersion kVersions[] = {
    known("people_msgs/People", "v1", "18722f4b8db20cc2369740732357847b", F::kPeople),
    known("people_msgs/PositionMeasurementArray", "v1", "59c860d40aa739ec920eb3ad24ae019e",
          F::kPositionMeasurementArray),
    known("spencer_tracking_msgs/TrackedPersons", "v1", "fff87da612a8c3a29a0c8975fb284991",
          F::kSpencerV1),
    known("spencer_tracking_msgs/TrackedPersons", "v2", "21c0b1a57c4933e68f39aa3802861828",
          F::kSpencerV2),
    known("spencer_tracking_msgs/TrackedPersons", "v3", "a8d3f58bab50e004b03178ad80cb76ac",
          F::kSpencerV3),
    known("pedsim_msgs/TrackedPersons", "v1", "fff87da612a8c3a29a0c8975fb284991", F::kSpencerV1),
    known("pedsim_msgs/TrackedPersons", "v2", "21c0b1a57c4933e68f39aa3802861828", F::kSpencerV2),
    known("bayes_people_tracker/PeopleTracker", "v1", "748ea76bfa4fbc576a15a2b7a15777db",
          F::kBayesV1),
    known("bayes_people_tracker/PeopleTracker", "v2", "e8903e0f53d53a16b295eae14263c817",
          F::kBayesV2),
    known("leg_tracker/PersonArray", "v1", "7b54bf6148ab21083b85a27eec643002",
          F::kLegTrackerPersonArray),
    known("derived_object_msgs/ObjectArray", "v1", "492c83cd255b9a57845d0c197d7977be",
          F::kDerivedObjectArray),
    known("derived_object_msgs/ObjectWithCovarianceArray", "v1", "59dfdf4ed3407a2558ccbc7f5732bf46",
          F::kDerivedObjectWithCovarianceArray),
    known("obstacle_detector/Obstacles", "v1", "043bbf49c7775f8111e850268dbcf2e3", F::kObstacles),
    known("vision_msgs/Detection3DArray", "v1", "05c51d9aea1fb4cfdc8effb94f197b6f",
          F::kDetection3DArray),
    known("jsk_recognition_msgs/BoundingBoxArray", "v1", "19cc943fcedfafbf4787a46810f9356a",
          F::kJskBoxArrayV1),
    known("jsk_recognition_msgs/BoundingBoxArray", "v2", "c8f4a8bb1acd18ce778d183912bb472d",
          F::kJskBoxArrayV2),
    known("visualization_msgs/MarkerArray", "debian", "d155b9ce5188fbaf89745847fd5882d7",
          F::kMarkerArray),
    known("geometry_msgs/PoseArray", "debian", "916c28c5764443f268b296bb671b9d97", F::kPoseArray),
    known("workspace_proximity/TrackedBoxArray", "v1", "d56a591380bdbf88ec37ec86270fc893",
          F::kTrackedBoxArrayV1),
    known("jsk_recognition_msgs/HumanSkeletonArray", "v1", "4013ce44abe9aafa9055e095797a9d50",
          F::kJskHumanSkeletonArray),
    known("hri_msgs/IdsList", "v1", "84a63f55b5676f78b625e8a8bb809fe5", F::kHriIdsList),
};
constexpr std::size_t kVersionCount = sizeof(kVersions) / sizeof(kVersions[0]);

// One field of a definition: its type and name, the type without its package.
struct Field {
  std::string_view type;
  std::string_view name;
};

// The fields of one (nested) type; `name` is the type without its package, "" for the top.
struct Section {
  std::string_view name;
  std::vector<Field> fields;
};

std::string_view trim(std::string_view s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

// "geometry_msgs/Point[3]" -> "Point[3]": packages are left out, since a nested type's name is
// resolved relative to its package and "Header" means "std_msgs/Header".
std::string_view withoutPackage(std::string_view type) {
  const auto slash = type.rfind('/');
  return slash == std::string_view::npos ? type : type.substr(slash + 1);
}

// Sections of a definition in ROS's full-text form (the connection header's message_definition
// or a layout above): comments, blank lines, constants and "====" separators are skipped.
std::vector<Section> parseDefinition(std::string_view text) {
  std::vector<Section> sections(1);
  while (!text.empty()) {
    const auto eol = text.find('\n');
    std::string_view line = text.substr(0, eol);
    text = eol == std::string_view::npos ? std::string_view() : text.substr(eol + 1);
    const auto hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    line = trim(line);
    if (line.empty()) continue;
    if (line.substr(0, 4) == "MSG:") {
      sections.push_back({withoutPackage(trim(line.substr(4))), {}});
      continue;
    }
    if (line.find('=') != std::string_view::npos) continue;  // a constant or a separator
    const auto space = line.find_first_of(" \t");
    if (space == std::string_view::npos) continue;
    sections.back().fields.push_back(
        {withoutPackage(line.substr(0, space)), trim(line.substr(space + 1))});
  }
  return sections;
}

const Section* findSection(const std::vector<Section>& sections, std::string_view name) {
  for (const Section& s : sections) {
    if (s.name == name) return &s;
  }
  return nullptr;
}

const Field* findField(const Section& section, std::string_view name) {
  for (const Field& f : section.fields) {
    if (f.name == name) return &f;
  }
  return nullptr;
}

}  // namespace

const ForeignVersion* foreignVersions(std::size_t* count) {
  *count = kVersionCount;
  return kVersions;
}

const ForeignVersion* findForeignVersion(std::string_view type, std::string_view md5) {
  for (const ForeignVersion& v : kVersions) {
    if (v.type == type && v.md5 == md5) return &v;
  }
  return nullptr;
}

bool isKnownForeignType(std::string_view type) {
  return std::any_of(std::begin(kVersions), std::end(kVersions),
                     [&](const ForeignVersion& v) { return v.type == type; });
}

std::string layoutDifference(std::string_view definition, std::string_view layout, int* count) {
  const std::vector<Section> given = parseDefinition(definition);
  const std::vector<Section> known = parseDefinition(layout);
  std::ostringstream out;
  *count = 0;
  auto note = [&](std::string_view section, const std::string& text) {
    out << (*count == 0 ? "" : "; ") << (section.empty() ? "top level" : section) << ": "
        << text;
    ++*count;
  };
  for (const Section& k : known) {
    const Section* g = findSection(given, k.name);
    if (g == nullptr) {
      note(k.name, "no such nested type in the definition");
      continue;
    }
    for (const Field& f : k.fields) {
      const Field* h = findField(*g, f.name);
      if (h == nullptr) {
        note(k.name, "no field '" + std::string(f.name) + "'");
      } else if (h->type != f.type) {
        note(k.name, "field '" + std::string(f.name) + "' is " + std::string(h->type) +
                         ", not " + std::string(f.type));
      }
    }
    for (const Field& h : g->fields) {
      if (findField(k, h.name) == nullptr) {
        note(k.name, "extra field '" + std::string(h.type) + " " + std::string(h.name) + "'");
      }
    }
    // Same fields in another order are another wire layout.
    bool same_set = g->fields.size() == k.fields.size();
    for (std::size_t i = 0; same_set && i < k.fields.size(); ++i) {
      same_set = findField(*g, k.fields[i].name) != nullptr;
    }
    if (same_set) {
      for (std::size_t i = 0; i < k.fields.size(); ++i) {
        if (g->fields[i].name != k.fields[i].name) {
          note(k.name, "fields in another order");
          break;
        }
      }
    }
  }
  return out.str();
}

std::string describeUnknownMd5(std::string_view type, std::string_view md5,
                               std::string_view definition) {
  std::ostringstream out;
  int versions = 0;
  for (const ForeignVersion& v : kVersions) versions += v.type == type ? 1 : 0;
  out << type << " md5 " << md5 << " is none of the " << versions << " known version"
      << (versions == 1 ? "" : "s") << " (";
  int listed = 0;
  for (const ForeignVersion& v : kVersions) {
    if (v.type != type) continue;
    out << (listed++ == 0 ? "" : ", ") << v.version << " " << v.md5;
  }
  out << ")";
  if (definition.empty()) {
    out << "; no message definition came with it to compare layouts; not read";
    return out.str();
  }
  // The nearest known version: the fewest field differences.
  const ForeignVersion* nearest = nullptr;
  std::string nearest_text;
  int nearest_count = 0;
  for (const ForeignVersion& v : kVersions) {
    if (v.type != type) continue;
    int n = 0;
    std::string text = layoutDifference(definition, v.layout, &n);
    if (nearest == nullptr || n < nearest_count) {
      nearest = &v;
      nearest_text = std::move(text);
      nearest_count = n;
    }
  }
  out << "; nearest: " << nearest->version;
  if (nearest_count == 0) {
    out << " (same fields; the difference is in constants or in nested standard types)";
  } else {
    out << " (differs in " << nearest_text << ")";
  }
  out << "; the layout differs, so it is not read";
  return out.str();
}

std::string describeUnknownType(std::string_view type) {
  std::ostringstream out;
  out << "'" << type << "' is not a supported foreign type (supported:";
  std::string_view previous;
  for (const ForeignVersion& v : kVersions) {
    if (v.type == previous) continue;
    out << " " << v.type;
    previous = v.type;
  }
  out << ")";
  return out.str();
}

}  // namespace workspace_proximity
