#include "tests/testing/chewing_sequence.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <random>

#include <Eigen/Geometry>

#include "measure/delaunay.h"
#include "io/surface_reader.h"

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kRadians = kPi / 180.0;

Eigen::Matrix4d RotationAbout(const Eigen::Vector3d& axis, double angle, const Eigen::Vector3d& point) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
  m.topLeftCorner<3, 3>() = r;
  m.topRightCorner<3, 1>() = point - r * point;
  return m;
}

// The face as a piecewise-linear surface: samples in mm, their xy mesh, and
// the cumulative triangle areas for area-uniform sampling.
struct PlFace {
  std::vector<Point2> xy;
  std::vector<double> z;
  Triangulation mesh;
  std::vector<double> cumulative_area;
};

PlFace BuildFace(const std::vector<std::array<double, 3>>& face, double scale) {
  PlFace out;
  double mx = 0, my = 0, max_z = -1e300;
  for (const auto& p : face) {
    mx += p[0];
    my += p[1];
    max_z = std::max(max_z, p[2]);
  }
  mx /= static_cast<double>(face.size());
  my /= static_cast<double>(face.size());
  for (const auto& p : face) {
    out.xy.push_back({(p[0] - mx) * scale, (p[1] - my) * scale});
    out.z.push_back((p[2] - max_z) * scale);
  }
  out.mesh = Triangulate(out.xy);
  double total = 0;
  for (int32_t t = 0; t < out.mesh.num_triangles(); ++t) {
    const Point2& a = out.xy[out.mesh.triangles[3 * t]];
    const Point2& b = out.xy[out.mesh.triangles[3 * t + 1]];
    const Point2& c = out.xy[out.mesh.triangles[3 * t + 2]];
    total += 0.5 * std::fabs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    out.cumulative_area.push_back(total);
  }
  return out;
}

// `count` points uniform in area on the face with y ≥ level (upper) or y < level.
void Sample(const PlFace& face, bool upper, double level, int count, std::mt19937_64* rng,
            std::vector<std::array<double, 3>>* out) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double total = face.cumulative_area.back();
  int added = 0;
  while (added < count) {
    const double pick = unit(*rng) * total;
    const int32_t t = static_cast<int32_t>(
        std::upper_bound(face.cumulative_area.begin(), face.cumulative_area.end(), pick) -
        face.cumulative_area.begin());
    if (t >= face.mesh.num_triangles()) continue;
    double u = unit(*rng), v = unit(*rng);
    if (u + v > 1) {
      u = 1 - u;
      v = 1 - v;
    }
    const int32_t ia = face.mesh.triangles[3 * t], ib = face.mesh.triangles[3 * t + 1],
                  ic = face.mesh.triangles[3 * t + 2];
    const double w = 1 - u - v;
    const double x = w * face.xy[ia].x + u * face.xy[ib].x + v * face.xy[ic].x;
    const double y = w * face.xy[ia].y + u * face.xy[ib].y + v * face.xy[ic].y;
    if ((y >= level) != upper) continue;
    const double z = w * face.z[ia] + u * face.z[ib] + v * face.z[ic];
    out->push_back({x, y, z});
    ++added;
  }
}

void Apply(const Eigen::Matrix4d& m, std::array<double, 3>* p) {
  const Eigen::Vector3d q = m.topLeftCorner<3, 3>() * Eigen::Vector3d((*p)[0], (*p)[1], (*p)[2]) +
                            m.topRightCorner<3, 1>();
  *p = {q.x(), q.y(), q.z()};
}

std::array<double, 3> Euler(const Eigen::Matrix3d& r) {  // R = Rz·Ry·Rx, degrees
  const double ry = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  return {std::atan2(r(2, 1), r(2, 2)) / kRadians, ry / kRadians, std::atan2(r(1, 0), r(0, 0)) / kRadians};
}

}  // namespace

std::string DenseFacePath() {
#ifdef SURFREG_SOURCE_DIR
  return std::string(SURFREG_SOURCE_DIR) + "/configs/data/mannequin_face_dense.xyz";
#else
  return "configs/data/mannequin_face_dense.xyz";
#endif
}

std::vector<std::array<double, 3>> ReadFacePoints(const std::string& path) {
  const Surface surface = ReadSurface(path);  // the project's reader
  std::vector<std::array<double, 3>> points;
  points.reserve(surface.size());
  for (std::size_t i = 0; i < surface.size(); ++i) {
    points.push_back({surface.xy[i].x + surface.origin[0], surface.xy[i].y + surface.origin[1],
                      surface.z[i] + surface.origin[2]});
  }
  return points;
}

