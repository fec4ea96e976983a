// surfreg jaw --config JAW.yaml [--key=value ...]: jaw motion over a 3D
// sequence (faces/jaw.h) with the settings of tools/jaw_config.h;
// writes the per-frame CSV, the JSON of 4×4 matrices (with σ, the path and
// the helical axes) and the plots where asked (atomically), a progress line
// per frame on stderr and a summary on stdout.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "faces/face_frame.h"
#include "measure/input_error.h"
#include "faces/jaw.h"
#include "io/atomic_file.h"
#include "tools/commands.h"
#include "io/interrupt.h"
#include "io/mesh_reader.h"
#include "io/surface_reader.h"
#include "tools/jaw_config.h"
#include "tools/json_writer.h"
#include "io/plot.h"

// The jaw's own keys as flags (strings, so tools/jaw_config.cc parses flags
// and files alike; "" = not given). The keys jaw shares with other commands
// (reference, orientation, cost, trim_fraction, normal_distance, max_iterations,
// max_fold_fraction, threads, progress) use those commands' flags of the same
// names, looked up by name, so every key is a flag without defining any twice.
DECLARE_bool(quiet);  // tools/run_measure.cc
DEFINE_string(frames, "", "jaw: a folder of frames or a list a.xyz,b.xyz,...");
DEFINE_string(boundary_y, "", "jaw: y level in the reference frame: upper at and above, lower below");
DEFINE_string(boundary_polygon, "", "jaw: polygon file (x y per line): inside = lower part");
DEFINE_string(boundary_margin, "", "jaw: drop points this close to the boundary");
DEFINE_string(step_tolerance, "", "jaw: converged after a step shorter than this (data units)");
DEFINE_string(volume_iterations, "", "jaw: cost volume: L-BFGS iterations after the axial solve");
DEFINE_string(predict, "", "jaw: constant-velocity warm start (true | false)");
DEFINE_string(min_part_points, "", "jaw: fewest points a part may have");
DEFINE_string(output_csv, "", "jaw: write the per-frame CSV here");
DEFINE_string(output_json, "", "jaw: write the per-frame matrices (JSON) here");
DEFINE_string(plot, "", "jaw: write a PNG of the six motion parameters here");
DEFINE_string(path_point, "", "jaw: x,y,z of the point whose path is reported (reference frame)");
DEFINE_string(path_plot, "", "jaw: write a PNG of the path point's displacement here");
DECLARE_string(config);

namespace surfreg {
namespace {

JawConfig LoadConfig(const std::vector<std::string>& args) {
  if (!args.empty()) throw UsageError("jaw: unexpected argument '" + args[0] + "' (settings go in --config)");
  if (FLAGS_config.empty()) throw UsageError("jaw: missing --config JAW.yaml");
  JawConfig config;
  ApplyJawConfigFile(FLAGS_config, &config);
  for (const JawConfigKey& key : JawConfigKeys()) {
    gflags::CommandLineFlagInfo info;
    if (gflags::GetCommandLineFlagInfo(key.name, &info) && !info.is_default) {
      ApplyJawFlag(key.name, info.current_value, &config);
    }
  }
  FinishJawConfig(&config);
  return config;
}

// The face frame of the reference (NormalizeFace), applied to every frame;
// identity for as_is.
struct Normalization {
  bool active = false;
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();  // frame point = matrix · input point
};

Normalization Normalize(const JawConfig& config) {
  Normalization n;
  if (config.orientation.orientation == FaceOrientation::kAsIs) return n;
  const FaceFrame frame = NormalizeFace(ReadMesh(config.frame_files[config.reference_index]), config.orientation);
  n.active = true;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) n.matrix(i, j) = frame.rotation[3 * i + j];
    n.matrix(i, 3) = frame.translation[i];
  }
  return n;
}

