#pragma once
/// The whole prediction pipeline: bodies in, contact events out. ROS-free.
///
/// A body moves with one constant twist over the horizon (setMotion), or along a piecewise
/// constant-twist path (setPath); its margin may grow with time (setGrowth). Pairs with a path
/// or growth run the contact window and narrow phase piece by piece (PairPieces).
///
/// predict(H): swept bounds over [0, H] -> incremental sweep-and-prune (the world mirrors its
/// pairs from began/ended) -> pair rules (cached per pair) -> contact window (per-axis time of
/// impact, then the moving separating-axis test for translating boxes) -> narrow phase
/// (closed forms and FCL, conservative advancement inside the window) -> events.
/// It runs in two halves, so that what needs only the pairs within reach (speed and
/// separation monitoring) can act before the contacts are predicted: predictNear(H) (swept
/// bounds, the pairs within reach) then predictEvents() (broad phase, contact window, narrow
/// phase, events); predict(H) is both.

#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "workspace_proximity/aabb.hpp"
#include "workspace_proximity/body.hpp"
#include "workspace_proximity/motion_path.hpp"
#include "workspace_proximity/narrow_phase.hpp"      // NarrowPhaseConfig
#include "workspace_proximity/pair_event.hpp"
#include "workspace_proximity/pair_rules.hpp"
#include "workspace_proximity/sweep_and_prune.hpp"   // SweepAndPruneConfig, SweepAndPruneStats

namespace workspace_proximity {

struct WorldConfig {
  int initial_body_capacity = 256;
  int initial_pair_capacity = 1024;
  int initial_event_capacity = 256;
  SweepAndPruneConfig broad_phase;   ///< capacities above override its capacities
  NarrowPhaseConfig narrow_phase;
  PairRules rules;                   ///< default: robot-robot pairs skipped
  /// Time the per-pair stages (contact window, narrow phase) separately. Costs two clock
  /// reads per pair, so off by default: ns_axis then holds both and ns_narrow is 0.
  bool time_pair_stages = false;
  /// Threads for the per-pair stages of predict() (rules, contact window, narrow phase): 1,
  /// the caller's alone; n > 1, the caller's and n - 1 workers of the world's own, started at
  /// the first prediction with at least `parallel_pairs` broad-phase pairs (with fewer the
  /// caller's thread does them alone: waking a worker costs some microseconds). The events,
  /// their order and the stats' counts are the same for every value (the reports follow the
  /// pairs' order); the stage times ns_axis and ns_narrow are then summed over the threads.
  int pair_threads = 1;
  int parallel_pairs = 2048;  ///< broad-phase pairs from which pair_threads > 1 are used
  /// pair_threads is in [1, kMaxPairThreads] and parallel_pairs >= 1, or the world's
  /// constructor throws std::invalid_argument.
  static constexpr int kMaxPairThreads = 64;
};

/// Two bodies near each other now: an allowed pair whose bare shapes (margins not included) are
/// at most reach(a) + reach(b) apart at the prediction instant (see ProximityWorld::setReach).
struct NearPair {
  BodyHandle body_a;
  BodyHandle body_b;
  double distance = 0.0;  ///< m between the bare shapes now; 0 when they touch or overlap
  /// Nearest points now (world, m); for overlapping shapes both are the contact point the
  /// narrow phase found (near the overlap, not necessarily inside both).
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();
  /// Unit, from a towards b; for overlapping shapes the contact normal (a towards b).
  Eigen::Vector3d normal = Eigen::Vector3d::UnitX();
};

/// Counts and per-stage times (ns) of the last predict().
struct WorldStats {
  int bodies = 0;
  int broad_pairs = 0;       ///< overlapping swept bounds
  int allowed_pairs = 0;     ///< after the pair rules
  int axis_candidates = 0;   ///< per-axis time of impact within the horizon (contact window, step 1)
  int contacts = 0;          ///< confirmed by the narrow phase
  int narrow_iterations = 0; ///< distance queries (FCL calls and closed-form upright boxes)
  int near_pairs = 0;        ///< pairs within reach (nearPairs())
  /// Stage times, ns: swept bounds; broad phase (with the world's pair cache); contact
  /// window; narrow phase; events.
  std::int64_t ns_bounds = 0, ns_broad = 0, ns_axis = 0, ns_narrow = 0, ns_events = 0;
  std::int64_t ns_pairs = 0;  ///< rules + contact window + narrow phase, all pairs
  std::int64_t ns_near = 0;   ///< the pairs within reach (predictNear's scan)
  SweepAndPruneStats broad_phase;
};

class ProximityWorld {
 public:
  explicit ProximityWorld(const WorldConfig& config = WorldConfig());
  ~ProximityWorld();
  ProximityWorld(const ProximityWorld&) = delete;
  ProximityWorld& operator=(const ProximityWorld&) = delete;

