#include "workspace_proximity/rules/foreign_observations.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "workspace_proximity/rules/track_growth.hpp"

namespace workspace_proximity {
namespace {

// FNV-1a over the id's kind and text: the finite-difference table's key. Two ids of one
// tracker colliding in 64 bits is not a practical concern (and would only pair two sightings).
std::uint64_t idKey(ForeignIdKind kind, std::string_view text) {
  std::uint64_t h = 1469598103934665603ull ^ static_cast<std::uint64_t>(kind);
  for (char c : text) {
    h ^= static_cast<unsigned char>(c);
    h *= 1099511628211ull;
  }
  return h;
}

// Below this the two sightings are one measurement (a republished message): no velocity.
constexpr double kMinDifferenceTime = 1e-3;  // s

}  // namespace

double threeSigma(const Eigen::Matrix3d& covariance, std::uint8_t axes) {
  if (axes == kAxesNone) return 0.0;
  Eigen::Matrix3d known = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if ((axes >> i & 1) && (axes >> j & 1)) known(i, j) = covariance(i, j);
    }
  }
  // Symmetrised: trackers write the matrix row by row and round each entry on its own.
  const Eigen::Matrix3d symmetric = 0.5 * (known + known.transpose());
  const double largest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(
                             symmetric, Eigen::EigenvaluesOnly)
                             .eigenvalues()
                             .maxCoeff();
  return 3.0 * std::sqrt(std::max(0.0, largest));
}

std::string_view foreignLabel(std::string_view label) {
  if (label.empty()) return "default";
  if (label == "pedestrian") return "person";
  return label;
}

ForeignObservations::ForeignObservations(std::size_t max_tracks)
    : max_tracks_(max_tracks), id_text_(max_tracks * kIdChars) {
  previous_.reserve(max_tracks);
  current_.reserve(max_tracks);
}

const ForeignObservations::Sighting* ForeignObservations::findPrevious(std::uint64_t key) const {
  auto it = std::lower_bound(previous_.begin(), previous_.end(), key,
                             [](const Sighting& s, std::uint64_t k) { return s.key < k; });
  return it != previous_.end() && it->key == key ? &*it : nullptr;
}

void ForeignObservations::differenceVelocity(const ForeignTrack& t, std::uint64_t key,
                                             bool no_id, const LabelSettings& label,
                                             double track_timeout, BoxObservation* b) const {
  // No velocity in the message: the difference of the last two sightings of this id.
  const Sighting* last = no_id ? nullptr : findPrevious(key);
  const double dt = last ? secondsBetween(last->stamp, t.stamp) : 0.0;
  // Two position errors over dt bound the difference's error (3 sigma each, added); a
  // difference less certain than the label's unknown-velocity speed says nothing more.
  const double error = dt > 0.0 ? 2.0 * b->position_error / dt : 0.0;
  if (last != nullptr && dt >= kMinDifferenceTime && dt <= track_timeout &&
      error <= unknownVelocitySpeed(label)) {
    b->linear_velocity = (t.position - last->position) / dt;
    b->velocity_known = true;
    b->velocity_error = error;
  } else {
    b->linear_velocity.setZero();
    b->velocity_known = false;
  }
}

void ForeignObservations::convert(const ForeignTrackArray& in, std::string_view frame,
                                  const MonitorParams& params, std::vector<BoxObservation>* out) {
  out->clear();
  current_.clear();
  skipped_frame_ = 0;
  skipped_position_ = 0;
  const std::size_t n = std::min(in.tracks.size(), max_tracks_);
  // The stamp the input bridge takes the message at: its header's, else its first element's.
  const Stamp base = in.stamp != 0 || in.tracks.empty() ? in.stamp : in.tracks.front().stamp;
  for (std::size_t i = 0; i < n; ++i) {
    const ForeignTrack& t = in.tracks[i];
    // One array, one transform: a track in another frame is not guessed into this one.
    if (t.frame_id != frame) {
      ++skipped_frame_;
      continue;
    }
    if ((t.position_axes & kAxesXY) != kAxesXY) {
      ++skipped_position_;
      continue;
    }
    BoxObservation& b = out->emplace_back();
    switch (t.id_kind) {
      case ForeignIdKind::kText:
        b.id = t.id_text;
        break;
      case ForeignIdKind::kNumber: {
        char* text = id_text_.data() + i * kIdChars;
        const std::to_chars_result r = std::to_chars(text, text + kIdChars, t.id_number);
        b.id = std::string_view(text, static_cast<std::size_t>(r.ptr - text));
        break;
      }
      case ForeignIdKind::kNone:
        b.id = {};  // refused by checkBox as an empty id: detections go through a tracker
        break;
    }
    // This package's own old layout names the monitor's labels already: taken as they are.
    const bool own = in.version != nullptr && in.version->format == ForeignFormat::kTrackedBoxArrayV1;
    b.label = own ? t.label : foreignLabel(t.label);
    const LabelSettings& label = params.label(std::string(b.label));
    b.position = t.position;
    if (t.has_orientation) b.quaternion = t.quaternion;
    const Eigen::Vector3d label_size(label.size_x, label.size_y, label.size_z);
    for (int a = 0; a < 3; ++a) {
      b.dimensions[a] = (t.dimension_axes >> a & 1) ? t.dimensions[a] : label_size[a];
    }
    // A floor tracker's height is not a measurement: the box stands on the frame's z = 0.
    if ((t.position_axes & 0b100) == 0) b.position.z() = 0.5 * b.dimensions.z();
    b.angular_velocity = t.angular_velocity;  // 0 but for this package's v1 TrackedBoxArray
    if (t.has_position_covariance) b.position_error = threeSigma(t.position_covariance, t.position_axes);

    const std::uint64_t key = idKey(t.id_kind, b.id);
    if (!b.id.empty()) current_.push_back({key, t.position, t.stamp});
    if (t.velocity_axes != kAxesNone) {
      // Axes the message leaves unset read 0: people trackers give x and y on a floor.
      b.linear_velocity = t.velocity;
      b.velocity_known = true;
      if (t.has_velocity_covariance) {
        b.velocity_error = threeSigma(t.velocity_covariance, t.velocity_axes);
      }
    } else {
      differenceVelocity(t, key, b.id.empty(), label, params.track_timeout, &b);
    }
    // An element stamped apart from the message (people_msgs' PositionMeasurement and
    // derived_object_msgs' objects have headers of their own) is taken at the message's stamp,
    // as every box of it is: carried there with its velocity, its position error grown by its
    // label's bound over that time, older or newer (never a guess narrower than the bound).
    const double lag = base != 0 && t.stamp != 0 ? secondsBetween(t.stamp, base) : 0.0;
    if (lag != 0.0) {
      b.position += b.linear_velocity * lag;
      const TrackErrors own{b.position_error, b.velocity_error, b.velocity_known};
      // R(|lag|) from the measurement on (at(), not the age, which trackGrowth clips).
      const double grown = trackGrowth(label, b.linear_velocity.norm(), 0.0, own).at(std::abs(lag));
      b.position_error = std::max(label.position_error, b.position_error) + grown;
    }
  }
  std::sort(current_.begin(), current_.end(),
            [](const Sighting& a, const Sighting& b) { return a.key < b.key; });
  previous_.swap(current_);
}

}  // namespace workspace_proximity