Surface LoadFrame(const std::string& path, const Normalization& n) {
  Surface surface = ReadSurface(path);
  if (!n.active) return surface;
  std::vector<std::array<double, 3>> points(surface.size());
  for (std::size_t i = 0; i < surface.size(); ++i) {
    const Eigen::Vector3d p(surface.xy[i].x + surface.origin[0], surface.xy[i].y + surface.origin[1],
                            surface.z[i] + surface.origin[2]);
    const Eigen::Vector3d q = n.matrix.topLeftCorner<3, 3>() * p + n.matrix.topRightCorner<3, 1>();
    points[i] = {q.x(), q.y(), q.z()};
  }
  return MakeSurface(points, {}, path);
}

JsonObject PartJson(const JawPartResult& p, bool reference) {
  JsonObject o;
  o.Int("points", p.points);
  if (reference) return o;
  o.String("verdict", VerdictName(p.verdict)).String("verdict_reason", p.verdict_reason);
  o.Int("iterations", p.iterations);
  o.Number("rho_d_axial_before", p.rho_d_axial_before).Number("rho_d_axial_after", p.rho_d_axial_after);
  o.Number("mean_abs_dz_after", p.mean_abs_dz_after).Number("overlap_area_after", p.overlap_area_after);
  o.Raw("reference_from_frame", JsonMatrix4(p.reference_from_frame));
  return o;
}

// A CSV number: %.9g, "nan" when undefined.
std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", value);
  return text;
}

std::string Vector(const Eigen::Vector3d& v) { return JsonNumbers({v.x(), v.y(), v.z()}); }

const char* VerdictText(const JawFrame& f, const JawPartResult& p) {
  return f.is_reference ? "reference" : VerdictName(p.verdict);
}

std::string Csv(const JawConfig& config, const JawSummary& s) {
  std::string csv =
      "frame,rx_deg,ry_deg,rz_deg,tx,ty,tz,file,upper_verdict,lower_verdict,upper_points,lower_points,"
      "dropped,upper_iterations,lower_iterations,upper_rho_d_axial,lower_rho_d_axial,upper_mean_abs_dz,"
      "lower_mean_abs_dz,seconds,rx_sd_deg,ry_sd_deg,rz_sd_deg,tx_sd,ty_sd,tz_sd,path_x,path_y,path_z,"
      "path_x_sd,path_y_sd,path_z_sd\n";
  char line[1024];
  for (const JawFrame& f : s.frames) {
    std::snprintf(line, sizeof(line), "%d,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%s,%s,%s,%d,%d,%d,%d,%d,%.9g,%.9g,%.9g,%.9g,%.4f",
                  f.index, f.euler_deg[0], f.euler_deg[1], f.euler_deg[2], f.translation[0], f.translation[1],
                  f.translation[2], config.frame_files[f.index].c_str(), VerdictText(f, f.upper), VerdictText(f, f.lower),
                  f.upper.points, f.lower.points, f.dropped, f.upper.iterations, f.lower.iterations,
                  f.upper.rho_d_axial_after, f.lower.rho_d_axial_after, f.upper.mean_abs_dz_after,
                  f.lower.mean_abs_dz_after, f.seconds);
    csv += line;
    for (double v : f.stddev) csv += "," + Number(v);
    for (int k = 0; k < 3; ++k) csv += "," + Number(f.path_point[k]);
    for (int k = 0; k < 3; ++k) csv += "," + Number(f.path_point_stddev[k]);
    csv += "\n";
  }
  return csv;
}

JsonObject BoundaryJson(const JawConfig& config, const JawSummary& s) {
  JsonObject o;
  if (s.boundary.polygon.empty()) {
    o.Number("y", s.boundary.y_level);
  } else {
    o.String("polygon", config.boundary_polygon);
  }
  o.String("found", s.boundary_found ? "automatic" : "given").Number("margin", s.boundary.margin);
  if (s.boundary_found) {
    const JawBoundarySearch& q = s.search;
    o.Int("frame", q.frame).Number("noise", q.noise).Number("threshold", q.threshold);
    o.Number("jaw_gap", q.jaw_gap).Int("points", q.points).Int("moving_points", q.moving_points);
    o.Int("misclassified", q.misclassified).Fixed("seconds", q.seconds, 4);
  }
  return o;
}

