// The unseen share against analytic scenes: a wall of points in front of a camera shadows
// exactly the protective voxels whose line of sight crosses the wall (a segment-box test
// written here), voxels outside the field of view are unseen, a wall outside the monitored
// volume still shadows what lies behind it, and a second sensor sees what the first cannot.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "allocation_counter.hpp"  // test/shared
#include "workspace_proximity/perception/cloud_frame.hpp"
#include "workspace_proximity/perception/unseen_share.hpp"

namespace wp = workspace_proximity;
namespace pc = workspace_proximity::perception;

namespace {

// Oracle: does the segment a -> b meet the closed box [lo, hi]? (Slab test.)
bool segmentHitsBox(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& lo,
                    const Eigen::Vector3d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector3d d = b - a;
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    double u = (lo[k] - a[k]) / d[k], v = (hi[k] - a[k]) / d[k];
    if (u > v) std::swap(u, v);
    t0 = std::max(t0, u);
    t1 = std::min(t1, v);
    if (t0 > t1) return false;
  }
  return true;
}

pc::CloudFrameParams sceneParams() {
  pc::CloudFrameParams p;
  p.volume = wp::Aabb{Eigen::Vector3d(0, -1, -1), Eigen::Vector3d(2, 1, 1)};
  p.voxel_size = 0.05;
  p.floor_height = -5.0;
  p.floor_tolerance = 0.0;
  p.min_cluster_points = 1;
  return p;
}

// Points at the centres of the cells filling [lo, hi) (a whole number of 5 cm cells).
std::vector<float> wallOfCells(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  std::vector<float> pts;
  for (double z = lo.z() + 0.025; z < hi.z(); z += 0.05) {
    for (double y = lo.y() + 0.025; y < hi.y(); y += 0.05) {
      for (double x = lo.x() + 0.025; x < hi.x(); x += 0.05) {
        pts.push_back(static_cast<float>(x));
        pts.push_back(static_cast<float>(y));
        pts.push_back(static_cast<float>(z));
      }
    }
  }
  return pts;
}

struct Scene {
  pc::SelfLink robot;
  double reach = 0.6, padding = 0.03;
  Scene() {
    robot.shape = wp::Shape::sphere(0.1);
    robot.pose = Eigen::Isometry3d(Eigen::Translation3d(1.5, 0.0, 0.0));
  }
  // Oracle: protective = centre within reach of the sphere and outside the padded sphere.
  bool protective(const Eigen::Vector3d& c) const {
    const double d = (c - robot.pose.translation()).norm() - 0.1;
    return d <= reach && d > padding;
  }
};

pc::SensorFov camera(const Eigen::Vector3d& at, double azimuth = 0.6, double elevation = 0.5) {
  pc::SensorFov f;
  f.pose = Eigen::Isometry3d(Eigen::Translation3d(at));
  f.azimuth_min = -azimuth;
  f.azimuth_max = azimuth;
  f.elevation_min = -elevation;
  f.elevation_max = elevation;
  f.range_min = 0.0;
  f.range_max = 10.0;
  return f;
}

TEST(UnseenShare, FastAtan2IsWithinItsStatedError) {
  // The error depends on the ratio of the smaller to the larger |coordinate| and on the
  // quadrant: a million ratios in each octant.
  double worst = 0.0;
  for (int i = 0; i <= 1000000; ++i) {
    const double t = i / 1000000.0;
    for (const auto& xy : {std::make_pair(1.0, t), std::make_pair(t, 1.0), std::make_pair(-1.0, t),
                           std::make_pair(-t, 1.0), std::make_pair(1.0, -t), std::make_pair(t, -1.0),
                           std::make_pair(-1.0, -t), std::make_pair(-t, -1.0)}) {
      const auto x = static_cast<float>(xy.first * 3.7), y = static_cast<float>(xy.second * 3.7);
      const double exact = std::atan2(static_cast<double>(y), static_cast<double>(x));
      double d = std::abs(pc::fastAtan2(y, x) - exact);
      d = std::min(d, std::abs(d - 2 * M_PI));  // -pi and pi are the same direction
      worst = std::max(worst, d);
    }
  }
  EXPECT_LT(worst, pc::kFastAtan2Error);
  EXPECT_EQ(pc::fastAtan2(0.0f, 0.0f), 0.0f);
}