  /// Adds a body. Throws std::invalid_argument if the shape, margin or motion is invalid
  /// or the id is empty.
  BodyHandle addBody(const BodyDesc& desc, const BodyMotion& motion);
  /// Removes a body; its pairs get END events at the next predict(). The handle stays
  /// readable (desc()) until the predict() after that, so END events can be named.
  void removeBody(BodyHandle body);
  /// New pose and velocity at the next prediction instant: one constant twist over the
  /// horizon (replaces a path). Throws on an invalid motion.
  void setMotion(BodyHandle body, const BodyMotion& motion);
  /// A piecewise constant-twist motion over the horizon from the next prediction instant on
  /// (motion_path.hpp): `count` segments, the first starting at t = 0 with the pose now; each
  /// segment may add a margin. Swept bounds are the union over the segments; the contact
  /// window and the narrow phase run piece by piece. One segment without margin is exactly
  /// setMotion(segments[0].motion). Allocation-free once the body has held as many segments.
  /// Throws std::invalid_argument on an invalid path (validPath()).
  void setPath(BodyHandle body, const MotionSegment* segments, int count);
  /// The body's margin grows with time from the next prediction on: margin + growth.at(t) at
  /// t s after the prediction instant (motion_path.hpp; growth.none(): it does not grow, as
  /// when added). Kept across setMotion() and setPath(). Throws on an invalid growth.
  void setGrowth(BodyHandle body, const MarginGrowth& growth);
  /// New shape and margin for a live body, keeping its identity (its pairs' events continue).
  /// Rebuilds the narrow phase's geometry, so callers should do it only when the size really
  /// changed.
  /// Throws on an invalid shape or margin.
  void setShape(BodyHandle body, const Shape& shape, double margin);

  /// True for a body that is live or removed but still nameable.
  bool contains(BodyHandle body) const;
  const BodyDesc& desc(BodyHandle body) const;
  /// The motion now: the constant twist, or a path's first segment.
  const BodyMotion& motion(BodyHandle body) const;
  const MarginGrowth& growth(BodyHandle body) const;
  /// Segments of the body's path as the last predict() prepared them (ends, margins, halves
  /// filled); 0 for a constant twist without growth.
  int pathSize(BodyHandle body) const;
  const PathSegment* path(BodyHandle body) const;
  /// Swept bounds used by the last predict().
  Aabb sweptBounds(BodyHandle body) const;
  int bodyCount() const;

  /// How near (m, >= 0; default 0) another body must come to this one to be reported in
  /// nearPairs(), whatever the contact prediction says: an allowed pair is reported when its
  /// bare shapes are at most reach(a) + reach(b) apart now. predictNear() finds them by a scan
  /// of every body against the bodies with a reach (meant for a few: the robot's), before the
  /// broad phase. The body's broad-phase bounds are grown by `reach` on every side as well (its
  /// sweptBounds() are not), so the broad phase pairs it with every such body too. Takes effect
  /// at the next predict(). Throws on a negative, non-finite or huge (> Limits::kMaxSize) reach.
  void setReach(BodyHandle body, double reach);
  double reach(BodyHandle body) const;

  /// Replaces the pair rules; takes effect at the next predict().
  void setRules(const PairRules& rules);

  /// Predicts contacts within `horizon` seconds (> 0... or 0 for "touching now" only).
  /// The returned events are valid until the next call. The same as predictNear(horizon)
  /// followed by predictEvents().
  const std::vector<PairEvent>& predict(double horizon);
  /// The first half of predict(horizon): every body's swept bounds and the pairs within reach
  /// (nearPairs(), returned), by a scan of every body against the bodies with a reach (their
  /// cost grows with the bodies times the bodies with a reach, not with the broad phase). The
  /// same pairs, in the same order, with the same distances as predict() reports; the broad
  /// phase and the events follow in predictEvents().
  /// A predictNear() not followed by predictEvents() has its events predicted (and dropped)
  /// by the next predictNear().
  const std::vector<NearPair>& predictNear(double horizon);
  /// The second half, with predictNear()'s horizon: the broad phase, the contact window,
  /// narrow phase and events. Throws std::logic_error unless predictNear() ran since the last
  /// predictEvents() (or predict()).
  const std::vector<PairEvent>& predictEvents();
  const WorldStats& stats() const;
  /// Every allowed pair within reach at the last predict() (see setReach), in no particular
  /// order; valid until the next call.
  const std::vector<NearPair>& nearPairs() const;

 private:
  // Bodies, the broad phase and its pair cache, the narrow phase and the event tracker
  // (src/core/proximity_world.cpp).
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace workspace_proximity
