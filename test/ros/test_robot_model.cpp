// Robot bodies from URDF collision elements: meshes loaded with geometric_shapes and
// resource_retriever, bounded by an oriented box; elements that cannot be modelled are
// listed, never dropped. No master.
//
// Oracles: the fixture box is known exactly (its corners are dyadic, so every format and
// float parse carries them without rounding); containment is checked against those
// corners and against the loaded vertices; tightness against the true box, analytic
// minima (prism), and a brute-force search over sampled orientations.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <unistd.h>

#include "workspace_proximity/ros/robot_model.hpp"

namespace wp = workspace_proximity;

namespace {

const std::string kFixtures = WP_FIXTURES_DIR;
const std::string kPackageFixtures = "package://workspace_proximity/test/ros/fixtures";

// The box of the rotated_box.* fixtures: rotation (-15 0 20; 16 -15 12; 12 20 9) / 25 (from
// the quaternion (1, 2, 2, 4) / 5), half extents 25 * (1/128, 1/256, 1/512), centre below.
Eigen::Matrix3d fixtureRotation() {
  Eigen::Matrix3d r;
  r << -15, 0, 20, 16, -15, 12, 12, 20, 9;
  return r / 25.0;
}
const Eigen::Vector3d kFixtureHalf(25.0 / 128, 25.0 / 256, 25.0 / 512);
const Eigen::Vector3d kFixtureCentre(0.125, -0.0625, 0.25);
double fixtureVolume() { return 8.0 * kFixtureHalf.prod(); }

// Corner i has sign +1 on axis a when bit (2 - a) of i is set (the fixtures' vertex order).
Eigen::Matrix3Xd boxCorners(const Eigen::Matrix3d& r, const Eigen::Vector3d& half,
                            const Eigen::Vector3d& centre) {
  Eigen::Matrix3Xd c(3, 8);
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d s((i & 4) ? 1 : -1, (i & 2) ? 1 : -1, (i & 1) ? 1 : -1);
    c.col(i) = centre + r * s.cwiseProduct(half);
  }
  return c;
}
Eigen::Matrix3Xd fixtureCorners() { return boxCorners(fixtureRotation(), kFixtureHalf, kFixtureCentre); }

// Triangles of the fixtures (outward, counter-clockwise), indices into boxCorners().
const std::array<std::array<int, 3>, 12> kBoxTriangles = {{{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5},
                                                            {0, 4, 5}, {0, 5, 1}, {2, 3, 7}, {2, 7, 6},
                                                            {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}}};

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n;
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
}

double aabbVolume(const Eigen::Matrix3Xd& pts) {
  return (pts.rowwise().maxCoeff() - pts.rowwise().minCoeff()).prod();
}

// The independent tightness oracle: the smallest volume of the box of `pts` along the axes
// of `samples` random orientations (and the points' own axes). Plain loops: it runs
// millions of points under the sanitizers too.
double bestSampledVolume(const Eigen::Matrix3Xd& pts, int samples, std::mt19937& rng) {
  double best = aabbVolume(pts);
  const double* p = pts.data();
  const Eigen::Index n = pts.cols();
  for (int s = 0; s < samples; ++s) {
    const Eigen::Matrix3d r = randomRotation(rng);
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (Eigen::Index i = 0; i < n; ++i) {
      const double x = p[3 * i], y = p[3 * i + 1], z = p[3 * i + 2];
      for (int a = 0; a < 3; ++a) {
        const double d = r(0, a) * x + r(1, a) * y + r(2, a) * z;
        lo[a] = std::min(lo[a], d);
        hi[a] = std::max(hi[a], d);
      }
    }
    best = std::min(best, (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]));
  }
  return best;
}

