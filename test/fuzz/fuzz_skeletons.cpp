// libFuzzer harness over the skeleton read path (issue 24 item 4), ROS-free: arbitrary bytes as
// one serialized skeleton message through its decoder (foreign_skeletons.hpp), then the bones
// through SkeletonCapsules (skeleton_capsules.hpp) twice, 0.1 s apart with every joint moved,
// so the finite-difference velocities run as well.
//
// Input: byte 0 picks the decoder: 0 jsk_recognition_msgs/HumanSkeletonArray, 1 the Azure
// Kinect driver's visualization_msgs/MarkerArray, 2 hri_msgs/IdsList (each with its catalogue
// md5), 3 and 4 HumanSkeletonArray and IdsList with an unknown md5 and the rest of the input as
// the publisher's definition; the rest is the message.
//
// Checks: a refusal has a named reason and an explanation and leaves no bones (ids); a read
// message has at most its capacity of bones (ids), finite joints and names (ids, frame) that
// view the input; the same bytes with one byte more are refused as overlong, with one byte less
// as truncated or of a bad length; an unknown md5 is refused as such. Every box the capsules
// give has a part label and the id "<body>/<bone>"; one whose joints are within a range where
// no sum overflows (|x| <= 1e150) is finite, has a unit quaternion, the documented extents and
// contains both joints grown by the radius in every direction (the capsule); with a known
// velocity, each joint's move between the passes is within velocity dt + velocity_error dt.
// Whatever the monitor's checkBox() refuses it refuses with an explanation.

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Geometry>

#include "fuzz_input.hpp"
#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/foreign_skeletons.hpp"
#include "workspace_proximity/rules/foreign_types.hpp"
#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/rules/skeleton_capsules.hpp"

namespace wp = workspace_proximity;
using wp::ForeignRefusal;

