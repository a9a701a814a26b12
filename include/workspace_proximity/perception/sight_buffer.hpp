#pragma once
/// One sensor's latest sight (its frame's voxel flags, its pose, its stamp), handed from the
/// thread that processes the sensor's frames to the thread that computes the unseen share
/// (UnseenShare), without either waiting for the other's work: a double buffer of two
/// preallocated slots, swapped under a short mutex (held only to pick or publish a slot, never
/// while copying or reading a grid).
///
/// The writer copies into the slot the reader does not hold and, once the copy is complete,
/// makes it the newest. The reader holds the newest complete slot until it releases it; the
/// writer never writes a held slot and the reader never gets a slot being written, so the
/// reader always sees one whole frame (flags, pose and stamps of the same write). When the
/// reader holds the older slot while frames keep coming, the writer overwrites the newer one:
/// meanwhile the newest complete sight is the held one (a frame older, still whole).
///
/// One reader at a time; writers to one buffer are serialised among themselves (a second
/// writer waits for the first, never for the reader). ROS-free; allocation-free after
/// configure().

#include <cstdint>
#include <mutex>
#include <string>

#include <Eigen/Geometry>

#include "workspace_proximity/perception/voxel_grid.hpp"

namespace workspace_proximity {
namespace perception {

struct SightSlot {
  /// The frame's cell flags (VoxelGrid::kHit, kShadow: what UnseenShare reads); the point
  /// counts are not copied (every flagged cell has count 0 here).
  VoxelGrid grid{0};
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor frame in the fixed frame at the stamp
  std::int64_t stamp_ns = 0;     ///< ns, the frame's stamp
  std::int64_t received_ns = 0;  ///< ns, when the frame was used (for the source timeout)
  std::int64_t sequence = 0;     ///< 1, 2, ...: which write filled it
};

class SightBuffer {
 public:
  SightBuffer() = default;
  SightBuffer(const SightBuffer&) = delete;
  SightBuffer& operator=(const SightBuffer&) = delete;

  /// Sizes both slots for grids of `geometry`'s cells and voxel size (allocates). False, with
  /// `why`, when the geometry cannot be taken (an empty grid).
  bool configure(const VoxelGrid& geometry, std::string* why);

  /// Writer: copies `grid`'s flags (it must have the configured geometry; false and nothing
  /// written otherwise), the pose and the stamps into the slot the reader does not hold, then
  /// makes it the newest.
  bool write(const VoxelGrid& grid, const Eigen::Isometry3d& pose, std::int64_t stamp_ns,
             std::int64_t received_ns);

  /// Reader: the newest complete slot, unchanged until release(); null before the first write.
  /// A second acquire() before release() returns the newest again (and holds that one).
  const SightSlot* acquire();
  /// Reader: gives the held slot back to the writer.
  void release();

  /// Writes so far; of them, those that had to overwrite the newer slot because the reader
  /// held the older one.
  std::int64_t writes() const;
  std::int64_t overwrites() const;

 private:
  mutable std::mutex mutex_;  // newest_, held_, the counters: held only to pick or publish
  std::mutex writer_;         // serialises writers; never taken by the reader
  SightSlot slots_[2];
  int newest_ = -1;  // the newest complete slot, or -1
  int held_ = -1;    // the slot the reader holds, or -1
  std::int64_t writes_ = 0;
  std::int64_t overwrites_ = 0;
};

}  // namespace perception
}  // namespace workspace_proximity
