#pragma once
/// Tracker arrays into the monitor: stamps, tf lookups into the fixed frame, and the one path
/// every array takes. Needs no master (tf comes from any tf2::BufferCore), so the node and the
/// offline replay share it.
///
/// Each source keeps at most one waiting array. The first array after a cycle is used as soon
/// as it arrives (so the cycle only extrapolates, predicts and publishes); later ones before
/// the next cycle replace the waiting one (counted as superseded) and the cycle uses the
/// newest. An array whose transform tf does not have yet at its stamp waits for the cycle,
/// which then falls back to the newest transform.
///
/// Foreign tracker types (foreign_types.hpp: people_msgs, spencer, leg_tracker, ...) arrive as
/// their serialized bytes with type, md5 and the publisher's definition: they are decoded on
/// arrival (a type or version it cannot read is refused by name, and the source is DEGRADED
/// while it sends it), turned into boxes (ForeignObservations) and take the same path. Types
/// of detections without ids (vision_msgs, jsk, MarkerArray, PoseArray) go through a
/// multi-object tracker per source (ForeignDetections, label `unknown`) in the fixed frame.
/// Skeletons (jsk HumanSkeletonArray; MarkerArray on a ~skeleton_marker_topics topic) become
/// one box per bone around its limb capsule (SkeletonCapsules, labels person/<part>). REP-155
/// bodies: the ids of an hri_msgs/IdsList, each body's link frames looked up in tf at the
/// message's stamp (a link tf does not have at that stamp leaves its bones out).

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <tf2/buffer_core.h>
#include <workspace_proximity/TrackedBoxArray.h>

#include "workspace_proximity/rules/foreign_detections.hpp"
#include "workspace_proximity/rules/foreign_skeletons.hpp"
#include "workspace_proximity/rules/foreign_observations.hpp"
#include "workspace_proximity/rules/foreign_tracks.hpp"
#include "workspace_proximity/rules/monitor.hpp"

namespace workspace_proximity {

class InputBridge {
 public:
  /// `monitor` and `tf` are borrowed. `fixed_frame`: the frame of the prediction.
  InputBridge(Monitor* monitor, tf2::BufferCore* tf, const std::string& fixed_frame);

  /// An array of source `source` arrived at `now` (the subscription callback). True when it
  /// was taken on arrival (used, or dropped with a reason), false when it waits for the cycle.
  bool onArray(int source, const TrackedBoxArray::ConstPtr& msg, Stamp now);
  /// A foreign message of source `source`: first foreignBytes(source, size) to hold its
  /// serialized form (filled by the caller), then onForeign with its type, md5 and the
  /// publisher's full definition (may be empty; it names the layout difference of an unknown
  /// md5). Returns as onArray.
  std::uint8_t* foreignBytes(int source, std::size_t size);
  bool onForeign(int source, std::string_view type, std::string_view md5,
                 std::string_view definition, Stamp now);
  /// The frame of source `source`'s last decoded foreign message (its header's, or its first
  /// element's): valid until its next message; empty when none was decoded.
  std::string_view foreignFrame(int source) const;
  /// A message whose type cannot be read at all (an old TrackedBoxArray): refused by name.
  void refuseType(int source, const std::string& why) { monitor_->refuseType(source, why); }
  /// At the cycle: every waiting array is used (the newest per source).
  void takePending(Stamp now);
  /// Forgets waiting arrays (after the clock went back).
  void reset();

  /// Arrays whose frame tf could not reach at all.
  std::uint64_t tfFailures() const { return tf_failures_; }

 private:
  struct Waiting {
    TrackedBoxArray::ConstPtr msg;
    bool foreign = false;            // a decoded foreign message waits (Foreign::decoded)
    bool taken_since_cycle = false;  // an array was used on arrival since the last cycle
  };
  // A source's foreign messages: made at its first one. Sized by ~max_tracks up front.
  struct Foreign {
    explicit Foreign(std::size_t max_tracks) : decoded(max_tracks), observations(max_tracks) {}
    std::vector<std::uint8_t> bytes;  // the message waiting (decoded views it)
    std::string frame;                // its frame (reused)
    // Detection types (no ids): the multi-object tracker, in the fixed frame, made at the
    // source's first detections message.
    std::unique_ptr<ForeignDetections> detections;
    bool waiting_detections = false;  // the waiting message is of the detections family
    ForeignTrackArray decoded;
    ForeignObservations observations;
    // Skeletons: the waiting message's bones (views into bytes) and their capsules, made at
    // the source's first skeleton message.
    std::unique_ptr<SkeletonFrame> skeleton;
    std::unique_ptr<SkeletonCapsules> capsules;
    bool waiting_skeleton = false;  // the waiting message is a skeleton
    std::unique_ptr<HriIds> hri;    // REP-155: the waiting message's body ids
    bool rep155 = false;            // the waiting skeleton is REP-155 (bones from tf)
    std::string link_frame;         // "<link>_<id>" (reused)
  };
  // REP-155: the bones of the waiting ids' bodies from tf at `stamp`, in the fixed frame, into
  // the source's skeleton. false (and *wait) when a link is not in tf yet on arrival.
  bool rep155Bones(int source, Stamp stamp, bool at_cycle, bool* wait);
  // Decodes the waiting skeleton message of `source`; false when refused (handled).
  bool decodeSkeleton(int source, std::string_view type, std::string_view md5,
                      std::string_view definition, bool k4abt_markers);
  bool waits(const Waiting& w) const { return w.msg || w.foreign; }
  bool arrive(int source, Stamp now);  // the common arrival of a TrackedBoxArray or foreign
  bool useForeign(int source, Stamp now, bool at_cycle);
  class ForeignPlacement;
  // The one path of an array. `at_cycle`: tf's newest transform is acceptable when it has none
  // at the stamp; otherwise the array keeps waiting. Returns false when it keeps waiting.
  bool take(int source, Stamp now, bool at_cycle);
  bool use(int source, const TrackedBoxArray& msg, Stamp now, bool at_cycle);
  class Placement;  // the array's frame from tf and its boxes, for Monitor::ingest
  // Pose of `frame` in the fixed frame at `stamp`; false when it is not known (yet).
  bool lookup(int source, const std::string& frame, Stamp stamp, bool at_cycle,
              Eigen::Isometry3d* fixed_from_frame, bool* wait);

  Monitor* monitor_;
  tf2::BufferCore* tf_;
  std::string fixed_frame_;
  std::vector<Waiting> waiting_;
  std::vector<BoxObservation> boxes_;  // reused by every array
  std::vector<std::unique_ptr<Foreign>> foreign_;  // per source; null until a foreign message
  std::uint64_t tf_failures_ = 0;
};

}  // namespace workspace_proximity
