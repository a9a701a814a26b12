// The perception front end's per-frame rules against analytic scenes and brute-force oracles:
// voxel counts of known shapes, connected clusters (26-neighbourhood), the self-filter against
// a clamp-to-shape distance computed here, a moving link's growth, floor and crop counts,
// malformed clouds rejected by name, laser scans extruded over a height band, no memory
// between frames and no allocation per frame.

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <tuple>
#include <vector>

#include "allocation_counter.hpp"  // test/shared
#include "random.hpp"              // test/shared
#include "workspace_proximity/perception/cloud_frame.hpp"
#include "workspace_proximity/perception/laser_scan.hpp"

namespace wp = workspace_proximity;
namespace pc = workspace_proximity::perception;

namespace {

using Points = std::vector<float>;

void add(Points* pts, double x, double y, double z) {
  pts->push_back(static_cast<float>(x));
  pts->push_back(static_cast<float>(y));
  pts->push_back(static_cast<float>(z));
}

// Points on a lattice of spacing `step` filling [lo, hi) (offset by a quarter step, so no
// point lies on a voxel face of a 5 cm grid when step divides 5 cm).
void fillBox(Points* pts, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double step) {
  for (double z = lo.z() + 0.25 * step; z < hi.z(); z += step) {
    for (double y = lo.y() + 0.25 * step; y < hi.y(); y += step) {
      for (double x = lo.x() + 0.25 * step; x < hi.x(); x += step) add(pts, x, y, z);
    }
  }
}

pc::CloudFrameParams openParams() {
  pc::CloudFrameParams p;
  p.volume = wp::Aabb{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(2, 2, 2)};
  p.voxel_size = 0.05;
  p.floor_height = -1.0;  // no floor inside the volume
  p.floor_tolerance = 0.0;
  p.min_cluster_points = 1;
  return p;
}

const pc::CloudFrameStats& run(pc::CloudFrame* frame, const Points& pts,
                               const Eigen::Isometry3f& pose = Eigen::Isometry3f::Identity()) {
  return frame->process(pc::packedXyz(pts.data(), static_cast<std::int64_t>(pts.size() / 3)), pose);
}

// A scanner 0.11 m above the floor at (0.02, 1, 0.11) looking along +x, beams from
// `angle_min` rad in steps of 0.002 rad (`steps` + 1 beams; range 0.05 .. 10 m): a beam whose
// line meets x = 1 (fixed x 1.02) at a y = tan(angle) where `hit(y)` holds sees something there
// (range 1 / cos(angle)), else nothing (inf). `ranges` holds the ranges the scan points into.
template <typename Hit>
pc::ScanView floorScan(double angle_min, int steps, Hit hit, std::vector<float>* ranges) {
  pc::ScanView scan;
  scan.angle_min = static_cast<float>(angle_min);
  scan.angle_increment = 0.002f;
  scan.range_min = 0.05f;
  scan.range_max = 10.0f;
  ranges->clear();
  for (int i = 0; i <= steps; ++i) {
    const double a = angle_min + 0.002 * i;
    ranges->push_back(hit(std::tan(a)) ? static_cast<float>(1.0 / std::cos(a))
                                       : std::numeric_limits<float>::infinity());
  }
  scan.ranges = ranges->data();
  scan.count = static_cast<std::int64_t>(ranges->size());
  return scan;
}

// The floor scanner's pose and a frame with the floor at z 0 (tolerance 0.02 m).
Eigen::Isometry3f floorScannerPose() {
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translate(Eigen::Vector3f(0.02f, 1.0f, 0.11f));
  return pose;
}

pc::CloudFrameParams floorParams() {
  pc::CloudFrameParams p = openParams();
  p.floor_height = 0.0;
  p.floor_tolerance = 0.02;
  return p;
}

// --- voxels ---------------------------------------------------------------------------

TEST(CloudFrame, VoxelCountOfABoxIsItsVolumeInVoxels) {
  pc::CloudFrame frame(openParams());
  Points pts;
  // [0.10, 0.40) x [0.20, 0.35) x [0.50, 0.75): 6 x 3 x 5 voxels of 5 cm.
  fillBox(&pts, {0.10, 0.20, 0.50}, {0.40, 0.35, 0.75}, 0.01);
  const auto& s = run(&frame, pts);
  EXPECT_EQ(s.kept, static_cast<std::int64_t>(pts.size() / 3));
  EXPECT_EQ(s.voxels, 6 * 3 * 5);
  ASSERT_EQ(s.clusters, 1);
  const pc::Detection& d = frame.detections()[0];
  EXPECT_NEAR(d.size.x(), 0.30, 1e-5);
  EXPECT_NEAR(d.size.y(), 0.15, 1e-5);
  EXPECT_NEAR(d.size.z(), 0.25, 1e-5);
  EXPECT_NEAR(d.centre.x(), 0.25, 1e-5);
  EXPECT_NEAR(d.centre.y(), 0.275, 1e-5);
  EXPECT_NEAR(d.centre.z(), 0.625, 1e-5);
  EXPECT_EQ(d.points, s.kept);
  EXPECT_EQ(d.voxels, 90);
}

TEST(CloudFrame, VoxelCountOfASphereShellMatchesASetOfCells) {
  pc::CloudFrame frame(openParams());
  Points pts;
  std::set<std::tuple<long, long, long>> cells;  // the oracle: floor(p / 5 cm) in double
  wp_test::Rng rng(7);
  const Eigen::Vector3d c(1.0, 1.0, 1.0);
  for (int i = 0; i < 20000; ++i) {
    Eigen::Vector3d u = rng.vector(-1, 1);
    if (u.norm() < 1e-3) continue;
    const Eigen::Vector3d p = c + 0.4 * u.normalized();
    const Eigen::Vector3d q = p / 0.05;
    // Points within 1e-4 voxel of a face could land on either side in float: left out.
    if (((q.array() - q.array().round()).abs() < 1e-4).any()) continue;
    add(&pts, p.x(), p.y(), p.z());
    cells.emplace(std::floor(q.x()), std::floor(q.y()), std::floor(q.z()));
  }
  const auto& s = run(&frame, pts);
  EXPECT_EQ(s.voxels, static_cast<std::int64_t>(cells.size()));
  EXPECT_EQ(s.clusters, 1);  // a closed shell is connected
}

// --- clusters ---------------------------------------------------------------------------

TEST(CloudFrame, TwoBlobsWithAnEmptyVoxelBetweenAreTwoClusters) {
  pc::CloudFrame frame(openParams());
  Points pts;
  fillBox(&pts, {0.20, 0.20, 0.20}, {0.40, 0.40, 0.40}, 0.01);
  fillBox(&pts, {0.45, 0.20, 0.20}, {0.60, 0.40, 0.40}, 0.01);  // one empty voxel column: x in [0.40, 0.45)
  const auto& s = run(&frame, pts);
  ASSERT_EQ(s.clusters, 2);
  float widths[2] = {frame.detections()[0].size.x(), frame.detections()[1].size.x()};
  std::sort(widths, widths + 2);
  EXPECT_NEAR(widths[0], 0.15, 1e-5);
  EXPECT_NEAR(widths[1], 0.20, 1e-5);
}

TEST(CloudFrame, BlobsTouchingAtACornerOrAnEdgeAreOneCluster) {
  for (int touching = 0; touching < 2; ++touching) {
    pc::CloudFrame frame(openParams());
    Points pts;
    fillBox(&pts, {0.20, 0.20, 0.20}, {0.30, 0.30, 0.30}, 0.01);
    // The second cube shares only a corner (touching 0) or an edge (1) of its voxels.
    const double y = touching == 0 ? 0.30 : 0.20;
    fillBox(&pts, {0.30, y, 0.30}, {0.40, y + 0.10, 0.40}, 0.01);
    const auto& s = run(&frame, pts);
    EXPECT_EQ(s.clusters, 1) << "touching " << touching;
    EXPECT_EQ(s.voxels, 16);
  }
}

TEST(CloudFrame, ClustersBelowMinPointsAreDroppedAndCounted) {
  auto p = openParams();
  p.min_cluster_points = 5;
  pc::CloudFrame frame(p);
  Points pts;
  add(&pts, 0.51, 0.51, 0.51);  // a lone point: noise
  fillBox(&pts, {1.0, 1.0, 1.0}, {1.05, 1.05, 1.05}, 0.01);  // 125 points
  const auto& s = run(&frame, pts);
  EXPECT_EQ(s.clusters, 1);
  EXPECT_EQ(s.clusters_small, 1);
  EXPECT_EQ(frame.detections()[0].points, 125);
}

TEST(CloudFrame, ClustersBeyondCapacityAreCountedAsOverflow) {
  auto p = openParams();
  p.max_clusters = 3;
  pc::CloudFrame frame(p);
  Points pts;
  for (int i = 0; i < 5; ++i) add(&pts, 0.11 + 0.2 * i, 0.11, 0.11);
  const auto& s = run(&frame, pts);
  EXPECT_EQ(s.clusters, 3);
  EXPECT_EQ(s.clusters_overflow, 2);
}

TEST(CloudFrame, NoMemoryBetweenFrames) {
  pc::CloudFrame frame(openParams());
  Points blob;
  fillBox(&blob, {0.5, 0.5, 0.5}, {0.7, 0.7, 0.9}, 0.02);
  EXPECT_EQ(run(&frame, blob).clusters, 1);
  const Points empty;
  const auto& s = run(&frame, empty);
  EXPECT_EQ(s.clusters, 0);
  EXPECT_EQ(s.voxels, 0);
  EXPECT_EQ(frame.grid().touched().size(), 0u);
  // The same blob again gives the same answer (labels reset).
  EXPECT_EQ(run(&frame, blob).voxels, 4 * 4 * 8);
}

// --- floor, crop, sensor pose ------------------------------------------------------------

TEST(CloudFrame, FloorAndCropCountEveryPointOnce) {
  auto p = openParams();
  p.volume = wp::Aabb{Eigen::Vector3d(-1, -1, -0.5), Eigen::Vector3d(1, 1, 2)};
  p.floor_height = 0.0;
  p.floor_tolerance = 0.03;
  pc::CloudFrame frame(p);
  Points pts;
  add(&pts, 0.1, 0.1, 0.0);     // floor
  add(&pts, 0.1, 0.1, 0.029);   // floor (below tolerance)
  add(&pts, 0.1, 0.1, -0.2);    // floor (below it, inside the volume)
  add(&pts, 0.1, 0.1, 0.031);   // kept
  add(&pts, 1.01, 0.0, 1.0);    // outside: x
  add(&pts, 0.0, -1.2, 1.0);    // outside: y
  add(&pts, 0.0, 0.0, 2.01);    // outside: z
  add(&pts, 0.0, 0.0, -0.6);    // outside: below the volume
  const auto& s = run(&frame, pts);
  EXPECT_EQ(s.floor, 3);
  EXPECT_EQ(s.kept, 1);
  EXPECT_EQ(s.outside_volume, 4);
  EXPECT_EQ(s.non_finite + s.outside_volume + s.floor + s.self + s.near_robot + s.kept, s.points_in);
}

TEST(CloudFrame, SensorPoseMapsPointsIntoTheFixedFrame) {
  pc::CloudFrame frame(openParams());
  Points pts;
  add(&pts, 1.0, 0.0, 0.0);  // 1 m ahead of a sensor at (0.51, 1.03, 1.03) turned 90 deg about z
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translate(Eigen::Vector3f(0.51f, 1.03f, 1.03f));
  pose.rotate(Eigen::AngleAxisf(static_cast<float>(M_PI / 2), Eigen::Vector3f::UnitZ()));
  const auto& s = run(&frame, pts, pose);
  EXPECT_EQ(s.outside_volume, 1);  // (0.51, 2.03, 1.03): beyond the 2 m volume's y
  EXPECT_EQ(s.clusters, 0);
  Points near;
  add(&near, 0.5, 0.0, 0.0);  // -> (0.51, 1.53, 1.03): cell (10, 30, 20)
  const auto& s2 = run(&frame, near, pose);
  ASSERT_EQ(s2.clusters, 1);
  EXPECT_NEAR(frame.detections()[0].centre.x(), 0.525, 1e-5);
  EXPECT_NEAR(frame.detections()[0].centre.y(), 1.525, 1e-5);
  EXPECT_NEAR(frame.detections()[0].centre.z(), 1.025, 1e-5);
}

// --- malformed input --------------------------------------------------------------------

TEST(CloudFrame, NonFinitePointsAreDroppedAndCounted) {
  pc::CloudFrame frame(openParams());
  Points pts;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  add(&pts, nan, 0.5, 0.5);
  add(&pts, 0.5, inf, 0.5);
  add(&pts, 0.5, 0.5, -inf);
  add(&pts, 0.51, 0.51, 0.51);
  const auto& s = run(&frame, pts);
  EXPECT_EQ(s.rejected, pc::CloudRejection::kNone);
  EXPECT_EQ(s.non_finite, 3);
  EXPECT_EQ(s.kept, 1);
  EXPECT_EQ(s.clusters, 1);
}

TEST(CloudFrame, MalformedCloudsAreRejectedByNameAndTheNextFrameWorks) {
  auto p = openParams();
  p.max_points = 1000;
  pc::CloudFrame frame(p);
  Points pts;
  fillBox(&pts, {0.5, 0.5, 0.5}, {0.6, 0.6, 0.6}, 0.02);  // 125 points
  const auto n = static_cast<std::int64_t>(pts.size() / 3);

  pc::CloudView missing = pc::packedXyz(pts.data(), n);
  missing.z_offset = -1;
  EXPECT_EQ(frame.process(missing, Eigen::Isometry3f::Identity()).rejected,
            pc::CloudRejection::kMissingXyz);
  EXPECT_STREQ(pc::cloudRejectionName(frame.stats().rejected), "missing_xyz");
  EXPECT_EQ(frame.detections().size(), 0u);

  pc::CloudView short_data = pc::packedXyz(pts.data(), n);
  short_data.data_size -= 1;
  EXPECT_EQ(frame.process(short_data, Eigen::Isometry3f::Identity()).rejected,
            pc::CloudRejection::kBadLayout);
  EXPECT_STREQ(pc::cloudRejectionName(frame.stats().rejected), "bad_layout");

  pc::CloudView narrow = pc::packedXyz(pts.data(), n);
  narrow.point_step = 8;  // z would lie in the next point
  EXPECT_EQ(frame.process(narrow, Eigen::Isometry3f::Identity()).rejected,
            pc::CloudRejection::kBadLayout);

  pc::CloudView absurd = pc::packedXyz(pts.data(), n);
  absurd.width = 1000;
  absurd.height = 1000;  // 1e6 points > max_points, whatever the data says
  EXPECT_EQ(frame.process(absurd, Eigen::Isometry3f::Identity()).rejected,
            pc::CloudRejection::kTooManyPoints);
  EXPECT_STREQ(pc::cloudRejectionName(frame.stats().rejected), "too_many_points");
  pc::CloudView overflow = absurd;
  overflow.width = overflow.height = std::int64_t(1) << 40;  // the product would overflow
  EXPECT_EQ(frame.process(overflow, Eigen::Isometry3f::Identity()).rejected,
            pc::CloudRejection::kTooManyPoints);

  const auto& s = frame.process(pc::packedXyz(pts.data(), n), Eigen::Isometry3f::Identity());
  EXPECT_EQ(s.rejected, pc::CloudRejection::kNone);
  EXPECT_EQ(s.clusters, 1);
}

TEST(CloudFrame, OrganisedCloudWithStrideAndRowPaddingReadsLikePacked) {
  // 4 x 3 points of 20 bytes (x at 8, y at 12, z at 0, 4 spare bytes), rows padded to 96 bytes.
  const int width = 4, height = 3, step = 20, row = 96;
  std::vector<std::uint8_t> bytes(row * height, 0xff);
  Points packed;
  for (int r = 0; r < height; ++r) {
    for (int c = 0; c < width; ++c) {
      const float xyz[3] = {0.11f + 0.1f * c, 0.31f + 0.1f * r, 0.71f};
      std::uint8_t* p = bytes.data() + r * row + c * step;
      std::memcpy(p + 8, &xyz[0], 4);
      std::memcpy(p + 12, &xyz[1], 4);
      std::memcpy(p + 0, &xyz[2], 4);
      add(&packed, xyz[0], xyz[1], xyz[2]);
    }
  }
  pc::CloudView v;
  v.data = bytes.data();
  v.data_size = static_cast<std::int64_t>(bytes.size());
  v.width = width;
  v.height = height;
  v.point_step = step;
  v.row_step = row;
  v.x_offset = 8;
  v.y_offset = 12;
  v.z_offset = 0;
  pc::CloudFrame a(openParams()), b(openParams());
  const auto& sa = a.process(v, Eigen::Isometry3f::Identity());
  const auto& sb = run(&b, packed);
  EXPECT_EQ(sa.kept, 12);
  EXPECT_EQ(sa.voxels, sb.voxels);
  EXPECT_EQ(sa.clusters, 12);  // 10 cm apart: one empty voxel between neighbours
  EXPECT_EQ(sa.clusters, sb.clusters);
}

TEST(CloudFrame, ParametersAreRefusedByName) {
  auto p = openParams();
  p.voxel_size = 0.0;
  EXPECT_NE(pc::checkCloudFrameParams(p).find("voxel_size"), std::string::npos);
  p = openParams();
  p.volume.upper.x() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(pc::checkCloudFrameParams(p).find("volume"), std::string::npos);
  p = openParams();
  p.max_cells = 1000;  // a 2 m cube of 5 cm voxels has 64 000
  EXPECT_NE(pc::checkCloudFrameParams(p).find("max_cells"), std::string::npos);
  EXPECT_THROW(pc::CloudFrame frame(p), std::invalid_argument);
  p = openParams();
  p.self_padding = -0.1;
  EXPECT_NE(pc::checkCloudFrameParams(p).find("self_padding"), std::string::npos);
  EXPECT_EQ(pc::checkCloudFrameParams(openParams()), "");
}

TEST(CloudFrame, RandomLayoutsAndBytesAreRejectedOrCountedNeverReadOutside) {
  // Random steps, offsets, sizes and bytes (NaN, inf, huge and ordinary floats): each cloud is
  // either rejected by name or every point is counted once; detections lie in the volume.
  // Under AddressSanitizer (scripts/test-sanitizers) a read past the data fails the test: the
  // bytes live in a buffer of exactly data_size.
  auto p = openParams();
  p.max_points = 5000;
  p.volume = wp::Aabb{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)};
  pc::CloudFrame frame(p);
  wp_test::Rng rng(23);
  int rejected = 0, processed = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    pc::CloudView v;
    v.width = rng.integer(0, 80);
    v.height = rng.integer(0, 3) == 0 ? rng.integer(0, 40) : 1;
    v.point_step = rng.integer(0, 40);
    v.row_step = rng.chance(0.8) ? v.width * v.point_step + rng.integer(0, 8) : rng.integer(0, 4000);
    v.x_offset = rng.integer(-1, 36);
    v.y_offset = rng.integer(-1, 36);
    v.z_offset = rng.integer(-1, 36);
    const std::int64_t honest = v.height > 1 ? v.row_step * v.height : v.row_step;
    const std::int64_t size = rng.chance(0.7) ? honest : rng.integer(0, 5000);
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(std::max<std::int64_t>(size, 0)));
    for (std::size_t i = 0; i + 4 <= bytes.size(); i += 4) {
      float f;
      const int kind = rng.integer(0, 9);
      if (kind == 0) {
        f = std::numeric_limits<float>::quiet_NaN();
      } else if (kind == 1) {
        f = std::numeric_limits<float>::infinity();
      } else if (kind == 2) {
        f = 3e38f;
      } else {
        f = static_cast<float>(rng.uniform(-1.5, 1.5));
      }
      std::memcpy(bytes.data() + i, &f, 4);
    }
    v.data = bytes.empty() ? nullptr : bytes.data();
    v.data_size = static_cast<std::int64_t>(bytes.size());
    const Eigen::Isometry3f pose(Eigen::AngleAxisf(static_cast<float>(rng.uniform(-3, 3)), Eigen::Vector3f::UnitZ()));
    const auto& s = frame.process(v, pose);
    if (s.rejected != pc::CloudRejection::kNone) {
      ++rejected;
      EXPECT_EQ(frame.detections().size(), 0u);
      continue;
    }
    ++processed;
    EXPECT_EQ(s.points_in, v.width * v.height);
    EXPECT_EQ(s.non_finite + s.outside_volume + s.floor + s.self + s.near_robot + s.kept, s.points_in);
    for (const pc::Detection& d : frame.detections()) {
      EXPECT_TRUE((d.centre.array() > -1.0f).all() && (d.centre.array() < 1.0f).all());
    }
  }
  EXPECT_GT(rejected, 300);
  EXPECT_GT(processed, 300);
}