std::string Json(const JawConfig& config, const JawSummary& s, const Normalization& n) {
  std::vector<std::string> matrices, frames, files;
  for (const JawFrame& f : s.frames) {
    matrices.push_back(JsonMatrix4(f.jaw));
    files.push_back(JsonString(config.frame_files[f.index]));
    JsonObject o;
    o.Int("frame", f.index).String("file", config.frame_files[f.index]).Raw("matrix", JsonMatrix4(f.jaw));
    o.Raw("euler_deg", JsonArray({JsonNumber(f.euler_deg[0]), JsonNumber(f.euler_deg[1]), JsonNumber(f.euler_deg[2])}));
    o.Raw("translation",
          JsonArray({JsonNumber(f.translation[0]), JsonNumber(f.translation[1]), JsonNumber(f.translation[2])}));
    o.Raw("stddev", JsonNumbers(std::vector<double>(f.stddev.begin(), f.stddev.end())));
    o.Raw("path_point", Vector(f.path_point)).Raw("path_point_stddev", Vector(f.path_point_stddev));
    o.Object("upper", PartJson(f.upper, f.is_reference)).Object("lower", PartJson(f.lower, f.is_reference));
    o.Int("dropped", f.dropped).Fixed("seconds", f.seconds, 4);
    frames.push_back(o.str());
  }
  JsonObject root;
  root.String("description", "per frame, the lower part's motion relative to the upper part: "
                             "4x4 row-major, reference lower part -> frame lower part, skull coordinates");
  root.Int("reference", s.reference);
  root.String("orientation", JawConfigValue(config, "orientation"));
  root.Raw("normalization", JsonMatrix4(n.matrix));
  root.Object("boundary", BoundaryJson(config, s));
  JsonObject path;
  path.Raw("point_reference", Vector(s.path_reference));
  path.String("rule", s.path_point_given ? "given" : "lowest");
  path.String("description", s.path_point_given
                                 ? "path_point as given, reference frame coordinates"
                                 : "the mean of the 5 reference lower-part points of smallest y");
  root.Object("path", path);
  std::vector<std::string> axes;
  for (std::size_t k = 0; k < s.helical_axes.size(); ++k) {
    const HelicalAxis& h = s.helical_axes[k];
    JsonObject o;
    o.Int("from", static_cast<int64_t>(k)).Int("to", static_cast<int64_t>(k + 1));
    o.String("kind", HelicalKindName(h.kind)).Raw("direction", Vector(h.direction));
    o.Raw("point", Vector(h.point)).Number("angle_deg", h.angle_deg).Number("slide", h.slide);
    axes.push_back(o.str());
  }
  root.Raw("helical_axes", JsonArray(axes));
  root.Raw("files", JsonArray(files)).Raw("matrices", JsonArray(matrices)).Raw("frames", JsonArray(frames));
  root.Int("failed_frames", s.failed_frames).Fixed("seconds", s.seconds, 4);
  return root.str() + "\n";
}

void WritePlot(const JawConfig& config, const JawSummary& s) {
  const char* names[6] = {"rx (deg)", "ry (deg)", "rz (deg)", "tx", "ty", "tz"};
  std::vector<Series> series(6);
  for (int p = 0; p < 6; ++p) {
    series[p].name = names[p];
    series[p].markers = true;
    for (const JawFrame& f : s.frames) {
      series[p].x.push_back(f.index);
      series[p].y.push_back(p < 3 ? f.euler_deg[p] : f.translation[p - 3]);
    }
  }
  FigureText text;
  text.title = "jaw motion relative to the skull (reference frame " + std::to_string(s.reference) + ")";
  text.x_label = "frame";
  text.y_label = "rotation (deg, R = Rz Ry Rx) / translation (data units)";
  WriteChartPng(config.plot, series, text, ChartStyle(), config.Where("plot"));
}

