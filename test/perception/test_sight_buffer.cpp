// The sensors' sights handed to the unseen share's thread (sight_buffer.hpp): a slot holds
// exactly the written frame's flags (every cell compared with the source), the reader's slot
// never changes while held however many frames are written, the newest complete frame is what
// the next acquire gets, and with a writer and a reader thread racing, every slot the reader
// holds is one whole frame (each cell's flags, the pose and the stamps all of one write,
// checked against the frame rebuilt from its number alone) and frames only go forward.
// Nothing is allocated once configured.

#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "allocation_counter.hpp"  // test/shared
#include "workspace_proximity/perception/sight_buffer.hpp"

namespace pc = workspace_proximity::perception;
namespace wp = workspace_proximity;

namespace {

// A 20 x 20 x 20 grid of 0.1 m cells from (-1, -1, 0).
void configureGrid(pc::VoxelGrid* g) {
  std::string why;
  ASSERT_TRUE(g->configure(wp::Aabb{Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(1, 1, 2)}, 0.1, &why)) << why;
}

// Frame k's flags for cell c, from k alone (the oracle): a pseudo-random pattern whose
// density changes with k, so frames differ in which cells and in how many.
std::uint8_t expectedFlags(std::int64_t k, std::int64_t c) {
  std::uint64_t h = static_cast<std::uint64_t>(k) * 0x9E3779B97F4A7C15ull ^ static_cast<std::uint64_t>(c) * 0xC2B2AE3D27D4EB4Full;
  h ^= h >> 29;
  h *= 0xBF58476D1CE4E5B9ull;
  h ^= h >> 32;
  const std::uint64_t density = 2 + static_cast<std::uint64_t>(k % 7);  // 1 cell in 2 .. 8
  if (h % density != 0) return 0;
  return static_cast<std::uint8_t>(1 + (h >> 8) % 3);  // kHit, kShadow or both
}

// Frame k written into `g` as CloudFrame would (points and hits and shadows).
void fillFrame(std::int64_t k, pc::VoxelGrid* g) {
  g->clear();
  for (std::int64_t c = 0; c < g->cells(); ++c) {
    const std::uint8_t f = expectedFlags(k, c);
    if ((f & pc::VoxelGrid::kHit) != 0) {
      if (c % 2 == 0) g->addPoint(c); else g->addHit(c);
    }
    if ((f & pc::VoxelGrid::kShadow) != 0) g->addShadow(c);
  }
}

Eigen::Isometry3d poseOf(std::int64_t k) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.translation() = Eigen::Vector3d(static_cast<double>(k), 2.0 * static_cast<double>(k), -0.5);
  p.linear() = Eigen::AngleAxisd(0.01 * static_cast<double>(k), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return p;
}

// Whether `slot` is exactly frame k; the first difference in `why`.
bool isFrame(const pc::SightSlot& slot, std::int64_t k, std::string* why) {
  if (slot.stamp_ns != 1000 * k || slot.received_ns != 1000 * k + 7) {
    *why = "stamps of another frame";
    return false;
  }
  if (!slot.pose.isApprox(poseOf(k), 1e-12)) {
    *why = "pose of another frame";
    return false;
  }
  std::int64_t flagged = 0;
  for (std::int64_t c = 0; c < slot.grid.cells(); ++c) {
    const std::uint8_t want = expectedFlags(k, c);
    if (slot.grid.flags(c) != want) {
      *why = "cell " + std::to_string(c) + " flags " + std::to_string(slot.grid.flags(c)) + ", frame " +
             std::to_string(k) + " has " + std::to_string(want);
      return false;
    }
    flagged += want != 0 ? 1 : 0;
  }
  // The touched list is the flagged cells, each once (clear() of the next write resets them).
  if (static_cast<std::int64_t>(slot.grid.touched().size()) != flagged) {
    *why = "touched list of " + std::to_string(slot.grid.touched().size()) + " cells, " +
           std::to_string(flagged) + " flagged";
    return false;
  }
  return true;
}

void writeFrame(pc::SightBuffer* b, pc::VoxelGrid* g, std::int64_t k) {
  fillFrame(k, g);
  ASSERT_TRUE(b->write(*g, poseOf(k), 1000 * k, 1000 * k + 7));
}

}  // namespace

// A buffer configured for the test grid (every test but the refusals starts here).
class ConfiguredSightBuffer : public ::testing::Test {
 protected:
  void SetUp() override {
    configureGrid(&g);
    ASSERT_TRUE(b.configure(g, &why)) << why;
  }
  pc::VoxelGrid g{100000};
  pc::SightBuffer b;
  std::string why;
};

TEST_F(ConfiguredSightBuffer, NothingBeforeTheFirstWrite) {
  EXPECT_EQ(b.acquire(), nullptr);
  b.release();
}

TEST(SightBuffer, RefusesAnEmptyGeometryAndAnotherGrid) {
  pc::SightBuffer b;
  std::string why;
  EXPECT_FALSE(b.configure(pc::VoxelGrid(10), &why));
  EXPECT_FALSE(why.empty());
  pc::VoxelGrid g(100000);
  configureGrid(&g);
  ASSERT_TRUE(b.configure(g, &why)) << why;
  pc::VoxelGrid other(100000);
  ASSERT_TRUE(other.configure(wp::Aabb{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 1, 1)}, 0.1, &why));
  EXPECT_FALSE(b.write(other, poseOf(1), 1, 1));
  EXPECT_EQ(b.acquire(), nullptr);
  b.release();
}

