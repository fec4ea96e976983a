// surfreg asymmetry FACE [--orientation=auto|as_is|RX,RY,RZ] [--depth_limit=D]
// [--map=MAP.png] [--json] [--output=ASYMMETRY.json]: facial asymmetry
// (faces/symmetry.h): the face in the standard frame against its
// mirror image about x = 0, then about the optimized symmetry plane.
//
// Orientation: without --orientation, a mesh (a file with triangles) is
// oriented automatically (principal axes and the nose heuristics) and a point
// cloud (.xyz, .txt, .csv: no triangles, so no visibility either) is taken as
// already in the face frame (as_is: only centred, max z = 0), which is what
// `surfreg normalize` writes and what the shipped face files are.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "faces/face_frame.h"
#include "measure/input_error.h"
#include "faces/symmetry.h"
#include "io/atomic_file.h"
#include "tools/commands.h"
#include "tools/face_orientation.h"
#include "io/mesh_reader.h"
#include "tools/json_writer.h"
#include "tools/key_flags.h"
#include "io/plot.h"

DEFINE_string(map, "",
              "asymmetry: write a PNG map of the left-right difference (face - mirror) about the "
              "refined plane here");
DECLARE_string(orientation);  // tools/run_normalize.cc
DECLARE_double(depth_limit);  // tools/run_normalize.cc

namespace surfreg {
namespace {

constexpr int kMapCells = 360;  // grid cells along the face's longer side

bool EndsWithPng(const std::string& path) {
  if (path.size() < 4) return false;
  std::string tail = path.substr(path.size() - 4);
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tail == ".png";
}

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value + 0.0);
  return text;
}

// Flags first: a mistake is reported before any work.
FaceFrameOptions CheckFlags() {
  FaceFrameOptions options;
  FaceOrientationFromString(FLAGS_orientation, "flag '--orientation'", &options);
  if (!(FLAGS_depth_limit >= 0.0) || !std::isfinite(FLAGS_depth_limit)) {
    throw InputError("flag '--depth_limit': expected a number >= 0, got " +
                     Format("%g", FLAGS_depth_limit));
  }
  options.depth_limit = FLAGS_depth_limit;
  if (!FLAGS_map.empty()) {
    if (!EndsWithPng(FLAGS_map)) {
      throw InputError("flag '--map': " + FLAGS_map + ": expected a .png file name");
    }
    RequirePngFigures("flag '--map'");
    CheckOutputPath(FLAGS_map, "flag '--map'");
  }
  if (!KeyFlag("output").empty()) CheckOutputPath(KeyFlag("output"), "flag '--output'");
  return options;
}

std::string Triple(const std::array<double, 3>& v) {
  return JsonArray({JsonNumber(v[0]), JsonNumber(v[1]), JsonNumber(v[2])});
}

JsonObject EstimateJson(const SymmetryEstimate& e) {
  JsonObject plane;
  plane.Raw("normal", Triple(e.plane.normal)).Number("offset", e.plane.offset);
  const MeasureSummary& m = e.measure;
  JsonObject json;
  json.Number("rho_d", m.rho_d)
      .Number("mean_abs_dz", m.mean_abs_dz)
      .Number("overlap_area", m.overlap_area)
      .Object("plane", plane)
      .Number("rho_d_per_area", m.overlap_area > 0 ? m.rho_d / m.overlap_area : 0.0)
      .Number("rho_d_axial", m.rho_d_axial)
      .Number("signed_volume", m.signed_volume)
      .Number("volume_above", m.volume_above)
      .Number("volume_below", m.volume_below)
      .Int("n_overlap_nodes", m.n_overlap_nodes);
  return json;
}

std::string ResultJson(const std::string& file, const FaceFrameOptions& options,
                       const Surface& face, const SymmetryResult& r) {
  JsonObject json;
  json.String("face", file)
      .String("orientation", FaceOrientationToString(options))
      .Number("depth_limit", options.depth_limit)
      .Int("points", static_cast<int64_t>(face.size()))
      .Object("initial", EstimateJson(r.initial))
      .Object("refined", EstimateJson(r.refined))
      .Raw("improved", r.improved ? "true" : "false")
      .String("note", r.note)
      .Number("angle_deg", r.angle_deg)
      .Int("iterations", r.iterations)
      .String("termination", r.termination)
      .Fixed("seconds_refine", r.seconds_refine, 4)
      .Fixed("seconds", r.seconds, 4);
  if (!FLAGS_map.empty()) json.String("map", FLAGS_map);
  return json.str();
}

void PrintRow(const char* name, const std::string& a, const std::string& b) {
  std::printf("  %-38s %-32s %s\n", name, a.c_str(), b.c_str());
}