// --- the self-filter -----------------------------------------------------------------------

// Oracle: distance from p to a posed box by clamping p's local coordinates onto the box.
double boxDistanceByClamp(const Eigen::Isometry3d& pose, const Eigen::Vector3d& half,
                          const Eigen::Vector3d& p) {
  const Eigen::Vector3d local = pose.inverse() * p;
  Eigen::Vector3d nearest;
  for (int k = 0; k < 3; ++k) nearest[k] = std::min(std::max(local[k], -half[k]), half[k]);
  return (local - nearest).norm();
}

TEST(SelfFilter, RemovesExactlyThePointsInsideTheGrownBox) {
  auto p = openParams();
  p.volume = wp::Aabb{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)};
  p.floor_height = -5.0;
  p.self_padding = 0.04;
  p.near_band = 0.05;
  pc::CloudFrame frame(p);
  pc::SelfLink link;
  link.shape = wp::Shape::box(Eigen::Vector3d(0.2, 0.1, 0.3));
  link.pose = Eigen::Translation3d(0.1, -0.05, 0.2) *
              Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized());
  ASSERT_TRUE(frame.setRobot(&link, 1, 0.0));
  wp_test::Rng rng(11);
  Points pts;
  std::int64_t inside = 0, near = 0, far = 0;
  while (pts.size() < 3 * 50000) {
    const Eigen::Vector3d q = rng.vector(-0.6, 0.8);
    const double d = boxDistanceByClamp(link.pose, link.shape.half_extents, q);
    // Float rounding: points within 10 um of a boundary are left out of the comparison.
    if (std::abs(d - 0.04) < 1e-5 || std::abs(d - 0.09) < 1e-5) continue;
    add(&pts, q.x(), q.y(), q.z());
    if (d <= 0.04) {
      ++inside;
    } else if (d <= 0.09) {
      ++near;
    } else {
      ++far;
    }
  }
  const auto& s = run(&frame, pts);
  EXPECT_GT(inside, 1000);
  EXPECT_EQ(s.self, inside);
  EXPECT_EQ(s.near_robot, near);
  EXPECT_EQ(s.kept, far);
}

