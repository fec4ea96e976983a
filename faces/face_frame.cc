// The standard face frame (Dyshkant 2010, 3.1): orientation by a given
// rotation or by principal axes with the nose heuristics, then the visible
// side by a grid-bucketed "is any triangle above this vertex" test.
#include "faces/face_frame.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "measure/input_error.h"

namespace surfreg {
namespace {

using Vec3 = Eigen::Vector3d;

constexpr double kPi = 3.14159265358979323846;

Vec3 ToVec(const std::array<double, 3>& p) { return Vec3(p[0], p[1], p[2]); }

[[noreturn]] void Fail(const Mesh& mesh, const std::string& what) {
  throw InputError((mesh.source.empty() ? std::string("face") : mesh.source) + ": " + what);
}

constexpr double kMaxCoordinate = 1e150;

void CheckMesh(const Mesh& mesh) {
  const std::size_t n = mesh.vertices.size();
  if (n < 3) Fail(mesh, "a face needs at least 3 points, got " + std::to_string(n));
  if (n > static_cast<std::size_t>(std::numeric_limits<int32_t>::max())) {
    Fail(mesh, "too many points for 32-bit indices");
  }
  for (std::size_t i = 0; i < n; ++i) {
    const auto& p = mesh.vertices[i];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      Fail(mesh, "point " + std::to_string(i) + " has a non-finite coordinate");
    }
    // The orientation sums squares of coordinates: beyond this they overflow.
    if (std::fabs(p[0]) > kMaxCoordinate || std::fabs(p[1]) > kMaxCoordinate ||
        std::fabs(p[2]) > kMaxCoordinate) {
      Fail(mesh,
           "point " + std::to_string(i) + " has a coordinate beyond ±1e150 (not a face scan's)");
    }
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (const int32_t v : mesh.triangles[t]) {
      if (v < 0 || static_cast<std::size_t>(v) >= n) {
        Fail(mesh, "triangle " + std::to_string(t) + " has vertex index " + std::to_string(v) +
                       " out of range (" + std::to_string(n) + " vertices)");
      }
    }
  }
}

void CheckOptions(const Mesh& mesh, const FaceFrameOptions& options) {
  if (!(options.depth_limit >= 0.0) || !std::isfinite(options.depth_limit)) {
    Fail(mesh, "depth_limit must be a finite number >= 0");
  }
  if (!(options.visibility_tolerance >= 0.0) || !std::isfinite(options.visibility_tolerance)) {
    Fail(mesh, "visibility_tolerance must be a finite number >= 0");
  }
  for (const double r : options.rotation_deg) {
    if (!std::isfinite(r)) Fail(mesh, "the rotation vector must be finite");
  }
}

double BoxDiagonal(const std::vector<std::array<double, 3>>& points) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& p : points) {
    lo = lo.cwiseMin(ToVec(p));
    hi = hi.cwiseMax(ToVec(p));
  }
  return (hi - lo).norm();
}

// Centroid and covariance: of the surface (uniform density over the
// triangles, exact second moments), so that the axes do not depend on how
// densely each part is meshed; of the points for a cloud.
void Moments(const Mesh& mesh, Vec3* centroid, Eigen::Matrix3d* covariance) {
  Vec3 ref = Vec3::Zero();  // moments about the vertex mean, for precision
  for (const auto& p : mesh.vertices) ref += ToVec(p);
  ref /= static_cast<double>(mesh.vertices.size());
  double total = 0.0;
  Vec3 first = Vec3::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const auto& t : mesh.triangles) {
    const Vec3 a = ToVec(mesh.vertices[t[0]]) - ref, b = ToVec(mesh.vertices[t[1]]) - ref,
               c = ToVec(mesh.vertices[t[2]]) - ref;
    const double area = 0.5 * (b - a).cross(c - a).norm();
    const Vec3 s = a + b + c;
    total += area;
    first += area / 3.0 * s;
    second += area / 12.0 *
              (s * s.transpose() + a * a.transpose() + b * b.transpose() + c * c.transpose());
  }
  if (!(total > 0.0)) {  // a cloud, or only degenerate triangles
    total = static_cast<double>(mesh.vertices.size());
    first.setZero();
    second.setZero();
    for (const auto& p : mesh.vertices) {
      const Vec3 q = ToVec(p) - ref;
      first += q;
      second += q * q.transpose();
    }
  }
  const Vec3 mean = first / total;
  *covariance = second / total - mean * mean.transpose();
  *centroid = ref + mean;
}