namespace {

constexpr std::size_t kMaxBones = 64;
constexpr std::size_t kMaxIds = 16;
constexpr wp::Stamp kLater = 100000000;  // ns: the second pass, 0.1 s after the message
constexpr double kDt = 0.1;              // s
// Joints beyond this may overflow a difference or a sum (the box is then refused downstream).
constexpr double kSafeCoordinate = 1e150;
constexpr std::string_view kUnknownMd5 = "00000000000000000000000000000000";
// WP_FUZZ_TRACE=1: one line per decode and per capsule pass (to see what a seed reaches).
const bool kTrace = std::getenv("WP_FUZZ_TRACE") != nullptr;

enum Pick { kJsk, kK4abt, kHri, kJskUnknown, kHriUnknown, kPickCount };

bool inside(std::string_view s, const std::uint8_t* data, std::size_t size) {
  if (s.empty()) return true;
  const auto* p = reinterpret_cast<const std::uint8_t*>(s.data());
  return p >= data && p + s.size() <= data + size;
}

std::string_view md5Of(std::string_view type) {
  std::size_t count = 0;
  const wp::ForeignVersion* versions = wp::foreignVersions(&count);
  for (std::size_t i = 0; i < count; ++i) {
    if (versions[i].type == type) return versions[i].md5;
  }
  wp_fuzz::fail("catalogue has no entry", std::string(type));
}

void checkRefusal(ForeignRefusal r, const wp::SkeletonDecode& d, std::size_t left) {
  WP_FUZZ_CHECK(r == d.refusal, wp::foreignRefusalName(r));
  const std::string name = wp::foreignRefusalName(r);
  if (r == ForeignRefusal::kNone) {
    WP_FUZZ_CHECK(d.detail.empty(), d.detail);
    return;
  }
  WP_FUZZ_CHECK(name != "unknown_refusal" && name != "none", name);
  WP_FUZZ_CHECK(!d.detail.empty(), name);
  WP_FUZZ_CHECK(left == 0, name + ": " + std::to_string(left) + " left after the refusal");
}

void checkFrame(const wp::SkeletonFrame& f, ForeignRefusal r, const wp::SkeletonDecode& d,
                const std::uint8_t* data, std::size_t size) {
  checkRefusal(r, d, f.bones.size());
  if (r != ForeignRefusal::kNone) return;
  WP_FUZZ_CHECK(f.bones.size() <= f.max_bones, std::to_string(f.bones.size()));
  WP_FUZZ_CHECK(inside(f.frame_id, data, size), "frame_id");
  for (std::size_t i = 0; i < f.bones.size(); ++i) {
    const wp::SkeletonBone& b = f.bones[i];
    const std::string at = "bone " + std::to_string(i);
    WP_FUZZ_CHECK(b.a.allFinite() && b.b.allFinite(), at);
    WP_FUZZ_CHECK(!b.name.empty() && b.part < wp::BodyPart::kCount, at);
    // jsk's names view the message; K4ABT's are the decoder's own constants.
    WP_FUZZ_CHECK(b.name.find("->") != std::string_view::npos, at + " name");
  }
}

void checkIds(const wp::HriIds& ids, ForeignRefusal r, const wp::SkeletonDecode& d,
              const std::uint8_t* data, std::size_t size) {
  checkRefusal(r, d, ids.ids.size());
  if (r != ForeignRefusal::kNone) return;
  WP_FUZZ_CHECK(ids.ids.size() <= ids.max_ids, std::to_string(ids.ids.size()));
  WP_FUZZ_CHECK(inside(ids.frame_id, data, size), "frame_id");
  for (std::string_view id : ids.ids) {
    WP_FUZZ_CHECK(!id.empty() && inside(id, data, size), std::string(id));
    WP_FUZZ_CHECK(id.find_first_of("/ \t\n") == std::string_view::npos, std::string(id));
  }
}

// Decodes `n` bytes at `msg` with the picked decoder; `bones` or `ids` gets the result.
ForeignRefusal decode(int pick, const std::uint8_t* msg, std::size_t n, wp::SkeletonFrame* bones,
                      wp::HriIds* ids, wp::SkeletonDecode* d) {
  static const std::string_view jsk = md5Of("jsk_recognition_msgs/HumanSkeletonArray");
  static const std::string_view markers = md5Of("visualization_msgs/MarkerArray");
  static const std::string_view hri = md5Of("hri_msgs/IdsList");
  const std::string_view rest(reinterpret_cast<const char*>(msg), n);
  switch (pick) {
    case kJsk: return wp::decodeJskSkeletons(jsk, msg, n, bones, d);
    case kK4abt: return wp::decodeK4abtMarkers(markers, msg, n, bones, d);
    case kHri: return wp::decodeHriIds(hri, msg, n, ids, d);
    case kJskUnknown: return wp::decodeJskSkeletons(kUnknownMd5, msg, n, bones, d, rest);
    default: return wp::decodeHriIds(kUnknownMd5, msg, n, ids, d, rest);
  }
}

void check(int pick, const std::uint8_t* msg, std::size_t n, ForeignRefusal r,
           const wp::SkeletonFrame& bones, const wp::HriIds& ids, const wp::SkeletonDecode& d) {
  if (pick == kHri || pick == kHriUnknown) {
    checkIds(ids, r, d, msg, n);
  } else {
    checkFrame(bones, r, d, msg, n);
  }
}

bool safe(const wp::SkeletonBone& bone) {
  return bone.a.cwiseAbs().maxCoeff() <= kSafeCoordinate &&
         bone.b.cwiseAbs().maxCoeff() <= kSafeCoordinate;
}

// Whether the box holds the sphere of `radius` about `p` (relative tolerance for rounding).
bool holds(const wp::BoxObservation& box, const Eigen::Vector3d& p, double radius) {
  const Eigen::Quaterniond q(box.quaternion[3], box.quaternion[0], box.quaternion[1],
                             box.quaternion[2]);
  const Eigen::Vector3d local = q.conjugate() * (p - box.position);
  const double scale = 1.0 + p.cwiseAbs().maxCoeff() + box.position.cwiseAbs().maxCoeff() +
                       box.dimensions.maxCoeff();
  const double tolerance = 1e-9 * scale;
  return (local.cwiseAbs().array() + radius <= 0.5 * box.dimensions.array() + tolerance).all();
}

void checkBoxes(const wp::SkeletonFrame& frame, const std::vector<wp::BoxObservation>& boxes,
                const wp::MonitorParams& params, const wp::SkeletonFrame* before) {
  WP_FUZZ_CHECK(boxes.size() == frame.bones.size(), std::to_string(boxes.size()));
  if (kTrace) {
    int known = 0;
    for (const wp::BoxObservation& b : boxes) known += b.velocity_known ? 1 : 0;
    std::fprintf(stderr, "capsules: %zu boxes, %d with a known velocity\n", boxes.size(), known);
  }
  const wp::BoxLimits limits;
  std::string detail;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const wp::BoxObservation& box = boxes[i];
    const wp::SkeletonBone& bone = frame.bones[i];
    const std::string at = "box " + std::to_string(i) + " " + std::string(box.id);
    WP_FUZZ_CHECK(box.label == wp::bodyPartLabel(bone.part), at);
    const std::string suffix = "/" + std::string(bone.name);
    WP_FUZZ_CHECK(box.id.size() > suffix.size() &&
                      box.id.substr(box.id.size() - suffix.size()) == suffix,
                  at);
    detail.clear();
    const wp::Drop drop = wp::checkBox(box, limits, &detail);
    WP_FUZZ_CHECK(drop == wp::Drop::kCount || !detail.empty(), at + " " + wp::dropName(drop));
    if (!safe(bone)) continue;

    const double radius = 0.5 * params.label(std::string(box.label)).size_x;
    WP_FUZZ_CHECK(box.position.allFinite() && box.quaternion.allFinite() &&
                      box.dimensions.allFinite() && box.linear_velocity.allFinite() &&
                      box.angular_velocity.allFinite() && std::isfinite(box.velocity_error) &&
                      box.velocity_error >= 0.0,
                  at + " not finite");
    WP_FUZZ_CHECK(std::abs(box.quaternion.norm() - 1.0) < 1e-9,
                  at + " quaternion " + wp_fuzz::str(box.quaternion.norm()) + " a " +
                      wp_fuzz::str(bone.a.x()) + " " + wp_fuzz::str(bone.a.y()) + " " +
                      wp_fuzz::str(bone.a.z()) + " b " + wp_fuzz::str(bone.b.x()) + " " +
                      wp_fuzz::str(bone.b.y()) + " " + wp_fuzz::str(bone.b.z()));
    const double length = (bone.b - bone.a).norm();
    const double scale = 1.0 + bone.a.cwiseAbs().maxCoeff() + bone.b.cwiseAbs().maxCoeff();
    WP_FUZZ_CHECK(std::abs(box.dimensions.x() - 2 * radius) <= 1e-12 * scale &&
                      std::abs(box.dimensions.y() - 2 * radius) <= 1e-12 * scale &&
                      std::abs(box.dimensions.z() - (length + 2 * radius)) <= 1e-9 * scale,
                  at + " extents " + wp_fuzz::str(box.dimensions.z()));
    WP_FUZZ_CHECK(holds(box, bone.a, radius) && holds(box, bone.b, radius),
                  at + " does not hold its capsule");

    if (before == nullptr || !box.velocity_known) continue;
    // The motion model covers the joints: each moved by at most (velocity + error) dt from
    // where velocity alone takes it.
    const wp::SkeletonBone& old = before->bones[i];
    const double slack = 1e-9 * (1.0 + scale) / kDt + 1e-7;
    for (const auto& [now, then] : {std::pair(bone.a, old.a), std::pair(bone.b, old.b)}) {
      const double off = ((now - then) / kDt - box.linear_velocity).norm();
      WP_FUZZ_CHECK(off <= box.velocity_error + slack,
                    at + " joint moved off its velocity by " + wp_fuzz::str(off) + " m/s");
    }
  }
}