TEST(SelfFilter, SphereCylinderAndCapsuleAgainstTheirClosedForms) {
  wp_test::Rng rng(5);
  const wp::Shape shapes[3] = {wp::Shape::sphere(0.15), wp::Shape::cylinder(0.1, 0.4),
                               wp::Shape::capsule(0.08, 0.3)};
  for (const wp::Shape& shape : shapes) {
    pc::SelfFilter filter(4);
    pc::SelfLink link;
    link.shape = shape;
    link.pose = Eigen::Translation3d(0.3, 0.2, 0.1) * Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitX());
    ASSERT_TRUE(filter.setLinks(&link, 1, 0.03, 0.0, 0.05));
    int mismatches = 0, inside = 0;
    for (int i = 0; i < 20000; ++i) {
      const Eigen::Vector3d q = rng.vector(-0.4, 0.9);
      const Eigen::Vector3d l = link.pose.inverse() * q;
      double d = 0.0;  // oracle: written per shape from its definition
      if (shape.type == wp::ShapeType::kSphere) {
        d = std::max(0.0, l.norm() - 0.15);
      } else if (shape.type == wp::ShapeType::kCylinder) {
        const double rho = std::sqrt(l.x() * l.x() + l.y() * l.y());
        const double zc = std::min(std::max(l.z(), -0.2), 0.2);
        const double rc = std::min(rho, 0.1);
        d = std::sqrt((rho - rc) * (rho - rc) + (l.z() - zc) * (l.z() - zc));
      } else {
        const double zc = std::min(std::max(l.z(), -0.15), 0.15);
        d = std::max(0.0, (l - Eigen::Vector3d(0, 0, zc)).norm() - 0.08);
      }
      if (std::abs(d - 0.03) < 1e-5 || std::abs(d - 0.08) < 1e-5) continue;
      const pc::SelfVerdict want = d <= 0.03   ? pc::SelfVerdict::kSelf
                                   : d <= 0.08 ? pc::SelfVerdict::kNear
                                               : pc::SelfVerdict::kClear;
      inside += want == pc::SelfVerdict::kSelf;
      mismatches += filter.classify(q.cast<float>()) != want;
    }
    EXPECT_EQ(mismatches, 0) << "shape type " << static_cast<int>(shape.type);
    EXPECT_GT(inside, 100);
  }
}

