#include "workspace_proximity/ros/oriented_box.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include <Eigen/Eigenvalues>
#include <geometric_shapes/bodies.h>
#include <geometric_shapes/mesh_operations.h>
#include <geometric_shapes/shapes.h>

namespace workspace_proximity {
namespace {

// ---------------------------------------------------------------------------
// Oriented bounding box.

// How many face directions of the hull (its triangles grouped by normal, largest total
// area first) become candidate box axes.
constexpr std::size_t kFaceCandidates = 64;
// Two unit normals closer than this (|dot| above) count as one face direction (0.08 deg).
constexpr double kSameDirection = 1.0 - 1e-6;
constexpr int kMaxRefinePasses = 16;
// More points than this are searched through their extreme points along kSupportDirections
// directions spread over the sphere (both ways), which keeps the search to tens of
// milliseconds; the candidates are then judged, and the extents taken, on every point.
constexpr Eigen::Index kMaxSearchPoints = 1024;
constexpr int kSupportDirections = 512;

using Vec2 = Eigen::Vector2d;

double cross2(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Convex hull of `pts` (Andrew's monotone chain), counter-clockwise, without collinear or
// repeated points. `pts` is sorted in place; `hull` is reused storage.
void hull2d(std::vector<Vec2>* pts, std::vector<Vec2>* hull) {
  std::sort(pts->begin(), pts->end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  hull->clear();
  const std::size_t n = pts->size();
  if (n == 0) return;
  hull->resize(2 * n);
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {  // lower chain
    while (k >= 2 && cross2((*hull)[k - 2], (*hull)[k - 1], (*pts)[i]) <= 0.0) --k;
    (*hull)[k++] = (*pts)[i];
  }
  for (std::size_t i = n - 1, lower = k + 1; i-- > 0;) {  // upper chain
    while (k >= lower && cross2((*hull)[k - 2], (*hull)[k - 1], (*pts)[i]) <= 0.0) --k;
    (*hull)[k++] = (*pts)[i];
  }
  hull->resize(k > 1 ? k - 1 : k);  // the last point repeats the first
}

// Unit direction (in the plane) of one side of the minimum-area rectangle around a convex
// polygon given counter-clockwise. Such a rectangle has a side flush with an edge of the
// polygon, so every edge is tried; rotating calipers keep the three other supporting
// vertices moving forward, which makes it linear in the number of vertices.
Vec2 minAreaRectangleSide(const std::vector<Vec2>& h) {
  const std::size_t n = h.size();
  if (n < 2) return Vec2(1.0, 0.0);
  if (n == 2) return (h[1] - h[0]).normalized();
  auto next = [n](std::size_t i) { return i + 1 == n ? 0 : i + 1; };
  double best_area = std::numeric_limits<double>::infinity();
  Vec2 best(1.0, 0.0);
  std::size_t far_e = 0, far_n = 0, near_e = 0;  // argmax along the edge, along its normal, argmin
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 e = (h[next(i)] - h[i]).normalized();
    const Vec2 nrm(-e.y(), e.x());  // points into the polygon
    if (i == 0) {
      for (std::size_t j = 1; j < n; ++j) {
        if (h[j].dot(e) > h[far_e].dot(e)) far_e = j;
        if (h[j].dot(nrm) > h[far_n].dot(nrm)) far_n = j;
        if (h[j].dot(e) < h[near_e].dot(e)) near_e = j;
      }
    }
    for (std::size_t s = 0; s < n && h[next(far_e)].dot(e) >= h[far_e].dot(e); ++s) far_e = next(far_e);
    for (std::size_t s = 0; s < n && h[next(far_n)].dot(nrm) >= h[far_n].dot(nrm); ++s) far_n = next(far_n);
    for (std::size_t s = 0; s < n && h[next(near_e)].dot(e) <= h[near_e].dot(e); ++s) near_e = next(near_e);
    const double width = h[far_e].dot(e) - h[near_e].dot(e);
    const double height = h[far_n].dot(nrm) - h[i].dot(nrm);
    if (width * height < best_area) {
      best_area = width * height;
      best = e;
    }
  }
  return best;
}

// Scratch storage of one orientedBoundingBox() call.
struct Scratch {
  std::vector<Vec2> projected;
  std::vector<Vec2> hull;
};

// Lowest and highest coordinates of `pts` along the axes `r` (columns).
void extentsIn(const Eigen::Matrix3d& r, const Eigen::Matrix3Xd& pts, Eigen::Vector3d* lo,
               Eigen::Vector3d* hi) {
  *lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  *hi = -*lo;
  for (Eigen::Index i = 0; i < pts.cols(); ++i) {
    const Eigen::Vector3d q = r.transpose() * pts.col(i);
    *lo = lo->cwiseMin(q);
    *hi = hi->cwiseMax(q);
  }
}

// The volume of the box of `pts` along the axes `r`, used to compare frames: each extent
// counts at least `floor`, so that flat or thin point sets are compared by their area (or
// length) instead of all tying at zero.
double scoreIn(const Eigen::Matrix3d& r, const Eigen::Matrix3Xd& pts, double floor) {
  Eigen::Vector3d lo, hi;
  extentsIn(r, pts, &lo, &hi);
  return (hi - lo).cwiseMax(floor).prod();
}

// `r` turned about its axis k so that its two other axes frame the minimum-area rectangle
// around the points' projection on their plane.
Eigen::Matrix3d turnAbout(const Eigen::Matrix3d& r, int k, const Eigen::Matrix3Xd& pts,
                          Scratch* s) {
  const Eigen::Vector3d u = r.col((k + 1) % 3), v = r.col((k + 2) % 3);
  s->projected.resize(static_cast<std::size_t>(pts.cols()));
  for (Eigen::Index i = 0; i < pts.cols(); ++i) {
    s->projected[static_cast<std::size_t>(i)] = Vec2(u.dot(pts.col(i)), v.dot(pts.col(i)));
  }
  hull2d(&s->projected, &s->hull);
  const Vec2 side = minAreaRectangleSide(s->hull);
  Eigen::Matrix3d turned = r;
  turned.col((k + 1) % 3) = (side.x() * u + side.y() * v).normalized();
  turned.col((k + 2) % 3) = r.col(k).cross(turned.col((k + 1) % 3)).normalized();
  return turned;
}

// Turns `r` one axis at a time until the score stops shrinking; each turn can only shrink
// it (the extent along the fixed axis stays, the area across it is the smallest possible).
Eigen::Matrix3d refine(Eigen::Matrix3d r, const Eigen::Matrix3Xd& pts, double floor, Scratch* s,
                       double* score) {
  *score = scoreIn(r, pts, floor);
  for (int pass = 0; pass < kMaxRefinePasses; ++pass) {
    const double before = *score;
    for (int k = 0; k < 3; ++k) {
      const Eigen::Matrix3d turned = turnAbout(r, k, pts, s);
      const double sc = scoreIn(turned, pts, floor);
      if (sc < *score) {
        *score = sc;
        r = turned;
      }
    }
    if (!(*score < before * (1.0 - 1e-12))) break;
  }
  return r;
}

// A right-handed rotation whose third column is `axis` (unit).
Eigen::Matrix3d frameAround(const Eigen::Vector3d& axis) {
  Eigen::Index smallest;
  axis.cwiseAbs().minCoeff(&smallest);
  Eigen::Vector3d u = Eigen::Vector3d::Unit(smallest).cross(axis).normalized();
  Eigen::Matrix3d r;
  r.col(0) = u;
  r.col(1) = axis.cross(u);
  r.col(2) = axis;
  return r;
}

// Eigenvectors of a covariance as a right-handed rotation.
Eigen::Matrix3d principalAxes(const Eigen::Matrix3d& covariance) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d r = solver.eigenvectors();
  if (r.determinant() < 0.0) r.col(2) = -r.col(2);
  return r;
}

Eigen::Matrix3d vertexCovariance(const Eigen::Matrix3Xd& pts) {
  const Eigen::Vector3d mean = pts.rowwise().mean();
  const Eigen::Matrix3Xd centred = pts.colwise() - mean;
  return centred * centred.transpose() / static_cast<double>(pts.cols());
}

// Covariance of the surface of a triangle mesh (area-weighted, every point of every
// triangle, not just its corners). For one triangle with corners a, b, c and area A the
// integral of x x^T over it is A/12 (a a^T + b b^T + c c^T + s s^T) with s = a + b + c.
bool surfaceCovariance(const std::vector<Eigen::Vector3d>& vertices,
                       const std::vector<unsigned int>& triangles, Eigen::Matrix3d* covariance) {
  double area = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const Eigen::Vector3d& a = vertices[triangles[t]];
    const Eigen::Vector3d& b = vertices[triangles[t + 1]];
    const Eigen::Vector3d& c = vertices[triangles[t + 2]];
    const double at = 0.5 * (b - a).cross(c - a).norm();
    const Eigen::Vector3d sum = a + b + c;
    area += at;
    first += at * sum / 3.0;
    second += at / 12.0 *
              (a * a.transpose() + b * b.transpose() + c * c.transpose() + sum * sum.transpose());
  }
  if (!(area > 0.0)) return false;
  const Eigen::Vector3d mean = first / area;
  *covariance = second / area - mean * mean.transpose();
  return covariance->allFinite();
}

// The directions of the hull's largest faces: triangles grouped by normal (either sign),
// largest total area first.
std::vector<Eigen::Vector3d> largestFaceDirections(const std::vector<Eigen::Vector3d>& vertices,
                                                   const std::vector<unsigned int>& triangles) {
  std::vector<std::pair<double, Eigen::Vector3d>> faces;  // (area, unit normal)
  for (std::size_t t = 0; t + 2 < triangles.size(); t += 3) {
    const Eigen::Vector3d& a = vertices[triangles[t]];
    const Eigen::Vector3d n = (vertices[triangles[t + 1]] - a).cross(vertices[triangles[t + 2]] - a);
    const double twice_area = n.norm();
    if (twice_area > 0.0 && std::isfinite(twice_area)) faces.emplace_back(twice_area, n / twice_area);
  }
  // Largest triangles first, so the largest faces found the groups.
  std::sort(faces.begin(), faces.end(),
            [](const auto& x, const auto& y) { return x.first > y.first; });
  std::vector<std::pair<double, Eigen::Vector3d>> groups;
  for (const auto& f : faces) {
    bool joined = false;
    for (auto& g : groups) {
      if (std::abs(g.second.dot(f.second)) > kSameDirection) {
        g.first += f.first;
        joined = true;
        break;
      }
    }
    if (!joined && groups.size() < kFaceCandidates) groups.push_back(f);
  }
  std::sort(groups.begin(), groups.end(),
            [](const auto& x, const auto& y) { return x.first > y.first; });
  std::vector<Eigen::Vector3d> directions;
  for (const auto& g : groups) directions.push_back(g.second);
  return directions;
}

// Convex hull of the points with geometric_shapes (qhull). Returns false, leaving the
// outputs empty, for inputs qhull cannot take (fewer than 4 points, flat).
bool convexHull(const Eigen::Matrix3Xd& pts, double diameter, std::vector<Eigen::Vector3d>* vertices,
                std::vector<unsigned int>* triangles) {
  vertices->clear();
  triangles->clear();
  if (pts.cols() < 4) return false;
  // qhull complains (on stderr) about flat input; the principal axes tell flat apart first.
  const Eigen::Matrix3d axes = principalAxes(vertexCovariance(pts));
  Eigen::Vector3d lo, hi;
  extentsIn(axes, pts, &lo, &hi);
  if (!((hi - lo).minCoeff() > 1e-9 * diameter)) return false;
  shapes::Mesh mesh(static_cast<unsigned int>(pts.cols()), 0);
  for (Eigen::Index i = 0; i < pts.cols(); ++i) {
    for (int d = 0; d < 3; ++d) mesh.vertices[3 * i + d] = pts(d, i);
  }
  const bodies::ConvexMesh hull(&mesh);
  const EigenSTL::vector_Vector3d& hv = hull.getVertices();
  const std::vector<unsigned int>& ht = hull.getTriangles();
  if (hv.size() < 4 || ht.size() < 12) return false;
  for (unsigned int t : ht) {
    if (t >= hv.size()) return false;
  }
  vertices->assign(hv.begin(), hv.end());
  *triangles = ht;
  return true;
}

// The points of `pts` that are farthest along, or against, one of kSupportDirections
// directions (a spherical Fibonacci lattice). Their hull is inside the points' hull and
// touches every supporting plane within 1 - cos(spacing / 2) of the points' radius
// (spacing about 0.16 rad, so 0.3 %).
Eigen::Matrix3Xd supportPoints(const Eigen::Matrix3Xd& pts) {
  const double golden_angle = M_PI * (3.0 - std::sqrt(5.0));
  std::vector<Eigen::Index> chosen;
  chosen.reserve(2 * kSupportDirections);
  for (int i = 0; i < kSupportDirections; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / kSupportDirections;
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    const Eigen::Vector3d d(rho * std::cos(golden_angle * i), rho * std::sin(golden_angle * i), z);
    const Eigen::VectorXd along = pts.transpose() * d;
    Eigen::Index hi, lo;
    along.maxCoeff(&hi);
    along.minCoeff(&lo);
    chosen.push_back(hi);
    chosen.push_back(lo);
  }
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  Eigen::Matrix3Xd out(3, static_cast<Eigen::Index>(chosen.size()));
  for (std::size_t i = 0; i < chosen.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = pts.col(chosen[i]);
  return out;
}

Eigen::Matrix3Xd toMatrix(const std::vector<Eigen::Vector3d>& v) {
  Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) m.col(static_cast<Eigen::Index>(i)) = v[i];
  return m;
}

}  // namespace

OrientedBox orientedBoundingBox(const Eigen::Matrix3Xd& points) {
  OrientedBox box;
  if (points.cols() == 0) return box;
  Scratch scratch;
  Eigen::Vector3d lo, hi;
  extentsIn(Eigen::Matrix3d::Identity(), points, &lo, &hi);
  const double diameter = (hi - lo).norm();
  // Extents below this count as this much when frames are compared (flat meshes).
  const double floor = std::max(1e-9 * diameter, std::numeric_limits<double>::min());

  // Only the hull's vertices can touch a box; its faces give candidate axes. A large hull
  // is searched through its support points (see kMaxSearchPoints).
  std::vector<Eigen::Vector3d> hull_vertices;
  std::vector<unsigned int> hull_triangles;
  Eigen::Matrix3Xd candidates_pts = points.cols() > kMaxSearchPoints ? supportPoints(points) : points;
  if (convexHull(candidates_pts, diameter, &hull_vertices, &hull_triangles)) {
    candidates_pts = toMatrix(hull_vertices);
  }

  std::vector<Eigen::Matrix3d> starts;
  starts.push_back(Eigen::Matrix3d::Identity());
  starts.push_back(principalAxes(vertexCovariance(candidates_pts)));
  Eigen::Matrix3d surface;
  if (surfaceCovariance(hull_vertices, hull_triangles, &surface)) starts.push_back(principalAxes(surface));
  for (const Eigen::Vector3d& n : largestFaceDirections(hull_vertices, hull_triangles)) {
    starts.push_back(frameAround(n));
  }

  Eigen::Matrix3d best = Eigen::Matrix3d::Identity();
  double best_score = std::numeric_limits<double>::infinity();
  for (const Eigen::Matrix3d& start : starts) {
    if (!start.allFinite()) continue;
    double score;
    const Eigen::Matrix3d r = refine(start, candidates_pts, floor, &scratch, &score);
    // Judged on every point when the search saw only the support points.
    if (candidates_pts.cols() != points.cols()) score = scoreIn(r, points, floor);
    if (score < best_score) {
      best_score = score;
      best = r;
    }
  }

  // The extents come from every point, not only the hull's (qhull may merge a vertex that
  // lies within rounding of a face). The points' own frame wins ties, so the result is
  // never larger than the box of the points.
  Eigen::Vector3d blo, bhi;
  extentsIn(best, points, &blo, &bhi);
  const double floor_best = (bhi - blo).cwiseMax(floor).prod();
  const double floor_identity = (hi - lo).cwiseMax(floor).prod();
  if (!(floor_best < floor_identity)) {
    best = Eigen::Matrix3d::Identity();
    blo = lo;
    bhi = hi;
  }
  box.pose.linear() = best;
  box.pose.translation() = best * (0.5 * (blo + bhi));
  box.half_extents = 0.5 * (bhi - blo);
  return box;
}

}  // namespace workspace_proximity