// Largest amount by which a point lies outside the box (<= 0 when all are inside).
double worstOutside(const Eigen::Isometry3d& pose, const Eigen::Vector3d& half, const Eigen::Matrix3Xd& pts) {
  double worst = -std::numeric_limits<double>::infinity();
  const Eigen::Isometry3d inv = pose.inverse();
  for (Eigen::Index i = 0; i < pts.cols(); ++i) {
    const Eigen::Vector3d local = inv * Eigen::Vector3d(pts.col(i));
    worst = std::max(worst, (local.cwiseAbs() - half).maxCoeff());
  }
  return worst;
}

Eigen::Vector3d sorted(Eigen::Vector3d v) {
  std::sort(v.data(), v.data() + 3);
  return v;
}

Eigen::Matrix3Xd transformed(const Eigen::Isometry3d& t, const Eigen::Matrix3Xd& pts) {
  Eigen::Matrix3Xd out(3, pts.cols());
  for (Eigen::Index i = 0; i < pts.cols(); ++i) out.col(i) = t * Eigen::Vector3d(pts.col(i));
  return out;
}

// A fresh folder under /tmp, removed with its files at the end of the test.
class TempDir {
 public:
  TempDir() {
    char name[] = "/tmp/wp_robot_model_XXXXXX";
    if (!mkdtemp(name)) throw std::runtime_error("mkdtemp failed");
    path_ = name;
  }
  ~TempDir() {
    for (const std::string& f : files_) std::remove(f.c_str());
    rmdir(path_.c_str());
  }
  std::string write(const std::string& name, const std::string& content) {
    const std::string file = path_ + "/" + name;
    std::ofstream(file, std::ios::binary) << content;
    files_.push_back(file);
    return file;
  }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<std::string> files_;
};

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A binary STL of the fixture box, written here (80-byte header, count, 50 bytes a triangle).
std::string binaryStl(const Eigen::Matrix3Xd& corners) {
  std::string out(80, ' ');
  out.replace(0, 30, "workspace_proximity test box  ");
  const std::uint32_t n = kBoxTriangles.size();
  out.append(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : kBoxTriangles) {
    const Eigen::Vector3d a = corners.col(t[0]), b = corners.col(t[1]), c = corners.col(t[2]);
    const Eigen::Vector3f normal = (b - a).cross(c - a).normalized().cast<float>();
    out.append(reinterpret_cast<const char*>(normal.data()), 12);
    for (int k : t) {
      const Eigen::Vector3f v = corners.col(k).cast<float>();
      out.append(reinterpret_cast<const char*>(v.data()), 12);
    }
    out.append(2, '\0');
  }
  return out;
}

std::string urdfWithCollisions(const std::string& link, const std::string& collisions) {
  return "<?xml version=\"1.0\"?><robot name=\"r\"><link name=\"" + link + "\">" + collisions +
         "</link></robot>";
}

std::string meshCollision(const std::string& url, const std::string& origin = "",
                          const std::string& scale = "") {
  return "<collision>" + origin + "<geometry><mesh filename=\"" + url + "\"" +
         (scale.empty() ? std::string() : " scale=\"" + scale + "\"") + "/></geometry></collision>";
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// ---------------------------------------------------------------------------
// orientedBoundingBox on point sets with known answers.

TEST(OrientedBox, RotatedBoxCornersGiveTheBoxExactly) {
  const Eigen::Matrix3Xd corners = fixtureCorners();
  const wp::OrientedBox box = wp::orientedBoundingBox(corners);
  EXPECT_LE(worstOutside(box.pose, box.half_extents, corners), 1e-12);
  EXPECT_NEAR(box.volume(), fixtureVolume(), 1e-12 * fixtureVolume());
  EXPECT_TRUE(sorted(box.half_extents).isApprox(sorted(kFixtureHalf), 1e-12));
  EXPECT_TRUE(box.pose.translation().isApprox(kFixtureCentre, 1e-12));
  EXPECT_TRUE(box.pose.linear().isUnitary(1e-12));
  EXPECT_NEAR(box.pose.linear().determinant(), 1.0, 1e-12);
  // The box of the vertices in the mesh frame is 6.6 times larger.
  EXPECT_GT(aabbVolume(corners), 6.0 * box.volume());
}

TEST(OrientedBox, BoxFilledWithPointsUnderRandomRotations) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> size(0.01, 2.0), unit(-1.0, 1.0), place(-5.0, 5.0);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix3d r = randomRotation(rng);
    const Eigen::Vector3d half(size(rng), size(rng), size(rng));
    const Eigen::Vector3d centre(place(rng), place(rng), place(rng));
    Eigen::Matrix3Xd pts(3, 8 + 300);
    pts.leftCols(8) = boxCorners(r, half, centre);
    for (int i = 8; i < pts.cols(); ++i) {
      pts.col(i) = centre + r * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).cwiseProduct(half);
    }
    const wp::OrientedBox box = wp::orientedBoundingBox(pts);
    EXPECT_LE(worstOutside(box.pose, box.half_extents, pts), 1e-9) << trial;
    EXPECT_NEAR(box.volume(), 8.0 * half.prod(), 1e-9 * 8.0 * half.prod()) << trial;
  }
}