TEST(SelfFilter, AMovingLinkGrowsBySpeedTimesTheStampOffset) {
  pc::SelfFilter filter(2);
  pc::SelfLink link;
  link.shape = wp::Shape::sphere(0.1);
  link.speed = 2.0;  // m/s
  // Cloud 50 ms after the pose (and before it: the same growth): 0.02 + 2 x 0.05 = 0.12 m.
  for (const double offset : {0.05, -0.05}) {
    ASSERT_TRUE(filter.setLinks(&link, 1, 0.02, offset, 0.05));
    EXPECT_DOUBLE_EQ(filter.growth(0), 0.12);
    EXPECT_EQ(filter.classify(Eigen::Vector3f(0.219f, 0, 0)), pc::SelfVerdict::kSelf);
    EXPECT_EQ(filter.classify(Eigen::Vector3f(0, 0.221f, 0)), pc::SelfVerdict::kNear);
    EXPECT_EQ(filter.classify(Eigen::Vector3f(0, 0, -0.269f)), pc::SelfVerdict::kNear);
    EXPECT_EQ(filter.classify(Eigen::Vector3f(0.271f, 0, 0)), pc::SelfVerdict::kClear);
  }
  // The speed bound of a turning link: |v| + |w| x bounding radius.
  wp::BodyMotion m;
  m.linear_velocity = Eigen::Vector3d(0.3, 0.4, 0.0);  // 0.5 m/s
  m.angular_velocity = Eigen::Vector3d(0.0, 0.0, 2.0);
  EXPECT_DOUBLE_EQ(pc::linkSpeedBound(m, wp::Shape::capsule(0.05, 0.3)), 0.5 + 2.0 * 0.2);
}