// How far the most prominent point along `view` is from the middle of the
// projection (0 = in the middle, ~0.5 = at the rim), relative to the extents
// across and along `up`. A nose tip faces the camera near the middle of the
// face; seen from the back or the sides, the most prominent point is at the
// rim (the back of the neck, a shoulder, the edge of a face scan).
double TipOffCentre(const std::vector<Vec3>& q, const Vec3& view, const Vec3& up) {
  const Vec3 across = up.cross(view);
  double best = -std::numeric_limits<double>::infinity(), tip_x = 0, tip_y = 0;
  double x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0;
  for (const Vec3& p : q) {
    const double x = across.dot(p), y = up.dot(p), z = view.dot(p);
    if (z > best) best = z, tip_x = x, tip_y = y;
    x_lo = std::min(x_lo, x), x_hi = std::max(x_hi, x);
    y_lo = std::min(y_lo, y), y_hi = std::max(y_hi, y);
  }
  return std::hypot(tip_x / (x_hi - x_lo), tip_y / (y_hi - y_lo));
}

// > 0 if `up` points from chin to forehead: the nose's ridge stands out
// more from its sides in rows above the tip (the bridge between the eyes)
// than in rows below it (the upper lip between the cheeks). Each row is
// compared with itself, so a pitch of the frame (a whole head's principal
// axes lean with the neck) does not bias the cue, and yaw cancels between
// the two sides. Rows 6, 10, 14% of the face's length from the tip; sides
// 10, 15, 20% of its width; the highest point of each patch stands for it.
double RidgeScore(const std::vector<Vec3>& q, const Vec3& view, const Vec3& up) {
  constexpr double kRow[3] = {0.06, 0.10, 0.14}, kSide[3] = {0.10, 0.15, 0.20};
  const Vec3 across = up.cross(view);
  double best = -std::numeric_limits<double>::infinity();
  double y_lo = 0, y_hi = 0, x_lo = 0, x_hi = 0;
  Vec3 tip = Vec3::Zero();
  for (const Vec3& p : q) {
    const Vec3 f(across.dot(p), up.dot(p), view.dot(p));
    if (f.z() > best) best = f.z(), tip = f;
    y_lo = std::min(y_lo, f.y()), y_hi = std::max(y_hi, f.y());
    x_lo = std::min(x_lo, f.x()), x_hi = std::max(x_hi, f.x());
  }
  const double length = y_hi - y_lo, width = x_hi - x_lo, half = 0.02 * length;
  const double kLow = -std::numeric_limits<double>::infinity();
  // top[row][side][0 = above, 1 = below][0 = ridge, 1 = left, 2 = right]
  double top[3][3][2][3];
  std::fill(&top[0][0][0][0], &top[0][0][0][0] + 54, kLow);
  for (const Vec3& p : q) {
    const double dx = across.dot(p) - tip.x(), dy = up.dot(p) - tip.y(), z = view.dot(p);
    for (int r = 0; r < 3; ++r) {
      for (int b = 0; b < 2; ++b) {
        if (std::fabs(dy - (b == 0 ? 1 : -1) * kRow[r] * length) >= half) continue;
        for (int s = 0; s < 3; ++s) {
          double* patch = top[r][s][b];
          if (std::fabs(dx) < 1.5 * half) patch[0] = std::max(patch[0], z);
          if (std::fabs(dx + kSide[s] * width) < 1.5 * half) patch[1] = std::max(patch[1], z);
          if (std::fabs(dx - kSide[s] * width) < 1.5 * half) patch[2] = std::max(patch[2], z);
        }
      }
    }
  }
  double score = 0.0;
  for (int r = 0; r < 3; ++r) {
    for (int s = 0; s < 3; ++s) {
      const double* above = top[r][s][0];
      const double* below = top[r][s][1];
      if (std::min({above[0], above[1], above[2], below[0], below[1], below[2]}) == kLow) continue;
      score += (above[0] - 0.5 * (above[1] + above[2])) - (below[0] - 0.5 * (below[1] + below[2]));
    }
  }
  return score;
}