TEST(OrientedBox, OctagonalPrismGivesTheFlushSquare) {
  // A regular octagon of circumradius r, extruded by L > 2 r: the smallest box has its long
  // axis along the prism and a square cross-section flush with four sides, 2 r cos(pi/8) wide.
  std::mt19937 rng(11);
  const double r = 0.1, length = 0.5;
  const double expected = std::pow(2.0 * r * std::cos(M_PI / 8.0), 2) * length;
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::Matrix3d rot = randomRotation(rng);
    Eigen::Matrix3Xd pts(3, 16);
    for (int i = 0; i < 8; ++i) {
      const double a = M_PI / 4.0 * i + 0.3;
      for (int end = 0; end < 2; ++end) {
        pts.col(2 * i + end) =
            rot * Eigen::Vector3d(r * std::cos(a), r * std::sin(a), end ? length : 0.0) + Eigen::Vector3d(1, 2, 3);
      }
    }
    const wp::OrientedBox box = wp::orientedBoundingBox(pts);
    EXPECT_LE(worstOutside(box.pose, box.half_extents, pts), 1e-9) << trial;
    EXPECT_NEAR(box.volume(), expected, 1e-9 * expected) << trial;
  }
}

TEST(OrientedBox, RandomCloudsAreAsTightAsABruteForceSearch) {
  // Independent oracle: the smallest box of the points over 20 000 random orientations.
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  double worst_ratio = 0.0;
  const std::array<int, 5> counts = {6, 12, 40, 150, 600};
  for (int cloud = 0; cloud < 40; ++cloud) {
    const Eigen::Vector3d spread(0.05 + 0.5 * std::abs(n(rng)), 0.05 + 0.3 * std::abs(n(rng)),
                                 0.02 + 0.1 * std::abs(n(rng)));
    const Eigen::Matrix3d rot = randomRotation(rng);
    Eigen::Matrix3Xd pts(3, counts[cloud % counts.size()]);
    for (int i = 0; i < pts.cols(); ++i) {
      pts.col(i) = rot * Eigen::Vector3d(n(rng), n(rng), n(rng)).cwiseProduct(spread);
    }
    const wp::OrientedBox box = wp::orientedBoundingBox(pts);
    EXPECT_LE(worstOutside(box.pose, box.half_extents, pts), 1e-9) << cloud;
    const double brute = bestSampledVolume(pts, 20000, rng);
    EXPECT_LE(box.volume(), aabbVolume(pts) * (1 + 1e-12)) << cloud;
    EXPECT_LE(box.volume(), brute) << cloud;
    worst_ratio = std::max(worst_ratio, box.volume() / brute);
  }
  std::printf("largest volume / best of 20 000 sampled orientations: %.4f\n", worst_ratio);
}

