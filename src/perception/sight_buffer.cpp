#include "workspace_proximity/perception/sight_buffer.hpp"

namespace workspace_proximity {
namespace perception {

bool SightBuffer::configure(const VoxelGrid& geometry, std::string* why) {
  if (geometry.cells() <= 0) {
    if (why != nullptr) *why = "sight buffer: an empty grid";
    return false;
  }
  const std::lock_guard<std::mutex> w(writer_);
  const std::lock_guard<std::mutex> lock(mutex_);
  for (SightSlot& slot : slots_) {
    // The grid's own box and voxel size give back exactly its cells.
    slot.grid = VoxelGrid(geometry.cells());
    if (!slot.grid.configure(geometry.box(), geometry.voxelSize(), why)) return false;
    if (slot.grid.cells() != geometry.cells()) {
      if (why != nullptr) *why = "sight buffer: the grid's geometry did not round-trip";
      return false;
    }
    slot.sequence = 0;
  }
  newest_ = held_ = -1;
  writes_ = overwrites_ = 0;
  return true;
}

bool SightBuffer::write(const VoxelGrid& grid, const Eigen::Isometry3d& pose, std::int64_t stamp_ns,
                        std::int64_t received_ns) {
  const std::lock_guard<std::mutex> w(writer_);
  if (grid.cells() != slots_[0].grid.cells() || grid.nx() != slots_[0].grid.nx() ||
      grid.ny() != slots_[0].grid.ny()) {
    return false;
  }
  int target = 0;
  std::int64_t sequence = 0;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (held_ < 0) {
      // Nothing held: the other slot than the newest, so the newest stays readable meanwhile.
      target = newest_ == 0 ? 1 : 0;
    } else {
      target = 1 - held_;
      if (newest_ == target) {
        // The reader holds the older slot: the newer one is rewritten, and until it is whole
        // again the newest complete sight is the held one.
        newest_ = held_;
        ++overwrites_;
      }
    }
    sequence = ++writes_;
  }
  // Outside the lock: the reader can take (only) the other slot meanwhile.
  SightSlot& slot = slots_[target];
  slot.grid.clear();
  const std::uint8_t* flags = grid.flagData();
  for (const std::int64_t cell : grid.touched()) {
    const std::uint8_t f = flags[static_cast<std::size_t>(cell)];
    if ((f & VoxelGrid::kHit) != 0) slot.grid.addHit(cell);
    if ((f & VoxelGrid::kShadow) != 0) slot.grid.addShadow(cell);
  }
  slot.pose = pose;
  slot.stamp_ns = stamp_ns;
  slot.received_ns = received_ns;
  slot.sequence = sequence;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    newest_ = target;
  }
  return true;
}

const SightSlot* SightBuffer::acquire() {
  const std::lock_guard<std::mutex> lock(mutex_);
  held_ = newest_;
  return held_ < 0 ? nullptr : &slots_[held_];
}

void SightBuffer::release() {
  const std::lock_guard<std::mutex> lock(mutex_);
  held_ = -1;
}

std::int64_t SightBuffer::writes() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return writes_;
}

std::int64_t SightBuffer::overwrites() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return overwrites_;
}

}  // namespace perception
}  // namespace workspace_proximity