TEST(SelfFilter, RefusesBadLinksAndThenFiltersNothing) {
  pc::SelfFilter filter(1);
  pc::SelfLink links[2];
  EXPECT_FALSE(filter.setLinks(links, 2, 0.02, 0.0, 0.05));  // beyond capacity
  EXPECT_EQ(filter.count(), 0);
  links[0].speed = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(filter.setLinks(links, 1, 0.02, 0.0, 0.05));
  links[0].speed = 0.0;
  EXPECT_FALSE(filter.setLinks(links, 1, 0.02, std::numeric_limits<double>::infinity(), 0.05));
  EXPECT_EQ(filter.classify(Eigen::Vector3f::Zero()), pc::SelfVerdict::kClear);
  EXPECT_TRUE(filter.setLinks(links, 1, 0.02, 0.0, 0.05));
  EXPECT_EQ(filter.classify(Eigen::Vector3f::Zero()), pc::SelfVerdict::kSelf);
}

TEST(CloudFrame, DefaultVolumeIsTheRobotsReachPlusR) {
  pc::SelfLink links[2];
  links[0].shape = wp::Shape::sphere(0.1);
  links[0].pose = Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.5));
  links[1].shape = wp::Shape::box(Eigen::Vector3d(0.3, 0.4, 0.0));  // bounding radius 0.5
  links[1].pose = Eigen::Isometry3d(Eigen::Translation3d(0.6, 0, 0.3));
  const Eigen::Vector3d base(0, 0, 0.3);
  const double reach = pc::robotReach(links, 2, base);
  EXPECT_DOUBLE_EQ(reach, 0.6 + 0.5);
  const wp::Aabb v = pc::defaultMonitoredVolume(base, reach, 1.4, 0.0);
  EXPECT_DOUBLE_EQ(v.lower.x(), -2.5);
  EXPECT_DOUBLE_EQ(v.upper.y(), 2.5);
  EXPECT_DOUBLE_EQ(v.upper.z(), 2.8);
  EXPECT_DOUBLE_EQ(v.lower.z(), 0.0);  // cut at the floor
}

