// surfreg asymmetry FACE | FOLDER | SCAN1 SCAN2 [--orientation=auto|as_is|RX,RY,RZ]
// [--depth_limit=D] [--regions=NAME:FILE,...] [--map=MAP.png] [--points=D.csv|.ply]
// [--csv=TABLE.csv] [--norms=COHORT.csv] [--units=mm] [--threads=N|all] [--json]
// [--output=ASYMMETRY.json] [--quiet]: facial asymmetry (faces/symmetry.h, faces/asymmetry_index.h): the face in
// the standard frame against its mirror image about x = 0, then about the
// optimized symmetry plane, and the indices by region about that plane. A
// folder is a cohort (one table row per face); two scans of one face give
// the indices' differences (test-retest). A cohort's faces (and the two
// scans) are analysed side by side, one thread each.
//
// Orientation: without --orientation, a mesh (a file with triangles) is
// oriented automatically (principal axes and the nose heuristics) and a point
// cloud (.xyz, .txt, .csv: no triangles, so no visibility either) is taken as
// already in the face frame (as_is: only centred, max z = 0), which is what
// `surfreg normalize` writes and what the shipped face files are.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include "faces/asymmetry_cohort.h"
#include "faces/face_frame.h"
#include "faces/symmetry.h"
#include "io/atomic_file.h"
#include "io/mesh_reader.h"
#include "io/plot.h"
#include "measure/input_error.h"
#include "measure/tasks.h"
#include "tools/asymmetry_report.h"
#include "tools/commands.h"
#include "tools/face_orientation.h"
#include "tools/json_writer.h"
#include "tools/key_flags.h"

DEFINE_string(map, "",
              "asymmetry: write a PNG map of the left-right difference (face - mirror) about the "
              "refined plane here");
DEFINE_string(regions, "", "asymmetry: regions of your own, NAME:POLYGON_FILE[,NAME:FILE...] (face-frame x y)");
DEFINE_string(points, "", "asymmetry: write the difference at every point here (.csv or .ply)");
DEFINE_string(csv, "", "asymmetry: write the indices as a table, one row per face (a cohort's norms)");
DEFINE_string(norms, "", "asymmetry: a table written by --csv: add each index's z-score against it");
DEFINE_string(units, "units", "asymmetry: the scan's length unit, for labels (e.g. mm)");
DECLARE_string(orientation);  // tools/run_normalize.cc
DECLARE_double(depth_limit);  // tools/run_normalize.cc
DECLARE_bool(quiet);          // tools/run_measure.cc

namespace surfreg {
namespace {

constexpr int kMapCells = 360;  // grid cells along the face's longer side

std::string Format(const char* format, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), format, value + 0.0);
  return text;
}

struct Request {
  int threads = 0;  // 0: every core
  FaceFrameOptions frame_options;
  bool orientation_given = false;
  AsymmetryIndexOptions index_options;
  bool has_norms = false;
  AsymmetryNorms norms;
};

// Flags first: a mistake is reported before any work.
Request CheckFlags(bool single_face) {
  Request request;
  FaceOrientationFromString(FLAGS_orientation, "flag '--orientation'", &request.frame_options);
  gflags::CommandLineFlagInfo orientation;
  request.orientation_given =
      gflags::GetCommandLineFlagInfo("orientation", &orientation) && !orientation.is_default;
  if (!(FLAGS_depth_limit >= 0.0) || !std::isfinite(FLAGS_depth_limit)) {
    throw InputError("flag '--depth_limit': expected a number >= 0, got " + Format("%g", FLAGS_depth_limit));
  }
  request.frame_options.depth_limit = FLAGS_depth_limit;
  request.threads = ThreadsFlag();
  for (const auto& [path, flag] : {std::pair{FLAGS_map, "--map"}, std::pair{FLAGS_points, "--points"}}) {
    if (!path.empty() && !single_face) {
      throw InputError(std::string("flag '") + flag + "': one face at a time (not a folder or two scans)");
    }
  }
  if (!FLAGS_map.empty()) {
    if (!EndsWithLower(FLAGS_map, ".png")) throw InputError("flag '--map': " + FLAGS_map + ": expected a .png file name");
    RequirePngFigures("flag '--map'");
    CheckOutputPath(FLAGS_map, "flag '--map'");
  }
  if (!FLAGS_points.empty()) {
    if (!EndsWithLower(FLAGS_points, ".csv") && !EndsWithLower(FLAGS_points, ".ply")) {
      throw InputError("flag '--points': " + FLAGS_points + ": expected a .csv or .ply file name");
    }
    CheckOutputPath(FLAGS_points, "flag '--points'");
  }
  if (!FLAGS_csv.empty()) CheckOutputPath(FLAGS_csv, "flag '--csv'");
  if (!KeyFlag("output").empty()) CheckOutputPath(KeyFlag("output"), "flag '--output'");
  if (FLAGS_units.empty()) throw InputError("flag '--units': expected a unit name such as mm");
  if (!FLAGS_regions.empty()) request.index_options.regions = ReadFaceRegions(FLAGS_regions, "flag '--regions'");
  if (!FLAGS_norms.empty()) {
    std::ifstream in(FLAGS_norms, std::ios::binary);
    if (!in) throw InputError("flag '--norms': cannot read '" + FLAGS_norms + "'");
    std::ostringstream text;
    text << in.rdbuf();
    request.norms = ParseAsymmetryNorms(text.str(), FLAGS_norms);
    request.has_norms = true;
  }
  return request;
}