// Rows X, Y, Z of the frame's rotation from the principal axes: Y the axis
// of largest variance (chin to forehead is a face's, and a head's, longest
// extent); Z, the line of sight, whichever of ±(the other two axes) puts the
// most prominent point nearest the middle (so a whole head, whose depth may
// exceed its width, and a face scan, whose depth is its least variance, both
// work); the sign of Y by the ridge cue (RidgeScore); X = Y × Z.
Eigen::Matrix3d PrincipalAxes(const Mesh& mesh) {
  Vec3 centroid;
  Eigen::Matrix3d covariance;
  Moments(mesh, &centroid, &covariance);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  const Vec3 lambda = solver.eigenvalues();  // ascending
  if (!(lambda(2) > 0.0) || lambda(1) <= 1e-12 * lambda(2)) {
    Fail(mesh, "the points are collinear (or all equal): the face's axes are not defined");
  }
  if (lambda(0) <= 1e-12 * lambda(2)) {
    Fail(mesh, "the points are coplanar: the face's axes are not defined");
  }
  std::vector<Vec3> q;
  q.reserve(mesh.vertices.size());
  for (const auto& p : mesh.vertices) q.push_back(ToVec(p) - centroid);
  Vec3 up = solver.eigenvectors().col(2);
  const Vec3 candidates[4] = {solver.eigenvectors().col(1), -solver.eigenvectors().col(1),
                              solver.eigenvectors().col(0), -solver.eigenvectors().col(0)};
  Vec3 view = candidates[0];
  double best = std::numeric_limits<double>::infinity();
  for (const Vec3& candidate : candidates) {
    const double off = TipOffCentre(q, candidate, up);
    if (off < best) best = off, view = candidate;
  }
  if (RidgeScore(q, view, up) < 0.0) up = -up;
  Eigen::Matrix3d rotation;
  rotation.row(0) = up.cross(view).transpose();
  rotation.row(1) = up.transpose();
  rotation.row(2) = view.transpose();
  return rotation;
}

Eigen::Matrix3d Orientation(const Mesh& mesh, const FaceFrameOptions& options) {
  switch (options.orientation) {
    case FaceOrientation::kAsIs:
      return Eigen::Matrix3d::Identity();
    case FaceOrientation::kGiven: {
      const Vec3 r = ToVec(options.rotation_deg) * (kPi / 180.0);
      const double angle = r.norm();
      if (angle == 0.0) return Eigen::Matrix3d::Identity();
      return Eigen::AngleAxisd(angle, r / angle).toRotationMatrix();
    }
    case FaceOrientation::kPrincipalAxes:
      break;
  }
  return PrincipalAxes(mesh);
}

// True if all points lie on one line in xy (up to rounding).
bool CollinearXy(const std::vector<std::array<double, 3>>& xyz) {
  const auto& a = xyz[0];
  std::size_t far = 0;
  double far_d = 0.0;
  for (std::size_t i = 1; i < xyz.size(); ++i) {
    const double d = std::hypot(xyz[i][0] - a[0], xyz[i][1] - a[1]);
    if (d > far_d) far_d = d, far = i;
  }
  if (far_d == 0.0) return true;
  const auto& b = xyz[far];
  for (const auto& c : xyz) {
    const double cross = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (std::fabs(cross) > 1e-12 * far_d * far_d) return false;
  }
  return true;
}

}  // namespace