// --- laser scans -----------------------------------------------------------------------------

TEST(LaserScan, BeamsBecomeColumnsOverTheBand) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const float ranges[6] = {1.0f, 2.0f, nan, inf, 0.01f, 31.0f};
  pc::ScanView scan;
  scan.ranges = ranges;
  scan.count = 6;
  scan.angle_min = static_cast<float>(-M_PI / 2);
  scan.angle_increment = static_cast<float>(M_PI / 2);
  scan.range_min = 0.05f;
  scan.range_max = 30.0f;
  pc::ScanBand band{0.0f, 0.2f, 0.05f};
  EXPECT_EQ(band.layers(), 5);
  std::vector<float> xyz(3 * 100);
  const pc::ScanResult r = pc::scanToPoints(scan, band, xyz.data(), 100);
  EXPECT_FALSE(r.refused);
  EXPECT_EQ(r.beams, 2);
  EXPECT_EQ(r.invalid, 4);  // NaN, inf, below range_min, above range_max
  ASSERT_EQ(r.points, 10);
  // Beam 0 at -90 deg, 1 m: (0, -1); beam 1 at 0 deg, 2 m: (2, 0).
  for (int k = 0; k < 5; ++k) {
    EXPECT_NEAR(xyz[3 * k + 0], 0.0f, 1e-6);
    EXPECT_NEAR(xyz[3 * k + 1], -1.0f, 1e-6);
    EXPECT_NEAR(xyz[3 * k + 2], 0.05f * k, 1e-6);
    EXPECT_NEAR(xyz[15 + 3 * k + 0], 2.0f, 1e-6);
    EXPECT_NEAR(xyz[15 + 3 * k + 1], 0.0f, 1e-6);
  }
  // Out of room: truncated, never past the capacity.
  const pc::ScanResult small = pc::scanToPoints(scan, band, xyz.data(), 7);
  EXPECT_TRUE(small.truncated);
  EXPECT_EQ(small.points, 5);
  // A bad band is refused.
  EXPECT_TRUE(pc::scanToPoints(scan, pc::ScanBand{0.0f, 1.0f, 0.0f}, xyz.data(), 100).refused);
}

