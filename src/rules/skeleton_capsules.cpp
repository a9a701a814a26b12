#include "workspace_proximity/rules/skeleton_capsules.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <Eigen/Geometry>

#include "workspace_proximity/rules/track_growth.hpp"

namespace workspace_proximity {
namespace {

// Whether `name` contains `word`, ignoring ASCII case (joint names come in every spelling).
bool contains(std::string_view name, std::string_view word) {
  if (word.size() > name.size()) return false;
  for (std::size_t i = 0; i + word.size() <= name.size(); ++i) {
    bool same = true;
    for (std::size_t j = 0; same && j < word.size(); ++j) {
      char c = name[i + j];
      if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
      same = c == word[j];
    }
    if (same) return true;
  }
  return false;
}

bool any(std::string_view name, std::initializer_list<std::string_view> words) {
  for (std::string_view w : words) {
    if (contains(name, w)) return true;
  }
  return false;
}

// Joint classes by name. A wrist is both a hand and an arm joint: wrist-to-hand bones are
// hands, elbow-to-wrist bones arms.
bool handJoint(std::string_view n) { return any(n, {"wrist", "hand", "thumb", "finger"}); }
bool armJoint(std::string_view n) { return any(n, {"elbow", "wrist"}); }
bool legJoint(std::string_view n) { return any(n, {"knee", "ankle", "foot", "toe", "heel"}); }
bool headJoint(std::string_view n) { return any(n, {"nose", "eye", "ear", "head"}); }
bool torsoJoint(std::string_view n) {
  return any(n, {"neck", "spine", "chest", "pelvis", "hip", "clavicle", "shoulder", "navel", "naval",
                 "torso", "waist"});
}

// FNV-1a over the body id (number or text) and the bone's name: the finite-difference key.
std::uint64_t boneKey(std::uint64_t body, std::string_view body_name, std::string_view name) {
  std::uint64_t h = 1469598103934665603ull;
  for (int i = 0; i < 8; ++i) {
    h ^= (body >> (8 * i)) & 0xff;
    h *= 1099511628211ull;
  }
  for (char c : body_name) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  h ^= '/';
  h *= 1099511628211ull;
  for (char c : name) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

// FNV-1a over the body id alone (number or text): which bodies a message has.
std::uint64_t bodyKey(std::uint64_t body, std::string_view body_name) {
  return boneKey(body, body_name, std::string_view());
}

// Below this the two sightings are one measurement (a republished message): no velocity.
constexpr double kMinDifferenceTime = 1e-3;  // s
// A spread below this is the doubles' rounding, not a limb stretching: coordinates up to
// BoxLimits' 1e5 m differ by 2e-11 m in their last bit, over at least 1 ms 2e-8 m/s. Kept,
// such a spread would send a rigidly moving limb to the growth model's solver for nothing.
constexpr double kSpreadRounding = 1e-7;  // m/s

}  // namespace

std::string_view bodyPartLabel(BodyPart part) {
  switch (part) {
    case BodyPart::kHead: return "person/head";
    case BodyPart::kTorso: return "person/torso";
    case BodyPart::kArm: return "person/arm";
    case BodyPart::kHand: return "person/hand";
    case BodyPart::kLeg: return "person/leg";
    case BodyPart::kCount: break;
  }
  return "person";
}

bool bodyPartOfBone(std::string_view joint_a, std::string_view joint_b, BodyPart* part) {
  const std::string_view j[2] = {joint_a, joint_b};
  if (handJoint(j[0]) && handJoint(j[1])) {
    *part = BodyPart::kHand;
  } else if (armJoint(j[0]) || armJoint(j[1])) {
    *part = BodyPart::kArm;
  } else if (legJoint(j[0]) || legJoint(j[1])) {
    *part = BodyPart::kLeg;
  } else if (headJoint(j[0]) || headJoint(j[1])) {
    *part = BodyPart::kHead;
  } else if (torsoJoint(j[0]) && torsoJoint(j[1])) {
    *part = BodyPart::kTorso;
  } else {
    return false;
  }
  return true;
}

void capsuleBox(const Capsule& capsule, Eigen::Vector3d* centre, Eigen::Vector4d* quaternion,
                Eigen::Vector3d* dimensions) {
  const Eigen::Vector3d d = capsule.b - capsule.a;
  const double length = d.norm();
  *centre = 0.5 * (capsule.a + capsule.b);
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  // A sphere (both joints at one point) needs no axis. Otherwise the shortest rotation taking
  // z to the bone's direction u (the box's turn about u matters: its square cross-section
  // turned is another set), the quaternion (z x u, 1 + u_z) normalised. For u near -z,
  // 1 + u_z cancels: Quaterniond::FromTwoVectors left it 8e-9 off unit length there (a shin
  // hanging down; fuzz_skeletons), so it is computed as (u_x^2 + u_y^2) / (1 - u_z), which is
  // equal for a unit u and exact to rounding. Exactly along -z: a half turn about x. The
  // components are scaled by the largest before the norm: for u within 1e-154 of -z their
  // squares fall among the denormals, whose few bits left the quaternion up to 2e-4 off unit
  // length and the box's axis 1e-3 off the bone (fuzz_skeletons, session 20).
  // (Not Eigen's stableNormalized: it divides by the largest times the norm, a product that
  // rounds among the denormals when the largest is one: 3.8e-8 off unit length.)
  if (length > 1e-12) {
    const Eigen::Vector3d u = d / length;
    const double w = u.z() >= 0.0 ? 1.0 + u.z() : (u.x() * u.x() + u.y() * u.y()) / (1.0 - u.z());
    const Eigen::Vector4d c(-u.y(), u.x(), 0.0, w);  // x, y, z, w
    const double largest = c.cwiseAbs().maxCoeff();
    if (largest > 0.0) {
      const Eigen::Vector4d scaled = c / largest;
      q = Eigen::Quaterniond(scaled / scaled.norm());
    } else {
      q = Eigen::Quaterniond(0.0, 1.0, 0.0, 0.0);
    }
  }
  *quaternion = Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
  const double width = 2.0 * capsule.radius;
  *dimensions = Eigen::Vector3d(width, width, length + width);
}

void capsuleVelocity(const Eigen::Vector3d& velocity_a, const Eigen::Vector3d& velocity_b,
                     Eigen::Vector3d* velocity, double* spread) {
  *velocity = 0.5 * (velocity_a + velocity_b);
  *spread = 0.5 * (velocity_b - velocity_a).norm();
}

SkeletonCapsules::SkeletonCapsules(std::size_t max_bones) : max_bones_(max_bones) {
  // Missing bones ride along with a message's own: at most twice max_bones boxes.
  ids_.reserve(2 * max_bones * 64);
  id_ends_.reserve(2 * max_bones);
  previous_.reserve(2 * max_bones);
  current_.reserve(2 * max_bones);
  sighting_ids_[0].reserve(2 * max_bones * 64);
  sighting_ids_[1].reserve(2 * max_bones * 64);
  present_bodies_.reserve(max_bones);
  present_bones_.reserve(max_bones);
  missing_.reserve(2 * max_bones);
}

void SkeletonCapsules::findMissing(const SkeletonFrame& in, std::size_t n) {
  present_bodies_.clear();
  present_bones_.clear();
  missing_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const SkeletonBone& bone = in.bones[i];
    // A body without a stable id is a different index each message: nothing to carry over.
    if (!bone.body_id_stable) continue;
    present_bodies_.push_back(bodyKey(bone.body, bone.body_name));
    present_bones_.push_back(boneKey(bone.body, bone.body_name, bone.name));
  }
  std::sort(present_bodies_.begin(), present_bodies_.end());
  std::sort(present_bones_.begin(), present_bones_.end());
  for (std::size_t k = 0; k < previous_.size(); ++k) {
    const Sighting& s = previous_[k];
    if (std::binary_search(present_bones_.begin(), present_bones_.end(), s.key)) continue;
    if (!std::binary_search(present_bodies_.begin(), present_bodies_.end(), s.body_key)) continue;
    // Its message must be newer: the same stamp again (a republished message) or an older one
    // carries nothing over, and the capacity bounds what is carried.
    if (s.stamp >= in.stamp || n + missing_.size() >= 2 * max_bones_) continue;
    missing_.push_back(k);
  }
}

const SkeletonCapsules::Sighting* SkeletonCapsules::findPrevious(std::uint64_t key) const {
  auto it = std::lower_bound(previous_.begin(), previous_.end(), key,
                             [](const Sighting& s, std::uint64_t k) { return s.key < k; });
  return it != previous_.end() && it->key == key ? &*it : nullptr;
}

void SkeletonCapsules::convert(const SkeletonFrame& in, const MonitorParams& params,
                               std::vector<BoxObservation>* out) {
  out->clear();
  ids_.clear();
  id_ends_.clear();
  current_.clear();
  const std::size_t n = std::min(in.bones.size(), max_bones_);
  findMissing(in, n);
  const std::string& previous_ids = sighting_ids_[1 - buffer_];
  std::string& current_ids = sighting_ids_[buffer_];
  current_ids.clear();
  // Ids first, views after: ids_ may grow (a long bone name) while it is written.
  for (std::size_t i = 0; i < n; ++i) {
    if (!in.bones[i].body_name.empty()) {
      ids_.append(in.bones[i].body_name);
    } else {
      char digits[24];
      const std::to_chars_result r =
          std::to_chars(digits, digits + sizeof(digits), in.bones[i].body);
      ids_.append(digits, r.ptr);
    }
    ids_.push_back('/');
    ids_.append(in.bones[i].name);
    id_ends_.push_back(ids_.size());
  }
  for (std::size_t k : missing_) {
    const Sighting& s = previous_[k];
    ids_.append(previous_ids, s.id_begin, s.id_size);
    id_ends_.push_back(ids_.size());
  }
  // A bone named twice in one message (a body's joints in two runs of a MarkerArray, a
  // skeleton id or bone name repeated): which sighting is which is unknown, so neither gets a
  // velocity from a difference, now or next time (fuzz_skeletons found one differenced against
  // the other's joints: a velocity off by more than its error). present_bones_ holds the
  // message's stable bone keys, sorted (findMissing).
  const auto twice = [&](std::uint64_t key) {
    const auto range = std::equal_range(present_bones_.begin(), present_bones_.end(), key);
    return range.second - range.first > 1;
  };
  // Box i of *out: its id (the i-th in ids_), its part's label and its capsule's box, at rest.
  const auto addBox = [&](std::size_t i, BodyPart part, const Eigen::Vector3d& a,
                          const Eigen::Vector3d& b_joint) -> const LabelSettings& {
    BoxObservation& b = out->emplace_back();
    const std::size_t begin = i == 0 ? 0 : id_ends_[i - 1];
    b.id = std::string_view(ids_.data() + begin, id_ends_[i] - begin);
    b.label = bodyPartLabel(part);
    const LabelSettings& label = params.label(std::string(b.label));
    capsuleBox(Capsule{a, b_joint, 0.5 * label.size_x}, &b.position, &b.quaternion, &b.dimensions);
    b.angular_velocity.setZero();
    b.linear_velocity.setZero();
    b.velocity_known = false;
    return label;
  };
  for (std::size_t i = 0; i < n; ++i) {
    const SkeletonBone& bone = in.bones[i];
    const LabelSettings& label = addBox(i, bone.part, bone.a, bone.b);
    BoxObservation& b = out->back();

    const std::uint64_t key = boneKey(bone.body, bone.body_name, bone.name);
    const Sighting* last = bone.body_id_stable && !twice(key) ? findPrevious(key) : nullptr;
    if (bone.body_id_stable) {
      const auto id_begin = static_cast<std::uint32_t>(current_ids.size());
      current_ids.append(b.id);
      current_.push_back({key, bodyKey(bone.body, bone.body_name), bone.a, bone.b, in.stamp,
                          bone.part, id_begin, static_cast<std::uint32_t>(b.id.size())});
    }
    const double dt = last ? secondsBetween(last->stamp, in.stamp) : 0.0;
    if (last == nullptr || dt < kMinDifferenceTime || dt > params.track_timeout) continue;
    Eigen::Vector3d velocity;
    double spread = 0.0;
    capsuleVelocity((bone.a - last->a) / dt, (bone.b - last->b) / dt, &velocity, &spread);
    // A limb stretching faster than a person of its label can move says nothing: unknown.
    if (spread > unknownVelocitySpeed(label)) continue;
    b.linear_velocity = velocity;
    b.velocity_error = spread < kSpreadRounding ? 0.0 : spread;
    b.velocity_known = true;
  }
  // The missing bones of bodies still here: their last box, anywhere they could have got to.
  for (std::size_t m = 0; m < missing_.size(); ++m) {
    const Sighting& s = previous_[missing_[m]];
    const LabelSettings& label = addBox(n + m, s.part, s.a, s.b);
    BoxObservation& b = out->back();
    b.position_error =
        label.position_error + unknownVelocitySpeed(label) * secondsBetween(s.stamp, in.stamp);
    const auto id_begin = static_cast<std::uint32_t>(current_ids.size());
    current_ids.append(b.id);
    Sighting carried = s;  // its last sighting stays the last: the growth goes on from there
    carried.id_begin = id_begin;
    current_.push_back(carried);
  }
  std::sort(current_.begin(), current_.end(),
            [](const Sighting& a, const Sighting& b) { return a.key < b.key; });
  // Only the bones seen once are remembered.
  std::size_t kept = 0;
  for (std::size_t i = 0; i < current_.size();) {
    std::size_t j = i + 1;
    while (j < current_.size() && current_[j].key == current_[i].key) ++j;
    if (j == i + 1) current_[kept++] = current_[i];
    i = j;
  }
  current_.resize(kept);
  previous_.swap(current_);
  buffer_ = 1 - buffer_;
}

}  // namespace workspace_proximity
