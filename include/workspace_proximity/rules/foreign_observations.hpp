#pragma once
/// Foreign people tracks (foreign_tracks.hpp) as the monitor's box observations, ROS-free:
/// numeric ids written as text, point-like tracks sized by their label, covariances as 3 sigma
/// position and velocity errors, and a velocity by finite differences over the id for a track
/// whose message has none (velocity_known = false until two sightings give one). One converter
/// per input source; its capacities are set up front, so converting allocates nothing.

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "workspace_proximity/rules/box_observation.hpp"
#include "workspace_proximity/rules/foreign_tracks.hpp"
#include "workspace_proximity/rules/monitor_params.hpp"
#include "workspace_proximity/rules/stamp.hpp"

namespace workspace_proximity {

/// 3 sigma bound of a covariance restricted to the axes in `axes` (bit i: axis i): three times
/// the square root of its largest eigenvalue (the longest axis of the 3 sigma ellipsoid), in
/// the covariance's unit's square root. 0 when no axis is known.
double threeSigma(const Eigen::Matrix3d& covariance, std::uint8_t axes);

/// The monitor's label for a foreign track's class: derived_object_msgs' "pedestrian" is a
/// "person"; an empty class is "default"; every other name as the tracker gives it.
std::string_view foreignLabel(std::string_view label);

class ForeignObservations {
 public:
  /// At most `max_tracks` tracks per message (a ForeignTrackArray refuses more).
  explicit ForeignObservations(std::size_t max_tracks);

  /// `in`'s tracks given in `frame` (others are skipped, counted in skippedFrame()) as
  /// observations in `*out` (resized; its ids and labels view `in`'s bytes and this object,
  /// valid until the next call). Sizes from `params`' label size where the message gives
  /// none; a track with no velocity gets the finite difference of its position since its last
  /// sighting (within `params.track_timeout`), with the error 2 position_error / dt, else (and
  /// when that error exceeds the label's unknownVelocitySpeed) velocity_known = false. A track
  /// stamped apart from the message (its own header) is carried to the message's stamp (its
  /// header's, else its first track's) with its velocity, and its position_error becomes
  /// max(label's, own) + the label's growth bound over that time (trackGrowth).
  void convert(const ForeignTrackArray& in, std::string_view frame, const MonitorParams& params,
               std::vector<BoxObservation>* out);
  /// Tracks of the last message skipped because their frame was not the array's.
  std::size_t skippedFrame() const { return skipped_frame_; }
  /// Tracks of the last message skipped because their x or y is not valid (spencer: variance
  /// above 99999): where they are is unknown, so they are dropped, never guessed. A track
  /// whose z alone is not valid stands on z = 0 of its frame (its box's centre at size_z / 2).
  std::size_t skippedPosition() const { return skipped_position_; }
  /// Forgets every sighting (after the clock went back).
  void reset() { previous_.clear(); }

  /// Bytes of one number id written as text (a uint64 has at most 20 digits).
  static constexpr std::size_t kIdChars = 24;

 private:
  struct Sighting {
    std::uint64_t key;         // hash of the id
    Eigen::Vector3d position;  // m, in the message's frame
    Stamp stamp;               // ns
  };
  const Sighting* findPrevious(std::uint64_t key) const;
  // The finite-difference velocity of `t` (key: its id's) into `b`, or velocity_known false.
  void differenceVelocity(const ForeignTrack& t, std::uint64_t key, bool no_id,
                          const LabelSettings& label, double track_timeout,
                          BoxObservation* b) const;

  std::size_t max_tracks_;
  std::vector<char> id_text_;         // kIdChars per track: number ids as text
  std::vector<Sighting> previous_;    // sorted by key: the last message's tracks
  std::vector<Sighting> current_;     // this message's, becomes previous_
  std::size_t skipped_frame_ = 0;
  std::size_t skipped_position_ = 0;
};

}  // namespace workspace_proximity