// One face on `threads` threads (0: every core). EstimateSymmetry's line
// search ends at |d|'s kink with a warning the termination message reports:
// the callers keep glog quiet around this.
FaceAsymmetry Analyze(const std::string& file, const Request& request, int threads) {
  FaceAsymmetry a;
  a.file = file;
  a.frame_options = request.frame_options;
  const Mesh mesh = ReadMesh(file);
  if (!request.orientation_given && mesh.triangles.empty()) a.frame_options.orientation = FaceOrientation::kAsIs;
  a.frame = NormalizeFace(mesh, a.frame_options);
  a.face = FaceSurface(a.frame, file);
  SymmetryOptions symmetry;
  symmetry.threads = threads;
  a.symmetry = EstimateSymmetry(a.face, symmetry);
  a.indices = ComputeAsymmetryIndices(a.face, a.symmetry.refined.plane, request.index_options);
  if (request.has_norms) a.z_scores = ZScores(request.norms, IndexValues(a.indices));
  return a;
}

void WriteMap(const FaceAsymmetry& a, const std::vector<FaceRegion>& regions) {
  const AsymmetryMap map = MapAsymmetry(a.face, a.symmetry.refined.plane, kMapCells);
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
  const RegionIndex& whole = a.indices.whole;
  const FigureText text{"face - mirror about the refined plane: RMS " + Format("%.3g", whole.rms) + " " +
                            FLAGS_units + ", max " + Format("%.3g", whole.max_abs) + " " + FLAGS_units,
                        "x, across the face, subject's right to left (" + FLAGS_units + ")",
                        "y, chin to forehead (" + FLAGS_units + ")"};
  MapStyle style;
  style.diverging = true;
  style.colorbar_label = "face - mirror (" + FLAGS_units + "; > 0: this side stands out)";
  // The regions: the thirds' edges, the plane's trace at the face's mean
  // depth (the halves' border), the user's polygons.
  for (int k = 1; k < 3; ++k) {
    style.outlines.push_back({{map.x_min, a.indices.thirds_y[k]}, {map.x_max, a.indices.thirds_y[k]}});
  }
  const SymmetryPlane& plane = a.symmetry.refined.plane;
  double depth = 0;
  for (const auto& p : a.frame.points) depth += p[2];
  depth /= static_cast<double>(std::max<std::size_t>(1, a.frame.points.size()));
  const auto trace_x = [&](double y) {
    return (plane.offset - plane.normal[1] * y - plane.normal[2] * depth) / plane.normal[0];
  };
  style.outlines.push_back({{trace_x(map.y_min), map.y_min}, {trace_x(map.y_max), map.y_max}});
  for (const FaceRegion& region : regions) {
    std::vector<std::array<double, 2>> ring = region.polygon;
    ring.push_back(ring.front());
    style.outlines.push_back(std::move(ring));
  }
  WriteMapPng(FLAGS_map, field, text, style, "flag '--map'");
}