TEST(OrientedBox, ManyPointsAreSearchedThroughTheirSupportPoints) {
  // Above 1 024 points the search sees only the extreme points along 512 directions: a box
  // stays exact (its corners are extreme), a cloud stays at least as tight as sampling.
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::normal_distribution<double> n;
  const Eigen::Matrix3d rot = randomRotation(rng);
  const Eigen::Vector3d half(0.4, 0.15, 0.07), centre(0.2, -1.0, 0.5);
  Eigen::Matrix3Xd filled(3, 5000);
  filled.leftCols(8) = boxCorners(rot, half, centre);
  for (int i = 8; i < filled.cols(); ++i) {
    filled.col(i) = centre + rot * Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).cwiseProduct(half);
  }
  const wp::OrientedBox box = wp::orientedBoundingBox(filled);
  EXPECT_LE(worstOutside(box.pose, box.half_extents, filled), 1e-9);
  EXPECT_NEAR(box.volume(), 8.0 * half.prod(), 1e-9 * 8.0 * half.prod());

  Eigen::Matrix3Xd cloud(3, 3000);
  for (int i = 0; i < cloud.cols(); ++i) {
    cloud.col(i) = rot * Eigen::Vector3d(0.3 * n(rng), 0.1 * n(rng), 0.05 * n(rng));
  }
  const wp::OrientedBox cloud_box = wp::orientedBoundingBox(cloud);
  EXPECT_LE(worstOutside(cloud_box.pose, cloud_box.half_extents, cloud), 1e-9);
  const double brute = bestSampledVolume(cloud, 20000, rng);
  EXPECT_LE(cloud_box.volume(), brute);
  std::printf("3 000-point cloud: volume / best of 20 000 sampled orientations: %.4f\n",
              cloud_box.volume() / brute);
}

TEST(OrientedBox, FlatAndDegeneratePointSets) {
  std::mt19937 rng(5);
  const Eigen::Matrix3d rot = randomRotation(rng);
  // A 0.4 x 0.1 rectangle in a tilted plane, with points inside it.
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::Matrix3Xd flat(3, 40);
  for (int i = 0; i < flat.cols(); ++i) {
    const Eigen::Vector3d local = i < 4 ? Eigen::Vector3d((i & 1) ? 0.2 : -0.2, (i & 2) ? 0.05 : -0.05, 0.0)
                                        : Eigen::Vector3d(0.2 * unit(rng), 0.05 * unit(rng), 0.0);
    flat.col(i) = rot * local + Eigen::Vector3d(0.5, 0.0, 1.0);
  }
  const wp::OrientedBox flat_box = wp::orientedBoundingBox(flat);
  EXPECT_LE(worstOutside(flat_box.pose, flat_box.half_extents, flat), 1e-12);
  const Eigen::Vector3d h = sorted(flat_box.half_extents);
  EXPECT_LE(h(0), 1e-12);
  EXPECT_NEAR(h(1), 0.05, 1e-12);
  EXPECT_NEAR(h(2), 0.2, 1e-12);

  Eigen::Matrix3Xd one(3, 3);
  one << 1, 1, 1, 2, 2, 2, 3, 3, 3;  // one point three times
  const wp::OrientedBox point = wp::orientedBoundingBox(one);
  EXPECT_EQ(point.half_extents, Eigen::Vector3d::Zero());
  EXPECT_TRUE(point.pose.translation().isApprox(Eigen::Vector3d(1, 2, 3)));

  Eigen::Matrix3Xd segment(3, 2);
  segment.col(0) = Eigen::Vector3d(0, 0, 0);
  segment.col(1) = Eigen::Vector3d(1, 1, 1);
  const wp::OrientedBox line = wp::orientedBoundingBox(segment);
  EXPECT_LE(worstOutside(line.pose, line.half_extents, segment), 1e-12);
  EXPECT_NEAR(sorted(line.half_extents)(2), 0.5 * std::sqrt(3.0), 1e-12);
  EXPECT_LE(sorted(line.half_extents)(1), 1e-12);
}