TEST(UnseenShare, AWallInFrontOfTheCameraShadowsTheVoxelsBehindIt) {
  pc::CloudFrame frame(sceneParams());
  // The wall: cells x in [0.80, 0.85), y in [-0.20, 0.20), z in [-0.15, 0.25).
  const Eigen::Vector3d lo(0.80, -0.20, -0.15), hi(0.85, 0.20, 0.25);
  const std::vector<float> wall = wallOfCells(lo, hi);
  // A camera outside the volume, off the grid's planes so no line of sight grazes an edge.
  const Eigen::Vector3d eye(-0.5, 0.013, 0.017);
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translate(eye.cast<float>());
  // The wall's points given in the camera frame, as a sensor would.
  std::vector<float> local(wall);
  for (std::size_t i = 0; i < local.size(); i += 3) {
    for (int k = 0; k < 3; ++k) local[i + k] -= static_cast<float>(eye[k]);
  }
  frame.process(pc::packedXyz(local.data(), static_cast<std::int64_t>(local.size() / 3)), pose);
  ASSERT_EQ(frame.stats().kept, static_cast<std::int64_t>(wall.size() / 3));

  Scene scene;
  pc::UnseenShare unseen(4);
  unseen.configure(frame.grid());
  // A narrow view (the protective ball spans about 0.34 rad from the camera): some of it is
  // outside.
  const pc::SensorSight sight{camera(eye, 0.25, 0.2), &frame.grid()};
  const pc::UnseenResult& r =
      unseen.compute(&scene.robot, 1, scene.reach, scene.padding, -5.0, &sight, 1);

  // The oracle, cell by cell over the whole grid.
  const pc::VoxelGrid& g = frame.grid();
  std::vector<char> is_unseen(static_cast<std::size_t>(g.cells()), 0);
  for (const std::int64_t c : unseen.unseenCells()) is_unseen[static_cast<std::size_t>(c)] = 1;
  std::int64_t protective = 0, shadowed = 0, outside = 0, ambiguous = 0, wrong = 0;
  const Eigen::Vector3d eps = Eigen::Vector3d::Constant(1e-6);
  for (std::int64_t c = 0; c < g.cells(); ++c) {
    const Eigen::Vector3d centre = g.centre(c).cast<double>();
    if (!scene.protective(centre)) continue;
    ++protective;
    const Eigen::Vector3d v = centre - eye;
    const double az = std::atan2(v.y(), v.x()), el = std::atan2(v.z(), std::hypot(v.x(), v.y()));
    const bool in_view = std::abs(az) <= 0.25 && std::abs(el) <= 0.2;
    // Within 1e-4 rad of a view limit: the code's margin (kFastAtan2Error) may say outside.
    if (std::abs(std::abs(az) - 0.25) < 1e-4 || std::abs(std::abs(el) - 0.2) < 1e-4) {
      ++ambiguous;
      continue;
    }
    const bool in_wall = (centre.array() > lo.array()).all() && (centre.array() < hi.array()).all();
    const bool hit_big = segmentHitsBox(eye, centre, lo - eps, hi + eps);
    const bool hit_small = segmentHitsBox(eye, centre, lo + eps, hi - eps);
    if (hit_big != hit_small) {
      ++ambiguous;
      continue;
    }
    const bool expect_unseen = !in_view || (hit_big && !in_wall);
    shadowed += in_view && hit_big && !in_wall;
    outside += !in_view;
    wrong += expect_unseen != (is_unseen[static_cast<std::size_t>(c)] != 0);
  }
  EXPECT_LT(ambiguous, 10);
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(r.protective, protective);
  EXPECT_GT(shadowed, 50);  // the scene does shadow something, and leaves something in view
  EXPECT_GT(outside, 50);
  // Exact but for the ambiguous voxels (each could fall either way).
  EXPECT_LE(std::abs(r.shadowed - shadowed), ambiguous);
  EXPECT_LE(std::abs(r.outside_fov - outside), ambiguous);
  EXPECT_LE(std::abs(r.unseen - (shadowed + outside)), ambiguous);
  EXPECT_DOUBLE_EQ(r.share, static_cast<double>(r.unseen) / static_cast<double>(protective));
}