std::string PlaneText(const SymmetryPlane& p) {
  return "(" + Format("%.6f", p.normal[0]) + ", " + Format("%.6f", p.normal[1]) + ", " +
         Format("%.6f", p.normal[2]) + ")";
}

void PrintText(const std::string& file, const FaceFrameOptions& options, const Surface& face,
               const SymmetryResult& r) {
  std::printf("face:  %s  (%zu points in the face frame, orientation %s)\n", file.c_str(),
              face.size(), FaceOrientationToString(options).c_str());
  const MeasureSummary &a = r.initial.measure, &b = r.refined.measure;
  PrintRow("", "initial (x = 0)", "refined plane");
  PrintRow("rho_d (units^3)", Format("%.6g", a.rho_d), Format("%.6g", b.rho_d));
  PrintRow("rho_d per area = mean |dz| (units)", Format("%.6g", a.mean_abs_dz),
           Format("%.6g", b.mean_abs_dz));
  PrintRow("rho'_d: mean |dz| at the nodes (units)", Format("%.6g", a.rho_d_axial),
           Format("%.6g", b.rho_d_axial));
  PrintRow("overlap area (units^2)", Format("%.6g", a.overlap_area), Format("%.6g", b.overlap_area));
  PrintRow("plane normal", PlaneText(r.initial.plane), PlaneText(r.refined.plane));
  PrintRow("plane offset (units)", Format("%.6g", r.initial.plane.offset),
           Format("%.6g", r.refined.plane.offset));
  std::printf("angle between the planes: %.4f deg\n", r.angle_deg);
  std::printf("refinement: %d iterations, %.3f s (%s); total %.3f s\n", r.iterations,
              r.seconds_refine, r.termination.c_str(), r.seconds);
  if (!r.note.empty()) std::printf("note: %s\n", r.note.c_str());
  if (!FLAGS_map.empty()) std::printf("map: %s\n", FLAGS_map.c_str());
  if (!KeyFlag("output").empty()) std::printf("written: %s\n", KeyFlag("output").c_str());
}

void WriteMap(const Surface& face, const SymmetryPlane& plane) {
  const AsymmetryMap map = MapAsymmetry(face, plane, kMapCells);
  GridField field;
  field.columns = map.columns;
  field.rows = map.rows;
  // Shown as face − mirror: positive (red) where this side of the face
  // stands out more than its mirror-image side.
  field.values = map.values;
  for (double& value : field.values) value = -value;
  field.x_min = map.x_min;
  field.x_max = map.x_max;
  field.y_min = map.y_min;
  field.y_max = map.y_max;
  const FigureText text{"Left-right difference about the refined symmetry plane",
                        "x, across the face (units)", "y, chin to forehead (units)"};
  MapStyle style;
  style.diverging = true;
  style.colorbar_label = "face - mirror height (units; > 0: this side stands out)";
  WriteMapPng(FLAGS_map, field, text, style, "flag '--map'");
}

}  // namespace

int RunAsymmetry(const std::vector<std::string>& args) {
  if (args.empty()) throw UsageError("asymmetry: missing FACE");
  if (args.size() > 1) throw UsageError("asymmetry: too many arguments");
  FaceFrameOptions frame_options = CheckFlags();
  const Mesh mesh = ReadMesh(args[0]);
  gflags::CommandLineFlagInfo orientation;
  if (gflags::GetCommandLineFlagInfo("orientation", &orientation) && orientation.is_default &&
      mesh.triangles.empty()) {
    frame_options.orientation = FaceOrientation::kAsIs;
  }
  const Surface face = FaceSurface(NormalizeFace(mesh, frame_options), args[0]);
  SymmetryResult result;
  {
    // At the optimum |d| has a kink, where the line search ends with a
    // warning; the termination message reports it, so keep stderr quiet.
    const int level = FLAGS_minloglevel;
    FLAGS_minloglevel = google::GLOG_ERROR;
    try {
      result = EstimateSymmetry(face);
    } catch (...) {
      FLAGS_minloglevel = level;
      throw;
    }
    FLAGS_minloglevel = level;
  }
  if (!FLAGS_map.empty()) WriteMap(face, result.refined.plane);
  const std::string json = ResultJson(args[0], frame_options, face, result);
  if (!KeyFlag("output").empty()) WriteFileAtomically(KeyFlag("output"), json + "\n", "flag '--output'");
  if (FLAGS_json) {
    std::printf("%s\n", json.c_str());
  } else {
    PrintText(args[0], frame_options, face, result);
  }
  return 0;
}

}  // namespace surfreg