TEST(LaserScan, TwoLegsSeenByAFloorScannerAreTwoClusters) {
  // A scanner 0.11 m above the floor at (0.02, 1, 0.11) sees two legs (0.1 m wide) 1 m ahead, 0.3 m
  // apart; the band extrudes them from 0.1 m below the scan plane to 0.7 m above.
  std::vector<float> ranges;
  const pc::ScanView scan = floorScan(-0.5, 500, [](double y) {
    return (y > -0.2 && y < -0.1) || (y > 0.1 && y < 0.2);  // the legs
  }, &ranges);
  std::vector<float> xyz(3 * 20000);
  const pc::ScanResult r = pc::scanToPoints(scan, pc::ScanBand{-0.1f, 0.7f, 0.05f}, xyz.data(), 20000);
  ASSERT_FALSE(r.truncated);
  pc::CloudFrame frame(floorParams());
  const auto& s = frame.process(pc::packedXyz(xyz.data(), r.points), floorScannerPose());
  EXPECT_EQ(s.clusters, 2);
  EXPECT_GT(s.floor, 0);  // the band's lowest layer, at z 0.01: below the floor tolerance
  for (const pc::Detection& d : frame.detections()) {
    // Points at z 0.06 .. 0.81: cells 1 .. 16, [0.05, 0.85).
    EXPECT_NEAR(d.size.z(), 0.80, 1e-5);
    EXPECT_NEAR(d.centre.z(), 0.45, 1e-5);
    EXPECT_NEAR(d.size.x(), 0.05, 1e-5);  // every leg point at x = 1.02
  }
}