// The bones through the capsules twice: as read, then 0.1 s later with each joint moved by an
// amount of its own (limbs stretch: the two ends of a bone move differently).
void runCapsules(const wp::SkeletonFrame& frame) {
  static const wp::MonitorParams params;
  wp::SkeletonCapsules capsules(kMaxBones);
  std::vector<wp::BoxObservation> boxes;
  boxes.reserve(kMaxBones);
  capsules.convert(frame, params, &boxes);
  checkBoxes(frame, boxes, params, nullptr);

  wp::SkeletonFrame later = frame;
  later.stamp += kLater;
  for (std::size_t i = 0; i < later.bones.size(); ++i) {
    const double k = static_cast<double>(i % 7) - 3.0;
    later.bones[i].a += Eigen::Vector3d(0.01 * k, 0.02, -0.005 * k);
    later.bones[i].b += Eigen::Vector3d(-0.015, 0.01 * k, 0.03);
  }
  capsules.convert(later, params, &boxes);
  checkBoxes(later, boxes, params, &frame);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const int pick = data[0] % kPickCount;
  const std::uint8_t* msg = data + 1;
  const std::size_t n = size - 1;

  wp::SkeletonFrame bones(kMaxBones);
  wp::HriIds ids(kMaxIds);
  wp::SkeletonDecode d;
  const ForeignRefusal r = decode(pick, msg, n, &bones, &ids, &d);
  if (kTrace) {
    std::fprintf(stderr, "decoder %d: %s %s, %zu bones, %zu ids, %zu unread\n", pick,
                 wp::foreignRefusalName(r), d.detail.c_str(), bones.bones.size(), ids.ids.size(),
                 d.unread);
  }
  check(pick, msg, n, r, bones, ids, d);
  if (pick == kJskUnknown || pick == kHriUnknown) {
    WP_FUZZ_CHECK(r == ForeignRefusal::kUnknownMd5, wp::foreignRefusalName(r));
    return 0;
  }
  if (r != ForeignRefusal::kNone) return 0;

  // Documented: bytes after the last field are refused; a message cut short never reads.
  std::vector<std::uint8_t> copy(msg, msg + n);
  copy.push_back(0);
  {
    wp::SkeletonFrame other(kMaxBones);
    wp::HriIds other_ids(kMaxIds);
    wp::SkeletonDecode od;
    const ForeignRefusal longer = decode(pick, copy.data(), copy.size(), &other, &other_ids, &od);
    check(pick, copy.data(), copy.size(), longer, other, other_ids, od);
    WP_FUZZ_CHECK(longer == ForeignRefusal::kOverlong, wp::foreignRefusalName(longer));
    if (n > 0) {
      const ForeignRefusal shorter = decode(pick, copy.data(), n - 1, &other, &other_ids, &od);
      check(pick, copy.data(), n - 1, shorter, other, other_ids, od);
      WP_FUZZ_CHECK(shorter == ForeignRefusal::kTruncated || shorter == ForeignRefusal::kBadLength,
                    wp::foreignRefusalName(shorter));
    }
  }
  if (pick != kHri) runCapsules(bones);
  return 0;
}