// ---------------------------------------------------------------------------
// Mesh files.

TEST(MeshFiles, EveryFormatGivesTheFixtureVertices) {
  TempDir dir;
  const std::vector<std::string> urls = {
      "file://" + kFixtures + "/rotated_box.stl",  // ASCII STL
      "file://" + kFixtures + "/rotated_box.obj",
      "file://" + kFixtures + "/rotated_box.dae",
      "file://" + dir.write("rotated_box_binary.stl", binaryStl(fixtureCorners())),
      kFixtures + "/rotated_box.obj",  // an absolute path works too
      kPackageFixtures + "/rotated_box.stl",
  };
  const Eigen::Matrix3Xd corners = fixtureCorners();
  for (const std::string& url : urls) {
    Eigen::Matrix3Xd v;
    std::string why;
    ASSERT_TRUE(wp::loadMeshVertices(url, Eigen::Vector3d::Ones(), &v, &why)) << url << ": " << why;
    // Each loaded vertex is one of the corners, and each corner is there.
    std::vector<bool> seen(8, false);
    for (Eigen::Index i = 0; i < v.cols(); ++i) {
      int match = -1;
      for (int c = 0; c < 8; ++c) {
        if ((v.col(i) - corners.col(c)).norm() <= 1e-12) match = c;
      }
      ASSERT_GE(match, 0) << url << " vertex " << v.col(i).transpose();
      seen[match] = true;
    }
    EXPECT_EQ(std::count(seen.begin(), seen.end(), true), 8) << url;
  }
}

TEST(MeshFiles, ScaleAndColladaUnitAreApplied) {
  TempDir dir;
  const Eigen::Vector3d scale(2.0, 0.5, 1.5);
  const Eigen::Matrix3Xd corners = fixtureCorners();
  Eigen::Matrix3Xd v;
  std::string why;
  ASSERT_TRUE(wp::loadMeshVertices("file://" + kFixtures + "/rotated_box.obj", scale, &v, &why)) << why;
  for (Eigen::Index i = 0; i < v.cols(); ++i) {
    double nearest = 1e9;
    for (int c = 0; c < 8; ++c) nearest = std::min(nearest, (v.col(i) - scale.cwiseProduct(corners.col(c))).norm());
    EXPECT_LE(nearest, 1e-12);
  }
  // A COLLADA file in half metres is half as large.
  std::string dae = readFile(kFixtures + "/rotated_box.dae");
  const std::string unit = "meter=\"1\"";
  ASSERT_TRUE(contains(dae, unit));
  dae.replace(dae.find(unit), unit.size(), "meter=\"0.5\"");
  ASSERT_TRUE(wp::loadMeshVertices("file://" + dir.write("half_metres.dae", dae), Eigen::Vector3d::Ones(), &v, &why))
      << why;
  for (Eigen::Index i = 0; i < v.cols(); ++i) {
    double nearest = 1e9;
    for (int c = 0; c < 8; ++c) nearest = std::min(nearest, (v.col(i) - 0.5 * corners.col(c)).norm());
    EXPECT_LE(nearest, 1e-12);
  }
}