// The path point's displacement from its reference position, y (up) against
// z (sagittal view) and against x (frontal view), on equal axes so that
// the path's shape is not distorted.
void WritePathPlot(const JawConfig& config, const JawSummary& s) {
  std::vector<Series> series(2);
  series[0].name = "sagittal: dz (horizontal), dy";
  series[1].name = "frontal: dx (horizontal), dy";
  double extent = 0;
  for (Series& line : series) line.markers = true;
  for (const JawFrame& f : s.frames) {
    const Eigen::Vector3d d = f.path_point - s.path_reference;
    series[0].x.push_back(d.z());
    series[0].y.push_back(d.y());
    series[1].x.push_back(d.x());
    series[1].y.push_back(d.y());
    extent = std::max(extent, d.cwiseAbs().maxCoeff());
  }
  ChartStyle style;
  style.width = style.height = 700;
  extent = extent > 0 ? 1.05 * extent : 1.0;
  style.x_min = style.y_min = -extent;
  style.x_max = style.y_max = extent;
  char point[128];
  std::snprintf(point, sizeof(point), "(%.3g, %.3g, %.3g)", s.path_reference.x(), s.path_reference.y(),
                s.path_reference.z());
  FigureText text;
  text.title = std::string("path of ") + point + " relative to the skull";
  text.x_label = "dz (sagittal) or dx (frontal), data units";
  text.y_label = "dy (data units, chin -> forehead)";
  WriteChartPng(config.path_plot, series, text, style, config.Where("path_plot"));
}

void PrintFrame(const JawConfig& config, const JawFrame& f) {
  if (!config.progress) return;
  if (f.is_reference) {
    std::fprintf(stderr, "jaw: frame %d (reference) %s: %d upper, %d lower, %d dropped points  %.2f s\n", f.index,
                 config.frame_files[f.index].c_str(), f.upper.points, f.lower.points, f.dropped, f.seconds);
    return;
  }
  std::fprintf(stderr,
               "jaw: frame %d: rx %.3f ry %.3f rz %.3f deg  t %.3f %.3f %.3f  upper %s (%d it, rho'_d %.3g)  "
               "lower %s (%d it, rho'_d %.3g)  %.2f s\n",
               f.index, f.euler_deg[0], f.euler_deg[1], f.euler_deg[2], f.translation[0], f.translation[1],
               f.translation[2], VerdictName(f.upper.verdict), f.upper.iterations, f.upper.rho_d_axial_after,
               VerdictName(f.lower.verdict), f.lower.iterations, f.lower.rho_d_axial_after, f.seconds);
}

}  // namespace

int RunJaw(const std::vector<std::string>& args) {
  JawConfig config = LoadConfig(args);
  if (FLAGS_quiet) config.progress = false;  // no per-frame lines (warnings still)
  const Normalization normalization = Normalize(config);
  config.options.on_frame = [&config](const JawFrame& f) { PrintFrame(config, f); };
  const JawSummary summary = TrackJaw(
      static_cast<int>(config.frame_files.size()),
      [&](int k) {
        ThrowIfInterrupted();  // between frames
        return LoadFrame(config.frame_files[k], normalization);
      },
      config.options);
  if (summary.failed_frames > 0) {
    LOG(WARNING) << "jaw: " << summary.failed_frames << " frames with a failed registration (see the CSV verdicts)";
  }
  if (!config.output_csv.empty()) WriteFileAtomically(config.output_csv, Csv(config, summary), config.Where("output_csv"));
  if (!config.output_json.empty()) {
    WriteFileAtomically(config.output_json, Json(config, summary, normalization), config.Where("output_json"));
  }
  if (!config.plot.empty()) WritePlot(config, summary);
  if (!config.path_plot.empty()) WritePathPlot(config, summary);
  std::printf("%s", summary.BriefReport().c_str());
  for (const char* key : {"output_csv", "output_json", "plot", "path_plot"}) {
    const std::string path = JawConfigValue(config, key);
    if (!path.empty()) std::printf("%-13s%s\n", (std::string(key) + ":").c_str(), path.c_str());
  }
  return 0;
}

}  // namespace surfreg
