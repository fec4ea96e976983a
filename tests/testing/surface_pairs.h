#pragma once
// Registration test pairs with a known answer: a reference surface, a moving
// surface, and the true 4×4 transform (moving → reference, input
// coordinates) built independently of surfreg's motion code (Eigen's
// AngleAxis).
#include <array>
#include <cmath>
#include <fstream>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "measure/surface.h"

namespace surfreg::testing {

using HeightFunction = std::function<double(double, double)>;

// A smooth analytic terrain on [0, 100]²: two hills, a valley and a ripple.
inline double SmoothTerrain(double x, double y) {
  return 8.0 * std::exp(-((x - 35) * (x - 35) + (y - 40) * (y - 40)) / 300.0) +
         5.0 * std::exp(-((x - 70) * (x - 70) + (y - 65) * (y - 65)) / 200.0) -
         4.0 * std::exp(-((x - 60) * (x - 60) + (y - 25) * (y - 25)) / 150.0) +
         0.8 * std::sin(0.15 * x) * std::cos(0.11 * y) + 0.02 * x;
}

// n points uniform in [x0, x1] × [y0, y1] with heights f.
inline std::vector<std::array<double, 3>> SampleUniform(const HeightFunction& f, std::size_t n,
                                                        double x0, double x1, double y0, double y1,
                                                        uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> ux(x0, x1), uy(y0, y1);
  std::vector<std::array<double, 3>> points(n);
  for (auto& p : points) {
    p[0] = ux(rng);
    p[1] = uy(rng);
    p[2] = f(p[0], p[1]);
  }
  return points;
}

// A grid DEM ("x y z" lines, '#' comments) as a bilinear height function.
struct GridDem {
  double x0 = 0, y0 = 0, step = 1;
  int nx = 0, ny = 0;
  std::vector<double> z;  // z[ix * ny + iy]

  double operator()(double x, double y) const {
    const double fx = std::clamp((x - x0) / step, 0.0, nx - 1.000000001);
    const double fy = std::clamp((y - y0) / step, 0.0, ny - 1.000000001);
    const int ix = static_cast<int>(fx), iy = static_cast<int>(fy);
    const double u = fx - ix, v = fy - iy;
    auto at = [&](int i, int j) { return z[static_cast<std::size_t>(i) * ny + j]; };
    return (1 - u) * (1 - v) * at(ix, iy) + u * (1 - v) * at(ix + 1, iy) +
           (1 - u) * v * at(ix, iy + 1) + u * v * at(ix + 1, iy + 1);
  }
  double x1() const { return x0 + (nx - 1) * step; }
  double y1() const { return y0 + (ny - 1) * step; }
};

// Reads a regular grid written as "x y z" lines in any order.
inline GridDem ReadGridDem(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::array<double, 3>> points;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::array<double, 3> p;
    if (fields >> p[0] >> p[1] >> p[2]) points.push_back(p);
  }
  GridDem dem;
  if (points.empty()) return dem;
  std::vector<double> xs, ys;
  for (const auto& p : points) {
    xs.push_back(p[0]);
    ys.push_back(p[1]);
  }
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end()), ys.end());
  dem.x0 = xs.front();
  dem.y0 = ys.front();
  dem.nx = static_cast<int>(xs.size());
  dem.ny = static_cast<int>(ys.size());
  dem.step = (xs.back() - xs.front()) / (dem.nx - 1);
  dem.z.assign(static_cast<std::size_t>(dem.nx) * dem.ny, 0.0);
  for (const auto& p : points) {
    const int ix = static_cast<int>(std::lround((p[0] - dem.x0) / dem.step));
    const int iy = static_cast<int>(std::lround((p[1] - dem.y0) / dem.step));
    dem.z[static_cast<std::size_t>(ix) * dem.ny + iy] = p[2];
  }
  return dem;
}

// The true motion: rotation `angle_deg` about `axis` through the moving
// cloud's centroid, then `shift`. Returns moving → reference.
inline Eigen::Matrix4d TrueMotion(const Eigen::Vector3d& axis, double angle_deg,
                                  const Eigen::Vector3d& shift, const Eigen::Vector3d& centre) {
  const Eigen::Matrix3d r = Eigen::AngleAxisd(angle_deg * M_PI / 180.0, axis.normalized()).matrix();
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = r;
  m.topRightCorner<3, 1>() = centre + shift - r * centre;
  return m;
}

// Points moved by the inverse of `truth`: the moving surface such that
// `truth` maps it back onto where the points were sampled.
inline std::vector<std::array<double, 3>> MoveByInverse(std::vector<std::array<double, 3>> points,
                                                        const Eigen::Matrix4d& truth) {
  const Eigen::Matrix4d inverse = truth.inverse();
  for (auto& p : points) {
    const Eigen::Vector4d q = inverse * Eigen::Vector4d(p[0], p[1], p[2], 1.0);
    p = {q[0], q[1], q[2]};
  }
  return points;
}

inline Eigen::Vector3d Centroid(const std::vector<std::array<double, 3>>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& p : points) sum += Eigen::Vector3d(p[0], p[1], p[2]);
  return sum / static_cast<double>(points.size());
}

// Errors of an estimated transform: rotation angle (degrees) of R_est R_trueᵀ,
// and the distance between where each sends the moving centroid.
struct MotionError {
  double rotation_deg = 0;
  double translation = 0;
};
inline MotionError CompareMotions(const Eigen::Matrix4d& estimate, const Eigen::Matrix4d& truth,
                                  const Eigen::Vector3d& moving_centroid) {
  const Eigen::Matrix3d delta = estimate.topLeftCorner<3, 3>() * truth.topLeftCorner<3, 3>().transpose();
  MotionError error;
  error.rotation_deg = Eigen::AngleAxisd(delta).angle() * 180.0 / M_PI;
  const Eigen::Vector4d c(moving_centroid.x(), moving_centroid.y(), moving_centroid.z(), 1.0);
  error.translation = ((estimate - truth) * c).head<3>().norm();
  return error;
}

}  // namespace surfreg::testing