std::vector<int32_t> VisibleVertices(const Mesh& mesh, double tolerance) {
  const std::size_t n = mesh.vertices.size();
  std::vector<int32_t> visible;
  if (n == 0) return visible;
  // A uniform xy grid of about one triangle per cell; each triangle is listed
  // in every cell its bounding box meets (CSR: offsets, then triangle ids).
  double x_lo = mesh.vertices[0][0], x_hi = x_lo, y_lo = mesh.vertices[0][1], y_hi = y_lo;
  for (const auto& p : mesh.vertices) {
    x_lo = std::min(x_lo, p[0]), x_hi = std::max(x_hi, p[0]);
    y_lo = std::min(y_lo, p[1]), y_hi = std::max(y_hi, p[1]);
  }
  const double w = std::max(x_hi - x_lo, 1e-300), h = std::max(y_hi - y_lo, 1e-300);
  const double cells = std::max<double>(1.0, static_cast<double>(mesh.triangles.size()));
  // Sides and cells clamped before they become ints (NaN from ranges that
  // overflow to infinity goes to the first cell: slower, still right).
  const auto side = [](double v) {
    return static_cast<int>(v >= 1.0 ? std::min(std::ceil(v), 4096.0) : 1.0);
  };
  const int nx = side(std::sqrt(cells * w / h)), ny = side(std::sqrt(cells * h / w));
  const auto clamp_cell = [](double u, int cells_on_side) {
    return u >= 0.0 ? static_cast<int>(std::min(u, cells_on_side - 1.0)) : 0;
  };
  const auto cell_x = [&](double x) { return clamp_cell((x - x_lo) / w * nx, nx); };
  const auto cell_y = [&](double y) { return clamp_cell((y - y_lo) / h * ny, ny); };
  std::vector<int64_t> offset(static_cast<std::size_t>(nx) * ny + 1, 0);
  std::vector<std::array<int, 4>> range(mesh.triangles.size());  // x0, x1, y0, y1
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& a = mesh.vertices[mesh.triangles[t][0]];
    const auto& b = mesh.vertices[mesh.triangles[t][1]];
    const auto& c = mesh.vertices[mesh.triangles[t][2]];
    range[t] = {cell_x(std::min({a[0], b[0], c[0]})), cell_x(std::max({a[0], b[0], c[0]})),
                cell_y(std::min({a[1], b[1], c[1]})), cell_y(std::max({a[1], b[1], c[1]}))};
    for (int j = range[t][2]; j <= range[t][3]; ++j) {
      for (int i = range[t][0]; i <= range[t][1]; ++i)
        ++offset[static_cast<std::size_t>(j) * nx + i + 1];
    }
  }
  for (std::size_t k = 1; k < offset.size(); ++k) offset[k] += offset[k - 1];
  std::vector<int32_t> bucket(static_cast<std::size_t>(offset.back()));
  std::vector<int64_t> fill(offset.begin(), offset.end() - 1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (int j = range[t][2]; j <= range[t][3]; ++j) {
      for (int i = range[t][0]; i <= range[t][1]; ++i) {
        bucket[fill[static_cast<std::size_t>(j) * nx + i]++] = static_cast<int32_t>(t);
      }
    }
  }
  // A vertex is hidden by a triangle (not one of its own) that covers its xy
  // (barycentric coordinates >= -kEdge: the boundary counts) and whose plane
  // there is above the vertex by more than `tolerance`.
  constexpr double kEdge = 1e-12;
  visible.reserve(n);
  for (std::size_t v = 0; v < n; ++v) {
    const auto& p = mesh.vertices[v];
    const std::size_t cell = static_cast<std::size_t>(cell_y(p[1])) * nx + cell_x(p[0]);
    bool hidden = false;
    for (int64_t k = offset[cell]; k < offset[cell + 1] && !hidden; ++k) {
      const auto& tri = mesh.triangles[bucket[k]];
      if (tri[0] == static_cast<int32_t>(v) || tri[1] == static_cast<int32_t>(v) ||
          tri[2] == static_cast<int32_t>(v)) {
        continue;
      }
      const auto& a = mesh.vertices[tri[0]];
      const auto& b = mesh.vertices[tri[1]];
      const auto& c = mesh.vertices[tri[2]];
      const double det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
      if (det == 0.0) continue;  // seen edge-on: no area to hide anything
      const double la = ((b[0] - p[0]) * (c[1] - p[1]) - (b[1] - p[1]) * (c[0] - p[0])) / det;
      const double lb = ((c[0] - p[0]) * (a[1] - p[1]) - (c[1] - p[1]) * (a[0] - p[0])) / det;
      const double lc = 1.0 - la - lb;
      if (la < -kEdge || lb < -kEdge || lc < -kEdge) continue;
      hidden = la * a[2] + lb * b[2] + lc * c[2] > p[2] + tolerance;
    }
    if (!hidden) visible.push_back(static_cast<int32_t>(v));
  }
  return visible;
}