std::string TableRow(const FaceAsymmetry& a) {
  std::string row = IndexTableRow(a.file, static_cast<int64_t>(a.face.size()), a.symmetry.angle_deg, a.indices);
  for (const ZScore& s : a.z_scores) row += "," + Format("%.6g", s.z);
  return row + "\n";
}

std::string TableHeader(const FaceAsymmetry& a) {
  std::string header = IndexTableHeader(a.indices);
  for (const ZScore& s : a.z_scores) header += ",z_" + s.name;
  return header + "\n";
}

std::vector<std::string> FolderFaces(const std::string& folder) {
  namespace fs = std::filesystem;
  std::vector<std::string> files;
  std::error_code error;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, error)) {
    if (!entry.is_regular_file(error)) continue;
    for (const char* ext : {".xyz", ".txt", ".ply", ".off", ".obj", ".las", ".laz"}) {
      if (EndsWithLower(entry.path().string(), ext)) files.push_back(entry.path().string());
    }
  }
  if (error) throw InputError(folder + ": cannot list the folder: " + error.message());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InputError(folder + ": no face files (.xyz .txt .ply .off .obj .las .laz)");
  return files;
}

void Finish(const std::string& json, const std::string& table) {
  if (!FLAGS_csv.empty()) WriteFileAtomically(FLAGS_csv, table, "flag '--csv'");
  if (!KeyFlag("output").empty()) WriteFileAtomically(KeyFlag("output"), json + "\n", "flag '--output'");
  if (FLAGS_json) std::printf("%s\n", json.c_str());
}

void PrintWritten() {
  for (const std::string& path : {FLAGS_map, FLAGS_points, FLAGS_csv, KeyFlag("output")}) {
    if (!path.empty()) std::printf("written: %s\n", path.c_str());
  }
}

// glog kept to errors while faces are analysed (Analyze); one switch for
// the faces analysed side by side, since the level is the process's.
class QuietLineSearch {
 public:
  QuietLineSearch() : level_(FLAGS_minloglevel) { FLAGS_minloglevel = google::GLOG_ERROR; }
  ~QuietLineSearch() { FLAGS_minloglevel = level_; }
  QuietLineSearch(const QuietLineSearch&) = delete;
  QuietLineSearch& operator=(const QuietLineSearch&) = delete;

 private:
  int level_;
};

// Faces of a cohort analysed at once, one thread each: a face keeps about
// one core busy (its stages are short), and each holds its scan in memory.
constexpr int kMaxFacesAtOnce = 8;

int FacesAtOnce(const Request& request, int faces) {
  return std::clamp(std::min(ExecutionFor(request.threads).threads, faces), 1, kMaxFacesAtOnce);
}

int RunOne(const std::string& file, const Request& request) {
  const FaceAsymmetry a = [&] {
    QuietLineSearch quiet;
    return Analyze(file, request, request.threads);
  }();
  if (!FLAGS_map.empty()) WriteMap(a, request.index_options.regions);
  if (!FLAGS_points.empty()) WritePointDifferences(a, FLAGS_points, "flag '--points'");
  Finish(FaceAsymmetryJson(a, FLAGS_map).str(), TableHeader(a) + TableRow(a));
  if (!FLAGS_json) {
    PrintFaceAsymmetry(a, FLAGS_units);
    PrintWritten();
  }
  return 0;
}