TEST(UnseenShare, AWallOutsideTheVolumeStillShadows) {
  pc::CloudFrame frame(sceneParams());
  // Points in a plane at x = -0.02 (outside the volume, which starts at x = 0), 1 cm apart,
  // y and z in [-0.05, 0.05]; the camera at x = -0.5.
  const Eigen::Vector3d eye(-0.5, 0.013, 0.017);
  std::vector<float> pts;
  for (double y = -0.05; y <= 0.05 + 1e-9; y += 0.01) {
    for (double z = -0.05; z <= 0.05 + 1e-9; z += 0.01) {
      pts.push_back(static_cast<float>(-0.02 - eye.x()));
      pts.push_back(static_cast<float>(y - eye.y()));
      pts.push_back(static_cast<float>(z - eye.z()));
    }
  }
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translate(eye.cast<float>());
  frame.process(pc::packedXyz(pts.data(), static_cast<std::int64_t>(pts.size() / 3)), pose);
  EXPECT_EQ(frame.stats().outside_volume, static_cast<std::int64_t>(pts.size() / 3));
  EXPECT_EQ(frame.stats().kept, 0);

  Scene scene;
  pc::UnseenShare unseen(4);
  unseen.configure(frame.grid());
  const pc::SensorSight sight{camera(eye), &frame.grid()};
  unseen.compute(&scene.robot, 1, scene.reach, scene.padding, -5.0, &sight, 1);
  const pc::VoxelGrid& g = frame.grid();
  std::vector<char> is_unseen(static_cast<std::size_t>(g.cells()), 0);
  for (const std::int64_t c : unseen.unseenCells()) is_unseen[static_cast<std::size_t>(c)] = 1;
  // Behind the plate shrunk by 1 cm: unseen. Clear of its shadow grown by 8 cm at the plate
  // (the marked entry voxels, 2 cm behind it, reach at most a voxel diagonal past its
  // shadow): seen when in view.
  std::int64_t behind = 0, clear = 0, wrong = 0;
  for (const std::int64_t c : unseen.protectiveCells()) {
    const Eigen::Vector3d centre = g.centre(c).cast<double>();
    const Eigen::Vector3d v = centre - eye;
    if (std::abs(std::atan2(v.y(), v.x())) > 0.6 - 1e-4 ||
        std::abs(std::atan2(v.z(), std::hypot(v.x(), v.y()))) > 0.5 - 1e-4) {
      continue;  // outside the view, or too close to its edge to call
    }
    const bool inner = segmentHitsBox(eye, centre, Eigen::Vector3d(-0.02, -0.04, -0.04),
                                      Eigen::Vector3d(-0.02, 0.04, 0.04));
    const bool outer = segmentHitsBox(eye, centre, Eigen::Vector3d(-0.02, -0.13, -0.13),
                                      Eigen::Vector3d(-0.02, 0.13, 0.13));
    if (inner) {
      ++behind;
      wrong += is_unseen[static_cast<std::size_t>(c)] == 0;
    } else if (!outer) {
      ++clear;
      wrong += is_unseen[static_cast<std::size_t>(c)] != 0;
    }
  }
  EXPECT_GT(behind, 20);
  EXPECT_GT(clear, 20);
  EXPECT_EQ(wrong, 0);
}