FaceFrame NormalizeFace(const Mesh& mesh, const FaceFrameOptions& options) {
  CheckMesh(mesh);
  CheckOptions(mesh, options);
  const Eigen::Matrix3d rotation = Orientation(mesh, options);
  Mesh turned;
  turned.triangles = mesh.triangles;
  turned.vertices.reserve(mesh.vertices.size());
  for (const auto& p : mesh.vertices) {
    const Vec3 q = rotation * ToVec(p);
    turned.vertices.push_back({q.x(), q.y(), q.z()});
  }
  std::vector<int32_t> visible;
  if (mesh.triangles.empty()) {
    visible.resize(mesh.vertices.size());
    for (std::size_t i = 0; i < visible.size(); ++i) visible[i] = static_cast<int32_t>(i);
  } else {
    const double tolerance = options.visibility_tolerance > 0.0
                                 ? options.visibility_tolerance
                                 : 1e-9 * BoxDiagonal(turned.vertices);
    visible = VisibleVertices(turned, tolerance);
  }
  FaceFrame frame;
  frame.hidden = static_cast<int64_t>(mesh.vertices.size() - visible.size());
  double z_top = -std::numeric_limits<double>::infinity();
  for (const int32_t v : visible) z_top = std::max(z_top, turned.vertices[v][2]);
  for (const int32_t v : visible) {
    if (options.depth_limit > 0.0 && turned.vertices[v][2] < z_top - options.depth_limit) {
      ++frame.beyond_depth;
      continue;
    }
    frame.input_index.push_back(v);
    frame.points.push_back(turned.vertices[v]);
  }
  if (frame.points.size() < 3 || CollinearXy(frame.points)) {
    Fail(mesh, "only " + std::to_string(frame.points.size()) +
                   " visible points kept, or all on one line seen from the camera: no face "
                   "height field (check the orientation and depth_limit)");
  }
  // Centre in two passes: the second removes the first's rounding, so Σx
  // and Σy are zero to a few ulps of the coordinates times n.
  double shift[2] = {0.0, 0.0};
  for (int pass = 0; pass < 2; ++pass) {
    for (int k = 0; k < 2; ++k) {
      double sum = 0.0;
      for (const auto& p : frame.points) sum += p[k] - shift[k];
      shift[k] += sum / static_cast<double>(frame.points.size());
    }
  }
  bool tip_found = false;
  for (auto& p : frame.points) {
    p = {p[0] - shift[0], p[1] - shift[1], p[2] - z_top};
    if (!tip_found && p[2] == 0.0) frame.nose_tip = p, tip_found = true;
  }
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) frame.rotation[3 * r + c] = rotation(r, c);
  }
  frame.translation = {-shift[0], -shift[1], -z_top};
  return frame;
}

Surface FaceSurface(const FaceFrame& frame, const std::string& source) {
  Surface surface = MakeSurface(frame.points, {}, source);
  ValidateSurface(surface);
  return surface;
}

std::array<double, 3> ToFaceFrame(const FaceFrame& frame, const std::array<double, 3>& input) {
  const auto& r = frame.rotation;
  std::array<double, 3> out;
  for (int k = 0; k < 3; ++k) {
    out[k] = r[3 * k] * input[0] + r[3 * k + 1] * input[1] + r[3 * k + 2] * input[2] +
             frame.translation[k];
  }
  return out;
}

}  // namespace surfreg