TEST_F(ConfiguredSightBuffer, ASlotIsExactlyTheWrittenFrame) {
  // Frames of different density one after another: no cell of an earlier frame stays.
  for (std::int64_t k = 1; k <= 9; ++k) {
    writeFrame(&b, &g, k);
    const pc::SightSlot* s = b.acquire();
    ASSERT_NE(s, nullptr);
    EXPECT_EQ(s->sequence, k);
    EXPECT_TRUE(isFrame(*s, k, &why)) << "frame " << k << ": " << why;
    // Counts are not handed over: flags only.
    for (const std::int64_t c : s->grid.touched()) EXPECT_EQ(s->grid.count(c), 0);
    b.release();
  }
}

TEST_F(ConfiguredSightBuffer, AHeldSlotNeverChangesAndWritesNeverWait) {
  writeFrame(&b, &g, 1);
  const pc::SightSlot* held = b.acquire();
  ASSERT_NE(held, nullptr);
  // The reader holds frame 1 while ten frames are written (on this very thread: a write that
  // waited for the reader would never return).
  for (std::int64_t k = 2; k <= 11; ++k) {
    writeFrame(&b, &g, k);
    EXPECT_TRUE(isFrame(*held, 1, &why)) << "after frame " << k << ": " << why;
  }
  // Frame 2 went to the free slot, frames 3 to 11 overwrote it (the reader held the other).
  EXPECT_EQ(b.writes(), 11);
  EXPECT_EQ(b.overwrites(), 9);
  b.release();
  // Released: the newest complete frame, 11.
  const pc::SightSlot* s = b.acquire();
  ASSERT_NE(s, nullptr);
  EXPECT_TRUE(isFrame(*s, 11, &why)) << why;
  // Held again (frame 11's slot): the next write goes to the other slot, frame 11 stays whole.
  writeFrame(&b, &g, 12);
  EXPECT_TRUE(isFrame(*s, 11, &why)) << why;
  b.release();
  s = b.acquire();
  ASSERT_NE(s, nullptr);
  EXPECT_TRUE(isFrame(*s, 12, &why)) << why;
  b.release();
}

TEST_F(ConfiguredSightBuffer, AReaderMovingOnGetsTheNewest) {
  // The reader holds frame 1 while frames 2 and 3 are written (both into the other slot), then
  // acquires again without releasing: frame 3, in the other slot, whole.
  writeFrame(&b, &g, 1);
  const pc::SightSlot* s1 = b.acquire();  // frame 1, slot A
  writeFrame(&b, &g, 2);                   // slot B, newest
  writeFrame(&b, &g, 3);                   // slot B again (A held), newest
  const pc::SightSlot* s3 = b.acquire();   // the reader moves on to frame 3
  ASSERT_NE(s3, nullptr);
  EXPECT_NE(s3, s1);
  EXPECT_TRUE(isFrame(*s3, 3, &why)) << why;
  b.release();
}

TEST_F(ConfiguredSightBuffer, NoAllocationOnceConfigured) {
  // Every frame's grid built first (VoxelGrid is allocation-free after configure too).
  const long before = wp_test::allocationCount();
  for (std::int64_t k = 1; k <= 20; ++k) {
    fillFrame(k, &g);
    b.write(g, poseOf(k), 1000 * k, 1000 * k + 7);
    if (k % 3 == 0) {
      const pc::SightSlot* s = b.acquire();
      b.write(g, poseOf(k), 1000 * k, 1000 * k + 7);  // while held
      EXPECT_NE(s, nullptr);
      b.release();
    }
  }
  EXPECT_EQ(wp_test::allocationCount(), before);
}

TEST_F(ConfiguredSightBuffer, AReaderThreadAlwaysSeesOneWholeFrame) {
  // One writer thread (a sensor's frames) and one reader thread (the unseen share): every slot
  // the reader holds is compared cell by cell with the frame its stamp names, twice (at once and
  // after a pause, so a write into a held slot would show), and the frames only go forward.
  constexpr std::int64_t kFrames = 1500;
  std::atomic<bool> done{false};
  std::atomic<std::int64_t> reads{0}, bad{0};
  std::string first_bad;
  std::thread reader([&] {
    std::int64_t last = 0;
    std::string reason;
    while (!done.load()) {
      const pc::SightSlot* s = b.acquire();
      if (s != nullptr) {
        const std::int64_t k = s->stamp_ns / 1000;
        bool ok = k >= last && s->sequence == k && isFrame(*s, k, &reason);
        if (ok && reads.load() % 4 == 0) {
          std::this_thread::yield();
          ok = isFrame(*s, k, &reason);
        }
        if (!ok && bad.fetch_add(1) == 0) {
          first_bad = "frame " + std::to_string(k) + " (last " + std::to_string(last) + "): " + reason;
        }
        last = k;
        ++reads;
      }
      b.release();
    }
  });
  for (std::int64_t k = 1; k <= kFrames; ++k) {
    fillFrame(k, &g);
    ASSERT_TRUE(b.write(g, poseOf(k), 1000 * k, 1000 * k + 7));
  }
  // Let the reader see the last frame at least once more.
  const std::int64_t seen = reads.load();
  while (reads.load() < seen + 2) std::this_thread::yield();
  done = true;
  reader.join();
  EXPECT_EQ(bad.load(), 0) << first_bad;
  EXPECT_GT(reads.load(), 2);
  const pc::SightSlot* s = b.acquire();
  ASSERT_NE(s, nullptr);
  EXPECT_TRUE(isFrame(*s, kFrames, &why)) << why;
  b.release();
  std::printf("reads %lld, writes %lld, overwrites %lld\n", static_cast<long long>(reads.load()),
              static_cast<long long>(b.writes()), static_cast<long long>(b.overwrites()));
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
