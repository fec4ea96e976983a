// AlignResult::BriefReport and FullReport: the result in words, as the CLI
// prints it (tools/run_align.cc adds the file names around it).
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>

#include "measure/dz_statistics.h"
#include "registration/align_result.h"

namespace surfreg {
namespace {

constexpr double kDegrees = 180.0 / 3.14159265358979323846;

// printf into a std::string.
void Append(std::string* out, const char* format, ...) __attribute__((format(printf, 2, 3)));
void Append(std::string* out, const char* format, ...) {
  char buffer[512];
  va_list args;
  va_start(args, format);
  const int n = std::vsnprintf(buffer, sizeof buffer, format, args);
  va_end(args);
  if (n < 0) return;
  if (static_cast<std::size_t>(n) < sizeof buffer) {
    out->append(buffer, n);
    return;
  }
  std::string long_line(n + 1, '\0');  // a long verdict reason
  va_start(args, format);
  std::vsnprintf(&long_line[0], long_line.size(), format, args);
  va_end(args);
  long_line.resize(n);
  *out += long_line;
}

double AngleDeg(const std::array<double, 3>& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * kDegrees;
}

}  // namespace

std::string AlignResult::BriefReport() const {
  std::string out;
  Append(&out, "%s: rotation %.6f deg, translation %.6g %.6g %.6g, mean |dz| %.6g -> %.6g, %d iterations, %.3f s",
         VerdictName(verdict), AngleDeg(rotation_vector), translation[0], translation[1], translation[2],
         before.mean_abs_dz, after.mean_abs_dz, iterations, seconds);
  return out;
}

std::string AlignResult::FullReport(const std::string& units) const {
  std::string out;
  const char* u = units.c_str();
  const auto& v = rotation_vector;
  const auto& sd = stddev;
  Append(&out, "verdict:      %s%s%s%s\n", VerdictName(verdict), verdict_reason.empty() ? "" : "  (",
         verdict_reason.c_str(), verdict_reason.empty() ? "" : ")");
  Append(&out, "rotation:     %.6f deg; vector rx %.6f ry %.6f rz %.6f deg\n", AngleDeg(v), v[0] * kDegrees,
         v[1] * kDegrees, v[2] * kDegrees);
  Append(&out, "euler:        rx %.6f ry %.6f rz %.6f deg  (R = Rz Ry Rx)\n", euler_deg[0], euler_deg[1],
         euler_deg[2]);
  Append(&out, "translation:  tx %.6g ty %.6g tz %.6g %s  (shift of the moving centroid)\n", translation[0],
         translation[1], translation[2], u);
  Append(&out, "stddev:       rx %.3g ry %.3g rz %.3g deg, tx %.3g ty %.3g tz %.3g %s  (%s)\n",
         sd[0] * kDegrees, sd[1] * kDegrees, sd[2] * kDegrees, sd[3], sd[4], sd[5], u, stddev_source.c_str());
  const double z = 1.959963984540054;  // 95%, two-sided
  Append(&out, "95%% interval: rx +/-%.3g ry +/-%.3g rz +/-%.3g deg, tx +/-%.3g ty +/-%.3g tz +/-%.3g %s\n",
         z * sd[0] * kDegrees, z * sd[1] * kDegrees, z * sd[2] * kDegrees, z * sd[3], z * sd[4], z * sd[5], u);
  Append(&out, "rho'_d:       %.6g -> %.6g %s  (mean |dz| at the nodes)\n", before.rho_d_axial,
         after.rho_d_axial, u);
  Append(&out, "mean |dz|:    %.6g -> %.6g %s  (rho_d / overlap area; sampling gap %.3g)\n", before.mean_abs_dz,
         after.mean_abs_dz, u, sampling_gap);
  Append(&out, "overlap:      %.2f%% -> %.2f%% of the smaller data domain\n", 100 * overlap_fraction_before,
         100 * overlap_fraction_after);
  if (chord_correction != "none")
    Append(&out, "density:      the %s surface has %.2fx the other's area per sample: its chords corrected for curvature\n",
           chord_correction.c_str(), density_ratio);
  if (solve_cost == "axial at the sparser surface's nodes")
    Append(&out, "solved with:  the axial cost at the sparser surface's nodes (%.2fx the other's area per sample)\n",
           density_ratio);
  if (stable.done) {
    Append(&out, "stable:       %.1f%% of the overlap; %d changed region%s left out (%d round%s%s); gap noise %.3g %s\n",
           100 * stable.stable_share, stable.regions, stable.regions == 1 ? "" : "s", stable.rounds,
           stable.rounds == 1 ? "" : "s", stable.settled ? "" : ", not settled", stable.noise_sigma, u);
    if (!stable.warning.empty()) Append(&out, "warning:      %s\n", stable.warning.c_str());
  }
  if (holdout.done) {
    const HoldoutCheck& h = holdout;
    Append(&out, "held out:     %.0f%% of the reference's tiles (%lld samples): robust RMSE of dz %.6g -> %.6g (%s)\n",
           100 * h.fraction, static_cast<long long>(h.samples), h.robust_before, h.robust_after,
           h.improved ? "improved" : "NOT improved");
    Append(&out, "              before %s\n", DzStatisticsLine(h.before, "").c_str());
    Append(&out, "              after  %s\n", DzStatisticsLine(h.after, "").c_str());
  }
  Append(&out, "iterations:   %d  (%s)\n", iterations, termination.c_str());
  Append(&out, "time:         %.3f s\n", seconds);
  return out;
}

}  // namespace surfreg