TEST(MeshFiles, UnusableFilesSayWhichAndWhy) {
  TempDir dir;
  struct Case {
    std::string url;
    std::vector<std::string> parts;  // all must be in the reason
  };
  const std::string missing = "file://" + dir.path() + "/missing.stl";
  const std::vector<Case> cases = {
      {missing, {"mesh '" + missing + "'", "cannot be retrieved", "missing.stl"}},
      {kPackageFixtures + "/missing_mesh.stl", {"fixtures/missing_mesh.stl", "cannot be retrieved"}},
      {"package://no_such_package_wp/meshes/a.stl", {"no_such_package_wp", "cannot be retrieved"}},
      {"file://" + kFixtures + "/not_a_mesh.stl", {"not_a_mesh.stl", "not a mesh assimp can read", "STL"}},
      {"file://" + dir.write("notes.txt", "just words\n"), {"notes.txt", "not a mesh assimp can read"}},
      {"file://" + dir.write("empty.stl", ""), {"empty.stl", "empty"}},
      {"file://" + dir.write("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n"), {"points.obj", "no triangles"}},
      {"meshes/relative.stl", {"meshes/relative.stl", "relative path"}},
  };
  for (const Case& c : cases) {
    Eigen::Matrix3Xd v;
    std::string why;
    bool loaded = true;
    EXPECT_NO_THROW(loaded = wp::loadMeshVertices(c.url, Eigen::Vector3d::Ones(), &v, &why)) << c.url;
    EXPECT_FALSE(loaded) << c.url;
    for (const std::string& part : c.parts) EXPECT_TRUE(contains(why, part)) << c.url << ": " << why;
  }
}

// ---------------------------------------------------------------------------
// bodiesFromUrdf.