std::vector<ChewingFrame> MakeChewingSequence(const std::vector<std::array<double, 3>>& face_points,
                                              const ChewingOptions& options) {
  const PlFace face = BuildFace(face_points, options.scale);
  std::mt19937_64 rng(options.seed);
  const Eigen::Vector3d head_axis = Eigen::Vector3d(0.3, 0.8, 0.5).normalized();
  const Eigen::Vector3d head_centre(0.0, 0.0, -60.0);
  const Eigen::Vector3d head_direction = Eigen::Vector3d(0.6, -0.5, 0.62).normalized();
  std::vector<ChewingFrame> frames(options.frames);
  for (int k = 0; k < options.frames; ++k) {
    ChewingFrame& frame = frames[k];
    const double phase = 2 * kPi * k / options.period_frames;
    frame.opening_deg = options.max_opening_deg * 0.5 * (1 - std::cos(phase));
    frame.lateral_deg = options.lateral_deg * std::sin(phase);
    // Opening turns the chin down and back: with the hinge behind the face
    // (z < 0, the camera looks along −z), a positive rotation about +x.
    frame.jaw = RotationAbout(Eigen::Vector3d::UnitY(), frame.lateral_deg * kRadians, options.hinge) *
                RotationAbout(Eigen::Vector3d::UnitX(), frame.opening_deg * kRadians, options.hinge);
    const double s = std::sin(kPi * k / options.frames);
    frame.head = RotationAbout(head_axis, options.head_angle_deg * s * kRadians, head_centre);
    frame.head.topRightCorner<3, 1>() += options.head_shift * s * head_direction;

    Sample(face, true, options.boundary_y, options.upper_points, &rng, &frame.points);
    frame.upper_count = static_cast<int>(frame.points.size());
    Sample(face, false, options.boundary_y, options.lower_points, &rng, &frame.points);
    for (std::size_t i = 0; i < frame.points.size(); ++i) {
      if (static_cast<int>(i) >= frame.upper_count) Apply(frame.jaw, &frame.points[i]);
      Apply(frame.head, &frame.points[i]);
    }
  }
  return frames;
}

bool WriteChewingSequence(const std::vector<ChewingFrame>& frames, const std::string& directory) {
  std::error_code error;
  std::filesystem::create_directories(directory + "/frames", error);
  if (error) return false;
  std::string csv = "frame,rx_deg,ry_deg,rz_deg,tx,ty,tz,opening_deg,lateral_deg\n";
  std::string json = "[\n";
  char buffer[512];
  for (std::size_t k = 0; k < frames.size(); ++k) {
    std::snprintf(buffer, sizeof(buffer), "%s/frames/frame_%03zu.xyz", directory.c_str(), k);
    std::FILE* file = std::fopen(buffer, "w");
    if (file == nullptr) return false;
    std::fprintf(file, "# synthetic chewing frame %zu (tests/testing/chewing_sequence.h), mm\n", k);
    for (const auto& p : frames[k].points) std::fprintf(file, "%.4f %.4f %.4f\n", p[0], p[1], p[2]);
    if (std::fclose(file) != 0) return false;
    const Eigen::Matrix4d& h = frames[k].jaw;
    const std::array<double, 3> e = Euler(h.topLeftCorner<3, 3>());
    std::snprintf(buffer, sizeof(buffer), "%zu,%.12f,%.12f,%.12f,%.12f,%.12f,%.12f,%.6f,%.6f\n", k, e[0],
                  e[1], e[2], h(0, 3), h(1, 3), h(2, 3), frames[k].opening_deg, frames[k].lateral_deg);
    csv += buffer;
    json += "  [";
    for (int i = 0; i < 4; ++i) {
      std::snprintf(buffer, sizeof(buffer), "%s[%.15g, %.15g, %.15g, %.15g]", i ? ", " : "", h(i, 0),
                    h(i, 1), h(i, 2), h(i, 3));
      json += buffer;
    }
    json += k + 1 < frames.size() ? "],\n" : "]\n";
  }
  json += "]\n";
  for (const auto& [name, text] : {std::pair<std::string, std::string>{"truth.csv", csv},
                                   std::pair<std::string, std::string>{"truth.json", json}}) {
    std::FILE* file = std::fopen((directory + "/" + name).c_str(), "w");
    if (file == nullptr) return false;
    std::fputs(text.c_str(), file);
    if (std::fclose(file) != 0) return false;
  }
  return true;
}

const std::vector<std::array<double, 3>>& DenseFace() {
  static const auto* face = new std::vector<std::array<double, 3>>(ReadFacePoints(DenseFacePath()));
  return *face;
}

std::vector<Surface> FrameSurfaces(const std::vector<ChewingFrame>& frames) {
  std::vector<Surface> out;
  for (std::size_t k = 0; k < frames.size(); ++k) {
    out.push_back(MakeSurface(frames[k].points, {}, "frame " + std::to_string(k)));
  }
  return out;
}

}  // namespace surfreg