TEST(UnseenShare, NoSensorMeansEverythingUnseenAndASecondSensorSeesAroundTheWall) {
  pc::CloudFrame front(sceneParams()), side(sceneParams());
  const Eigen::Vector3d lo(0.80, -0.20, -0.15), hi(0.85, 0.20, 0.25);
  const std::vector<float> wall = wallOfCells(lo, hi);
  front.process(pc::packedXyz(wall.data(), static_cast<std::int64_t>(wall.size() / 3)),
                Eigen::Isometry3f::Identity());  // points given in the fixed frame
  const std::vector<float> none;
  Scene scene;
  pc::UnseenShare unseen(4);
  unseen.configure(front.grid());
  const pc::UnseenResult blind = unseen.compute(&scene.robot, 1, scene.reach, scene.padding, -5.0, nullptr, 0);
  EXPECT_GT(blind.protective, 0);
  EXPECT_EQ(blind.unseen, blind.protective);
  EXPECT_EQ(blind.outside_fov, blind.protective);
  EXPECT_DOUBLE_EQ(blind.share, 1.0);

  const Eigen::Vector3d eye(-0.5, 0.013, 0.017);
  pc::SensorSight sights[2] = {{camera(eye), &front.grid()}, {}};
  const std::int64_t one = unseen.compute(&scene.robot, 1, scene.reach, scene.padding, -5.0, sights, 1).unseen;
  // A second camera above the robot looking down sees everything within reach (nothing in its
  // frame blocks it): every voxel in its view is seen.
  side.process(pc::packedXyz(none.data(), 0), Eigen::Isometry3f::Identity());
  sights[1].fov.pose = Eigen::Translation3d(1.5, 0.0, 5.0) *
                       Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY());  // +x points down
  sights[1].fov.azimuth_min = sights[1].fov.elevation_min = -1.0;
  sights[1].fov.azimuth_max = sights[1].fov.elevation_max = 1.0;
  sights[1].grid = &side.grid();
  const pc::UnseenResult& both = unseen.compute(&scene.robot, 1, scene.reach, scene.padding, -5.0, sights, 2);
  EXPECT_GT(one, 0);
  EXPECT_EQ(both.unseen, 0);

  // Steady state: the same computation again allocates nothing.
  const long before = wp_test::allocationCount();
  unseen.compute(&scene.robot, 1, scene.reach, scene.padding, -5.0, sights, 2);
  EXPECT_EQ(wp_test::allocationCount() - before, 0);
}

TEST(UnseenShare, TheFloorAndThePaddedRobotAreNotProtective) {
  pc::CloudFrame frame(sceneParams());
  Scene scene;
  pc::UnseenShare unseen(1);
  unseen.configure(frame.grid());
  const std::int64_t all = unseen.compute(&scene.robot, 1, scene.reach, scene.padding, -5.0, nullptr, 0).protective;
  const std::int64_t above = unseen.compute(&scene.robot, 1, scene.reach, scene.padding, 0.0, nullptr, 0).protective;
  std::int64_t expect_all = 0, expect_above = 0;
  const pc::VoxelGrid& g = frame.grid();
  for (std::int64_t c = 0; c < g.cells(); ++c) {
    const Eigen::Vector3d centre = g.centre(c).cast<double>();
    if (!scene.protective(centre)) continue;
    ++expect_all;
    expect_above += centre.z() >= 0.0;
  }
  EXPECT_EQ(all, expect_all);
  EXPECT_EQ(above, expect_above);
  EXPECT_LT(above, all);
}

TEST(UnseenShare, BadLinksOrReachAreRefusedAsAllUnseen) {
  pc::CloudFrame frame(sceneParams());
  Scene scene;
  pc::UnseenShare unseen(1);
  unseen.configure(frame.grid());
  scene.robot.pose.translation().x() = std::numeric_limits<double>::quiet_NaN();
  const pc::UnseenResult bad_link = unseen.compute(&scene.robot, 1, 0.6, 0.03, -5.0, nullptr, 0);
  EXPECT_TRUE(bad_link.refused);
  EXPECT_EQ(bad_link.share, 1.0);
  scene.robot.pose.translation().x() = 1.5;
  const pc::UnseenResult bad_reach =
      unseen.compute(&scene.robot, 1, std::numeric_limits<double>::infinity(), 0.03, -5.0, nullptr, 0);
  EXPECT_TRUE(bad_reach.refused);
  EXPECT_EQ(bad_reach.share, 1.0);
  EXPECT_FALSE(unseen.compute(&scene.robot, 1, 0.6, 0.03, -5.0, nullptr, 0).refused);
  // A view with an infinite limit sees nothing (and does not hang sizing its depth image).
  pc::SensorSight sight{camera(Eigen::Vector3d(-0.5, 0.013, 0.017)), &frame.grid()};
  sight.fov.azimuth_max = std::numeric_limits<double>::infinity();
  const pc::UnseenResult blind = unseen.compute(&scene.robot, 1, 0.6, 0.03, -5.0, &sight, 1);
  EXPECT_EQ(blind.unseen, blind.protective);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
