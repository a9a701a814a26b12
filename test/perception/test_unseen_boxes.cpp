// Unseen voxels as boxes (unseen_boxes.hpp): an L of three cells by hand, a solid block as one
// box, random sets against brute force (every cell centre inside a box exactly when the cell
// is in the set, boxes disjoint), the cap covering every cell, no allocation once configured.

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <string>
#include <vector>

#include "allocation_counter.hpp"  // test/shared
#include "workspace_proximity/perception/unseen_boxes.hpp"

namespace pc = workspace_proximity::perception;
namespace wp = workspace_proximity;

namespace {

// A 10 x 10 x 10 grid of 0.1 m cells from (-1, -1, 0).
pc::VoxelGrid grid10() {
  pc::VoxelGrid g(100000);
  std::string why;
  EXPECT_TRUE(g.configure(wp::Aabb{Eigen::Vector3d(-1, -1, 0), Eigen::Vector3d(0, 0, 1)}, 0.1, &why)) << why;
  return g;
}

bool inside(const pc::CellBox& b, const Eigen::Vector3f& p) {
  return ((p - b.centre).cwiseAbs().array() < 0.5f * b.size.array()).all();
}

// How many boxes hold the centre of each cell of the grid.
std::vector<int> coverage(const pc::VoxelGrid& g, const std::vector<pc::CellBox>& boxes) {
  std::vector<int> n(static_cast<std::size_t>(g.cells()), 0);
  for (std::int64_t c = 0; c < g.cells(); ++c) {
    for (const pc::CellBox& b : boxes) n[static_cast<std::size_t>(c)] += inside(b, g.centre(c)) ? 1 : 0;
  }
  return n;
}

}  // namespace

TEST(UnseenBoxes, AnLOfThreeCellsIsTwoBoxes) {
  const pc::VoxelGrid g = grid10();
  pc::UnseenBoxes u;
  u.configure(g);
  // (0,0,0), (1,0,0), (0,1,0): the x run of two, then the single cell above it in y.
  const auto& boxes = u.build(g, {g.cellAt(0, 1, 0), g.cellAt(1, 0, 0), g.cellAt(0, 0, 0)});
  ASSERT_EQ(boxes.size(), 2u);
  EXPECT_TRUE(boxes[0].centre.isApprox(Eigen::Vector3f(-0.9f, -0.95f, 0.05f), 1e-5f));
  EXPECT_TRUE(boxes[0].size.isApprox(Eigen::Vector3f(0.2f, 0.1f, 0.1f), 1e-5f));
  EXPECT_EQ(boxes[0].cells, 2);
  EXPECT_TRUE(boxes[1].centre.isApprox(Eigen::Vector3f(-0.95f, -0.85f, 0.05f), 1e-5f));
  EXPECT_TRUE(boxes[1].size.isApprox(Eigen::Vector3f(0.1f, 0.1f, 0.1f), 1e-5f));
  EXPECT_FALSE(u.capped());
}

TEST(UnseenBoxes, ASolidBlockIsOneBox) {
  const pc::VoxelGrid g = grid10();
  pc::UnseenBoxes u;
  u.configure(g);
  std::vector<std::int64_t> cells;
  for (int z = 2; z < 5; ++z)
    for (int y = 1; y < 7; ++y)
      for (int x = 3; x < 5; ++x) cells.push_back(g.cellAt(x, y, z));
  const auto& boxes = u.build(g, cells);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_TRUE(boxes[0].size.isApprox(Eigen::Vector3f(0.2f, 0.6f, 0.3f), 1e-5f));
  EXPECT_EQ(boxes[0].cells, 36);
}

TEST(UnseenBoxes, RandomSetsAreCoveredExactlyByDisjointBoxes) {
  const pc::VoxelGrid g = grid10();
  pc::UnseenBoxes u(100000);
  u.configure(g);
  std::mt19937 rng(23);
  for (int trial = 0; trial < 20; ++trial) {
    SCOPED_TRACE(trial);
    // Blobs: a few random blocks and random single cells.
    std::set<std::int64_t> set;
    std::uniform_int_distribution<int> pos(0, 9), len(1, 5), coin(0, 1);
    for (int k = 0; k < 4; ++k) {
      const int x0 = pos(rng), y0 = pos(rng), z0 = pos(rng), l = len(rng);
      for (int z = z0; z < std::min(10, z0 + l); ++z)
        for (int y = y0; y < std::min(10, y0 + l); ++y)
          for (int x = x0; x < std::min(10, x0 + l); ++x) set.insert(g.cellAt(x, y, z));
    }
    for (int k = 0; k < 30; ++k) set.insert(g.cellAt(pos(rng), pos(rng), pos(rng)));
    const std::vector<std::int64_t> cells(set.begin(), set.end());
    const auto& boxes = u.build(g, cells);
    const std::vector<int> n = coverage(g, boxes);
    for (std::int64_t c = 0; c < g.cells(); ++c) {
      EXPECT_EQ(n[static_cast<std::size_t>(c)], set.count(c) ? 1 : 0) << "cell " << c;
    }
    int total = 0;
    for (const pc::CellBox& b : boxes) total += b.cells;
    EXPECT_EQ(total, static_cast<int>(cells.size()));
    EXPECT_LE(boxes.size(), cells.size());
    EXPECT_FALSE(u.capped());
  }
}

TEST(UnseenBoxes, BeyondTheCapTheLastBoxBoundsTheRest) {
  const pc::VoxelGrid g = grid10();
  pc::UnseenBoxes u(3);
  u.configure(g);
  std::vector<std::int64_t> cells;  // a checkerboard layer: no two cells merge
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 10; ++x)
      if ((x + y) % 2 == 0) cells.push_back(g.cellAt(x, y, 4));
  const auto& boxes = u.build(g, cells);
  ASSERT_EQ(boxes.size(), 3u);
  EXPECT_TRUE(u.capped());
  const std::vector<int> n = coverage(g, boxes);
  for (std::int64_t c : cells) EXPECT_GE(n[static_cast<std::size_t>(c)], 1) << "cell " << c;
  EXPECT_EQ(boxes[0].cells + boxes[1].cells + boxes[2].cells, static_cast<int>(cells.size()));
}

TEST(UnseenBoxes, BuildingAllocatesNothingOnceConfigured) {
  const pc::VoxelGrid g = grid10();
  pc::UnseenBoxes u(64);
  u.configure(g);
  std::vector<std::int64_t> cells;
  for (int x = 0; x < 10; x += 3) cells.push_back(g.cellAt(x, 2, 3));
  u.build(g, cells);
  const long before = wp_test::allocationCount();
  for (int k = 0; k < 10; ++k) u.build(g, cells);
  EXPECT_EQ(wp_test::allocationCount() - before, 0);
}

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