TEST(LaserScan, ABeamThatHitsTheRobotDropsItsWholeColumn) {
  // The scanner at (0.02, 1, 0.11) looking along +x: beams at y < 0 (fixed y < 1) hit the
  // robot's base, a 0.2 m box at (1.02 + 0.1, 0.85, 0.3) reaching z 0.6; beams at y > 0 a leg.
  // Without the robot both are clusters; with it, the base's columns (which reach 0.8 m, above
  // the base) go whole and only the leg stays.
  std::vector<float> ranges;
  const pc::ScanView scan = floorScan(-0.3, 300, [](double y) {
    return (y > -0.24 && y < -0.06) || (y > 0.1 && y < 0.2);  // the base, the leg
  }, &ranges);
  const pc::ScanBand band{-0.1f, 0.7f, 0.025f};
  auto p = floorParams();
  p.self_padding = 0.03;
  pc::CloudFrame frame(p);
  const Eigen::Isometry3f pose = floorScannerPose();
  EXPECT_EQ(frame.processScan(scan, band, pose).clusters, 2);
  const std::int64_t all = frame.stats().points_in;
  pc::SelfLink base;
  base.shape = wp::Shape::box(Eigen::Vector3d(0.1, 0.1, 0.3));
  base.pose = Eigen::Isometry3d(Eigen::Translation3d(1.12, 0.85, 0.3));
  ASSERT_TRUE(frame.setRobot(&base, 1, 0.0));
  const auto& s = frame.processScan(scan, band, pose);
  EXPECT_EQ(s.clusters, 1);
  EXPECT_GT(frame.detections()[0].centre.y(), 1.0f);  // the leg
  EXPECT_EQ(s.points_in, all);
  EXPECT_EQ(s.self % band.layers(), 0);  // whole columns
  EXPECT_GT(s.self, 0);
  EXPECT_EQ(s.non_finite + s.outside_volume + s.floor + s.self + s.near_robot + s.kept, s.points_in);
  // A refused band is a named rejection.
  EXPECT_EQ(frame.processScan(scan, pc::ScanBand{0.0f, 1.0f, -1.0f}, pose).rejected,
            pc::CloudRejection::kBadLayout);
}

// --- no allocation per frame -------------------------------------------------------------------

TEST(CloudFrame, SteadyStateFramesAllocateNothing) {
  auto p = openParams();
  p.volume = wp::Aabb{Eigen::Vector3d(-1, -1, -1), Eigen::Vector3d(1, 1, 1)};
  pc::CloudFrame frame(p);
  pc::SelfLink link;
  link.shape = wp::Shape::capsule(0.05, 0.4);
  ASSERT_TRUE(frame.setRobot(&link, 1, 0.01));
  Points pts;
  wp_test::Rng rng(3);
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d q = rng.vector(-1.2, 1.2);
    add(&pts, q.x(), q.y(), q.z());
  }
  run(&frame, pts);
  const long before = wp_test::allocationCount();
  for (int i = 0; i < 3; ++i) {
    ASSERT_TRUE(frame.setRobot(&link, 1, 0.02 * i));
    run(&frame, pts);
  }
  EXPECT_EQ(wp_test::allocationCount() - before, 0);
  EXPECT_GT(frame.stats().clusters, 0);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