int RunCohort(const std::string& folder, const Request& request) {
  const std::vector<std::string> files = FolderFaces(folder);
  const int count = static_cast<int>(files.size());
  // Each face's outputs only (its scan is let go): a table row, its JSON,
  // its printed line.
  struct Face {
    std::string header, row, json, line;
  };
  std::vector<Face> results(files.size());
  {
    const int at_once = FacesAtOnce(request, count);
    QuietLineSearch quiet;
    std::mutex progress;
    ForEachItem(ExecutionFor(at_once), count, [&](int k) {  // the first failing face's error
      if (!FLAGS_quiet) {
        std::lock_guard<std::mutex> lock(progress);
        std::fprintf(stderr, "asymmetry: face %d/%d %s\n", k + 1, count, files[k].c_str());
      }
      const FaceAsymmetry a = Analyze(files[k], request, at_once > 1 ? 1 : request.threads);
      Face& face = results[k];
      face.header = TableHeader(a);
      face.row = TableRow(a);
      face.json = FaceAsymmetryJson(a, "").str();
      const RegionIndex* lower = a.indices.Find("lower_third");
      const RegionIndex* left = a.indices.Find("left");
      std::string z = "-";
      for (const ZScore& s : a.z_scores) {
        if (s.name == "face_rms") z = Format("%+.2f", s.z);
      }
      char line[512];
      std::snprintf(line, sizeof line, "%-40s %10.4f %12.5g %12.5g %12.5g %8s\n", files[k].c_str(),
                    a.symmetry.angle_deg, a.indices.whole.rms, lower != nullptr ? lower->rms : 0.0,
                    left != nullptr ? left->mean : 0.0, z.c_str());
      face.line = line;
    });
  }
  std::vector<std::string> faces;
  const std::string header = results.front().header;
  std::string table = header;
  for (int k = 0; k < count; ++k) {
    if (results[k].header != header) {
      throw InputError(files[k] + ": its indices differ from the first face's (regions off the face?)");
    }
    table += results[k].row;
    faces.push_back(std::move(results[k].json));
  }
  if (!FLAGS_json) {
    std::printf("%-40s %10s %12s %12s %12s %8s\n", "face", "angle_deg", "face_rms", "lower_rms", "left_mean", "z(rms)");
    for (const Face& face : results) std::fputs(face.line.c_str(), stdout);
  }
  JsonObject json;
  json.String("folder", folder).Int("faces", static_cast<int64_t>(files.size())).Raw("results", JsonArray(faces));
  Finish(json.str(), table);
  if (!FLAGS_json) PrintWritten();
  return 0;
}

int RunRetest(const std::string& first, const std::string& second, const Request& request) {
  FaceAsymmetry scans[2];
  {
    const int at_once = FacesAtOnce(request, 2);
    QuietLineSearch quiet;
    ForEachItem(ExecutionFor(at_once), 2, [&](int k) {
      scans[k] = Analyze(k == 0 ? first : second, request, at_once > 1 ? 1 : request.threads);
    });
  }
  const FaceAsymmetry& a = scans[0];
  const FaceAsymmetry& b = scans[1];
  const std::vector<IndexValue> va = IndexValues(a.indices), vb = IndexValues(b.indices);
  const std::vector<IndexValue> diff = IndexDifferences(va, vb);
  JsonObject differences;
  for (const IndexValue& d : diff) differences.Number(d.name, d.value);
  JsonObject json;
  json.Raw("scans", JsonArray({FaceAsymmetryJson(a, "").str(), FaceAsymmetryJson(b, "").str()}))
      .Object("differences", differences)
      .Number("plane_angle_deg", PlaneAngleDegrees(a.symmetry.refined.plane, b.symmetry.refined.plane));
  Finish(json.str(), TableHeader(a) + TableRow(a) + TableRow(b));
  if (FLAGS_json) return 0;
  std::printf("test-retest: %s and %s (second minus first; %s)\n", first.c_str(), second.c_str(),
              FLAGS_units.c_str());
  std::printf("  %-24s %14s %14s %14s\n", "index", "first", "second", "difference");
  for (std::size_t k = 0; k < diff.size(); ++k) {
    if (EndsWithLower(diff[k].name, "_area") || EndsWithLower(diff[k].name, "_max_abs")) continue;
    std::printf("  %-24s %14.6g %14.6g %+14.4g\n", diff[k].name.c_str(), va[k].value, vb[k].value, diff[k].value);
  }
  std::printf("planes %.4f deg apart\n", PlaneAngleDegrees(a.symmetry.refined.plane, b.symmetry.refined.plane));
  PrintWritten();
  return 0;
}

}  // namespace

int RunAsymmetry(const std::vector<std::string>& args) {
  if (args.empty()) throw UsageError("asymmetry: missing FACE (a face file, a folder of faces, or two scans)");
  if (args.size() > 2) throw UsageError("asymmetry: too many arguments (at most two scans of one face)");
  std::error_code error;
  const bool folder = args.size() == 1 && std::filesystem::is_directory(args[0], error);
  const Request request = CheckFlags(args.size() == 1 && !folder);
  if (folder) return RunCohort(args[0], request);
  if (args.size() == 2) return RunRetest(args[0], args[1], request);
  return RunOne(args[0], request);
}

}  // namespace surfreg