// The collision origin used below, and the corners of the fixture box seen in the link.
const char* kOrigin = "<origin xyz=\"0.3 -0.2 1.1\" rpy=\"0.4 -0.7 2.0\"/>";
Eigen::Isometry3d originPose() {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.translation() = Eigen::Vector3d(0.3, -0.2, 1.1);
  // URDF rpy: fixed axes x, y, z, i.e. Rz(yaw) Ry(pitch) Rx(roll).
  t.linear() = (Eigen::AngleAxisd(2.0, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return t;
}

TEST(BodiesFromUrdf, MeshesInEveryFormatAreBoundedByTheirOwnBox) {
  TempDir dir;
  const std::vector<std::string> urls = {
      "file://" + kFixtures + "/rotated_box.stl",
      "file://" + kFixtures + "/rotated_box.obj",
      "file://" + kFixtures + "/rotated_box.dae",
      "file://" + dir.write("rotated_box_binary.stl", binaryStl(fixtureCorners())),
      kPackageFixtures + "/rotated_box.dae",
  };
  const Eigen::Matrix3Xd in_link = transformed(originPose(), fixtureCorners());
  for (const std::string& url : urls) {
    const wp::UrdfBodies result = wp::bodiesFromUrdf(urdfWithCollisions("arm", meshCollision(url, kOrigin)));
    ASSERT_EQ(result.bodies.size(), 1u) << url << ": " << (result.unmodelled.empty() ? "" : result.unmodelled[0].reason);
    EXPECT_TRUE(result.unmodelled.empty());
    const wp::RobotBodySpec& b = result.bodies[0];
    EXPECT_EQ(b.name, "arm");
    EXPECT_EQ(b.frame, "arm");
    ASSERT_EQ(b.shape.type, wp::ShapeType::kBox);
    // Every vertex inside; the volume is the true box's, while the box of the vertices in
    // the mesh frame (what the node used before) is 6.6 times larger, and in the link frame
    // 2.7 times.
    EXPECT_LE(worstOutside(b.offset, b.shape.half_extents, in_link), 1e-9) << url;
    const double volume = 8.0 * b.shape.half_extents.prod();
    EXPECT_NEAR(volume, fixtureVolume(), 1e-9 * fixtureVolume()) << url;
    EXPECT_GT(aabbVolume(fixtureCorners()), 6.0 * volume) << url;
    EXPECT_GT(aabbVolume(in_link), 2.0 * volume) << url;
    EXPECT_TRUE(b.offset.linear().isUnitary(1e-12));
  }
}

TEST(BodiesFromUrdf, ScaleIsAppliedAndTheBoxStaysTight) {
  const std::string url = "file://" + kFixtures + "/rotated_box.stl";
  // Non-uniform: the scaled box is a parallelepiped; its box must hold it, be no larger
  // than the box of its vertices, and no smaller than its volume (1.5 times the box's).
  const Eigen::Vector3d scale(2.0, 0.5, 1.5);
  const wp::UrdfBodies skewed =
      wp::bodiesFromUrdf(urdfWithCollisions("arm", meshCollision(url, kOrigin, "2 0.5 1.5")));
  ASSERT_EQ(skewed.bodies.size(), 1u);
  const Eigen::Matrix3Xd scaled = scale.asDiagonal() * fixtureCorners();
  const wp::RobotBodySpec& b = skewed.bodies[0];
  EXPECT_LE(worstOutside(b.offset, b.shape.half_extents, transformed(originPose(), scaled)), 1e-9);
  const double volume = 8.0 * b.shape.half_extents.prod();
  EXPECT_LE(volume, aabbVolume(scaled));
  EXPECT_GE(volume, 1.5 * fixtureVolume() * (1 - 1e-12));

  // Uniform: exactly the box, twice as large on every axis.
  const wp::UrdfBodies twice = wp::bodiesFromUrdf(urdfWithCollisions("arm", meshCollision(url, kOrigin, "2 2 2")));
  ASSERT_EQ(twice.bodies.size(), 1u);
  const wp::RobotBodySpec& t = twice.bodies[0];
  EXPECT_LE(worstOutside(t.offset, t.shape.half_extents, transformed(originPose(), 2.0 * fixtureCorners())), 1e-9);
  EXPECT_TRUE(sorted(t.shape.half_extents).isApprox(sorted(2.0 * kFixtureHalf), 1e-9));
}

TEST(BodiesFromUrdf, PrimitivesAsTheyAre) {
  const wp::UrdfBodies r = wp::bodiesFromUrdf(urdfWithCollisions(
      "base",
      "<collision><origin xyz=\"0 0 0.25\"/><geometry><box size=\"0.6 0.4 0.5\"/></geometry></collision>"
      "<collision><geometry><cylinder radius=\"0.1\" length=\"1.0\"/></geometry></collision>"
      "<collision><geometry><sphere radius=\"0.25\"/></geometry></collision>"));
  ASSERT_EQ(r.bodies.size(), 3u);
  EXPECT_TRUE(r.unmodelled.empty());
  EXPECT_EQ(r.bodies[0].name, "base/0");
  EXPECT_EQ(r.bodies[0].shape.type, wp::ShapeType::kBox);
  EXPECT_TRUE(r.bodies[0].shape.half_extents.isApprox(Eigen::Vector3d(0.3, 0.2, 0.25)));
  EXPECT_TRUE(r.bodies[0].offset.translation().isApprox(Eigen::Vector3d(0, 0, 0.25)));
  EXPECT_EQ(r.bodies[1].name, "base/1");
  EXPECT_EQ(r.bodies[1].shape.type, wp::ShapeType::kCylinder);
  EXPECT_EQ(r.bodies[2].name, "base/2");
  EXPECT_EQ(r.bodies[2].shape.type, wp::ShapeType::kSphere);
  EXPECT_DOUBLE_EQ(r.bodies[2].shape.radius, 0.25);
}

TEST(BodiesFromUrdf, NoElementVanishes) {
  TempDir dir;
  const std::string missing = "file://" + dir.path() + "/gone.stl";
  const std::string not_mesh = "file://" + kFixtures + "/not_a_mesh.stl";
  const std::string flat = "file://" + dir.write("panel.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string collisions =
      "<collision><geometry><box size=\"0.1 0.1 0.1\"/></geometry></collision>" +  // 0: body
      meshCollision(missing) +                                                      // 1: missing
      meshCollision(not_mesh) +                                                     // 2: no mesh
      "<collision><geometry><box size=\"0 0 0\"/></geometry></collision>" +          // 3: zero size
      meshCollision(flat) +                                                         // 4: flat: body
      meshCollision(flat, "", "0 0 0");                                             // 5: scaled to nothing
  wp::UrdfBodies r;
  ASSERT_NO_THROW(r = wp::bodiesFromUrdf(urdfWithCollisions("wrist", collisions)));
  ASSERT_EQ(r.bodies.size() + r.unmodelled.size(), 6u);
  ASSERT_EQ(r.bodies.size(), 2u);
  EXPECT_EQ(r.bodies[0].name, "wrist/0");
  EXPECT_EQ(r.bodies[1].name, "wrist/4");
  // The flat panel is kept, thickened to the smallest shape size, around its vertices.
  Eigen::Matrix3Xd panel(3, 3);
  panel << 0, 1, 0, 0, 0, 1, 0, 0, 0;
  EXPECT_LE(worstOutside(r.bodies[1].offset, r.bodies[1].shape.half_extents, panel), 1e-12);
  EXPECT_TRUE(r.bodies[1].shape.valid());
  EXPECT_NEAR(sorted(r.bodies[1].shape.half_extents)(0), wp::Limits::kMinSize, 1e-15);

  ASSERT_EQ(r.unmodelled.size(), 4u);
  const std::vector<std::size_t> indices = {1, 2, 3, 5};
  const std::vector<std::vector<std::string>> reasons = {
      {missing, "cannot be retrieved"}, {not_mesh, "not a mesh"}, {"box 0 x 0 x 0 m", "zero or invalid size"}, {flat, "zero size"}};
  for (std::size_t i = 0; i < indices.size(); ++i) {
    const wp::UnmodelledElement& u = r.unmodelled[i];
    EXPECT_EQ(u.link, "wrist");
    EXPECT_EQ(u.index, indices[i]);
    EXPECT_EQ(u.body, "wrist/" + std::to_string(indices[i]));
    for (const std::string& part : reasons[i]) EXPECT_TRUE(contains(u.reason, part)) << u.reason;
  }
}

TEST(BodiesFromUrdf, BrokenMeshesFixture) {
  // The fixture the node's rostest uses: what it must expect.
  const wp::UrdfBodies r = wp::bodiesFromUrdf(readFile(kFixtures + "/broken_meshes.urdf"));
  ASSERT_EQ(r.bodies.size(), 2u);
  std::map<std::string, const wp::RobotBodySpec*> by_name;
  for (const wp::RobotBodySpec& b : r.bodies) by_name[b.name] = &b;
  ASSERT_EQ(by_name.count("base_link"), 1u);
  ASSERT_EQ(by_name.count("dae_link"), 1u);
  const wp::RobotBodySpec& base = *by_name["base_link"];
  EXPECT_TRUE(base.shape.half_extents.isApprox(Eigen::Vector3d(0.3, 0.3, 0.25)));
  EXPECT_TRUE(base.offset.translation().isApprox(Eigen::Vector3d(0, 0, 0.25)));
  const wp::RobotBodySpec& dae = *by_name["dae_link"];
  EXPECT_EQ(dae.frame, "dae_link");
  EXPECT_LE(worstOutside(dae.offset, dae.shape.half_extents, fixtureCorners()), 1e-9);
  EXPECT_TRUE(sorted(dae.shape.half_extents).isApprox(sorted(kFixtureHalf), 1e-9));
  EXPECT_TRUE(dae.offset.translation().isApprox(kFixtureCentre, 1e-9));

  ASSERT_EQ(r.unmodelled.size(), 1u);
  EXPECT_EQ(r.unmodelled[0].link, "missing_mesh_link");
  EXPECT_EQ(r.unmodelled[0].index, 0u);
  EXPECT_EQ(r.unmodelled[0].body, "missing_mesh_link");
  EXPECT_TRUE(contains(r.unmodelled[0].reason,
                       "package://workspace_proximity/test/ros/fixtures/missing_mesh.stl"));
  EXPECT_TRUE(contains(r.unmodelled[0].reason, "cannot be retrieved"));
}

TEST(BodiesFromUrdf, UnparsableUrdfThrows) {
  EXPECT_THROW(wp::bodiesFromUrdf("<robot name=\"r\"><link></robot>"), std::runtime_error);
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
