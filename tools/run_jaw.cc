// surfreg jaw --config JAW.yaml [--key=value ...]: jaw motion over a 3D
// sequence (faces/jaw.h) with the settings of tools/jaw_config.h;
// writes the per-frame CSV, the JSON of 4×4 matrices and the plot where
// asked (atomically), a progress line per frame on stderr and a summary on
// stdout.
#include <gflags/gflags.h>
#include <glog/logging.h>

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

const char* VerdictText(const JawFrame& f, const JawPartResult& p) {
  return f.is_reference ? "reference" : VerdictName(p.verdict);
}

std::string Csv(const JawConfig& config, const JawSummary& s) {
  std::string csv =
      "frame,rx_deg,ry_deg,rz_deg,tx,ty,tz,file,upper_verdict,lower_verdict,upper_points,lower_points,"
      "dropped,upper_iterations,lower_iterations,upper_rho_d_axial,lower_rho_d_axial,upper_mean_abs_dz,"
      "lower_mean_abs_dz,seconds\n";
  char line[1024];
  for (const JawFrame& f : s.frames) {
    std::snprintf(line, sizeof(line), "%d,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%s,%s,%s,%d,%d,%d,%d,%d,%.9g,%.9g,%.9g,%.9g,%.4f\n",
                  f.index, f.euler_deg[0], f.euler_deg[1], f.euler_deg[2], f.translation[0], f.translation[1],
                  f.translation[2], config.frame_files[f.index].c_str(), VerdictText(f, f.upper), VerdictText(f, f.lower),
                  f.upper.points, f.lower.points, f.dropped, f.upper.iterations, f.lower.iterations,
                  f.upper.rho_d_axial_after, f.lower.rho_d_axial_after, f.upper.mean_abs_dz_after,
                  f.lower.mean_abs_dz_after, f.seconds);
    csv += line;
  }
  return csv;
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
  std::printf("%s", summary.BriefReport().c_str());
  for (const char* key : {"output_csv", "output_json", "plot"}) {
    const std::string path = JawConfigValue(config, key);
    if (!path.empty()) std::printf("%-13s%s\n", (std::string(key) + ":").c_str(), path.c_str());
  }
  return 0;
}

}  // namespace surfreg
