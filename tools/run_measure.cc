// surfreg measure A B [--volume=overlay|union] [--weights=uniform|per_point|mask:POLYGON_FILE]
// [--domain=data|hull] [--lod=L] [--reference_crs=CRS] [--moving_crs=CRS] [--frame=auto|enu|utm]
// [--band=N] [--window=C,R,W,H] [--json]: the volume between two surfaces and the measures
// derived from it (measure/measures.h), cut/fill beyond a level of detection, with counts and
// per-stage timings. Both surfaces are read as `align` reads them (tools/terrain.h: rasters with
// their band, window and CRS) and measured in one metric frame.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "measure/input_error.h"
#include "measure/measures.h"
#include "tools/align_config.h"
#include "tools/commands.h"
#include "tools/io/polygon_reader.h"
#include "tools/io/surface_reader_internal.h"
#include "tools/json_writer.h"
#include "tools/terrain_uncertainty.h"
#include "tools/terrain.h"

DEFINE_string(volume, "overlay",
              "measure: how the volume between the surfaces is integrated: overlay (exact, on "
              "the common refinement of the two triangulations) or union (the paper's, on the "
              "triangulation of A and B together)");
DEFINE_string(weights, "uniform",
              "measure, align: the weight of the integrals: uniform, per_point (the samples' weights, "
              "interpolated linearly) or mask:POLYGON_FILE (1 inside the polygon, 0 outside; "
              "one 'x y' vertex per line, input coordinates, '#' comments)");

DECLARE_string(domain);  // tools/run_align.cc: a key of align's too
DECLARE_string(domain_max_edge_spacings);
DECLARE_string(domain_min_thinness);
DECLARE_string(reference_crs);  // the terrain keys of align that measure reads too
DECLARE_string(moving_crs);
DECLARE_string(frame);
DECLARE_string(band);
DECLARE_string(window);
DECLARE_string(lod);
DECLARE_string(sigma_reference);
DECLARE_string(sigma_moving);
DECLARE_string(lod_confidence);

namespace surfreg {
namespace {

// The align keys that measure takes as flags: how A and B are read and
// which frame they are measured in, and the level of detection.
constexpr const char* kTerrainFlags[] = {"reference_crs", "moving_crs",      "frame",
                                         "band",          "window",          "lod",
                                         "sigma_reference", "sigma_moving", "lod_confidence"};

struct MeasureReport {
  std::string file_a, file_b;
  std::string mask_file;  // for WeightMode::kMask
  MeasureOptions options;
  MeasureSummary summary;
  AlignConfig config;              // the files and the terrain flags
  ChangeUncertainty uncertainty;   // with --sigma_reference / --sigma_moving
  GeoFrame frame;
  Crs crs_a, crs_b;
  bool metric = false;  // lengths in metres: a geographic pair's frame, or a projected CRS in m
  double read_s = 0.0;
  double total_s = 0.0;  // the whole command: read + Measure
};

VolumeMode ParseVolumeMode(const std::string& value) {
  if (value == "overlay") return VolumeMode::kOverlay;
  if (value == "union") return VolumeMode::kUnion;
  throw InputError("bad value " + io_internal::Quote(value) +
                   " for flag '--volume' (expected overlay or union)");
}

// --weights=uniform | per_point | mask:POLYGON_FILE
void ParseWeights(const std::string& value, MeasureReport* report) {
  MeasureOptions& options = report->options;
  const std::string mask = "mask:";
  if (value == "uniform") {
    options.weight = WeightMode::kUniform;
  } else if (value == "per_point") {
    options.weight = WeightMode::kPerPoint;
  } else if (value.compare(0, mask.size(), mask) == 0 && value.size() > mask.size()) {
    options.weight = WeightMode::kMask;
    report->mask_file = value.substr(mask.size());
    options.mask_polygon = ReadPolygon(report->mask_file);
  } else {
    throw InputError("bad value " + io_internal::Quote(value) +
                     " for flag '--weights' (expected uniform, per_point or mask:POLYGON_FILE)");
  }
  std::string error;
  if (!options.IsValid(&error)) {
    throw InputError((options.weight == WeightMode::kMask ? report->mask_file + ": " : "") + error);
  }
}

// A and B as align's reference and moving surfaces (messages say "argument
// A"), with the terrain flags given. Nothing is read yet.
AlignConfig MeasureConfig(const std::string& a, const std::string& b) {
  AlignConfig config;
  ApplyAlignArguments(a, b, &config);
  config.origin["reference"] = "argument A";
  config.origin["moving"] = "argument B";
  for (const char* key : kTerrainFlags) {
    gflags::CommandLineFlagInfo info;
    CHECK(gflags::GetCommandLineFlagInfo(key, &info)) << "no flag --" << key;
    if (!info.is_default) ApplyAlignFlag(key, info.current_value, &config);
  }
  return config;
}

// "m²", or "units²" when the frame's length unit is not known to be the metre.
std::string Unit(const MeasureReport& r, int power) {
  static const char* const kPowers[] = {"", "²", "³"};
  return (r.metric ? "m" : "units") + std::string(kPowers[std::clamp(power, 1, 3) - 1]);
}

// Volumes carry the weight's unit too when the weights are the samples'.
std::string VolumeUnit(const MeasureReport& r) {
  return Unit(r, 3) + (r.options.weight == WeightMode::kPerPoint ? " × weight" : "");
}

bool HasChange(const MeasureReport& r) { return r.options.detect_change; }

void PrintJson(const MeasureReport& r) {
  const MeasureSummary& s = r.summary;
  JsonObject timings;
  // Seconds to the nanosecond (the clock's resolution); the measures above in full.
  timings.Fixed("read", r.read_s, 9)
      .Fixed("triangulate", s.timings.triangulate, 9)
      .Fixed("domain", s.timings.domain, 9)
      .Fixed("spanning_tree", s.timings.spanning_tree, 9)
      .Fixed("locate", s.timings.locate, 9)
      .Fixed("interpolate", s.timings.interpolate, 9)
      .Fixed("volume", s.timings.volume, 9)
      .Fixed("measure", s.timings.total, 9)  // Measure() alone
      .Fixed("total", r.total_s, 9);         // the whole command: read + measure
  JsonObject json;
  json.String("file_a", r.file_a)
      .String("file_b", r.file_b)
      .String("frame", r.frame.Describe())
      .String("crs_a", DescribeCrs(r.crs_a))
      .String("crs_b", DescribeCrs(r.crs_b))
      .String("length_unit", r.metric ? "m" : "units")
      .String("volume_mode", VolumeModeName(s.volume_mode))
      .String("weight_mode", WeightModeName(r.options.weight))
      .String("domain", DomainKindName(s.domain_kind));
  if (r.options.weight == WeightMode::kMask) {
    json.String("mask_file", r.mask_file)
        .Int("mask_vertices", static_cast<int64_t>(r.options.mask_polygon.size()));
  }
  json.Number("rho_d", s.rho_d)
      .Number("rho_d_axial", s.rho_d_axial)
      .Number("rho_s", s.rho_s)
      .Number("overlap_area", s.overlap_area)
      .Number("domain_area_a", s.domain_area_a)
      .Number("domain_area_b", s.domain_area_b)
      .Number("excluded_area_a", s.excluded_area_a)
      .Number("excluded_area_b", s.excluded_area_b)
      .Number("weight_integral", s.weight_integral)
      .Number("mean_abs_dz", s.mean_abs_dz)
      .Number("signed_volume", s.signed_volume)
      .Number("volume_above", s.volume_above)
      .Number("volume_below", s.volume_below)
      .Int("n_points_a", s.n_points_a)
      .Int("n_points_b", s.n_points_b)
      .Int("n_duplicates_a", s.n_duplicates_a)
      .Int("n_duplicates_b", s.n_duplicates_b)
      .Int("n_overlap_nodes", s.n_overlap_nodes)
      .Int("n_cells", s.n_cells)
      .Int("walk_steps", s.walk_steps);
  if (HasChange(r)) {  // the keys of align's terrain.change
    JsonObject change = DetectedChangeJson(s);
    if (r.uncertainty.active) change.Object("uncertainty", ChangeUncertaintyJson(r.config, r.uncertainty));
    json.Object("change", change);
  }
  json.Object("timings", timings);
  std::printf("%s\n", json.str().c_str());
}

void PrintText(const MeasureReport& r) {
  const MeasureSummary& s = r.summary;
  const std::string volume = VolumeUnit(r);
  const std::string length = Unit(r, 1), area = Unit(r, 2);
  const bool union_mode = s.volume_mode == VolumeMode::kUnion;
  std::printf("surface A:          %s  (%lld points, %lld duplicates merged; CRS %s)\n",
              r.file_a.c_str(), static_cast<long long>(s.n_points_a),
              static_cast<long long>(s.n_duplicates_a), DescribeCrs(r.crs_a).c_str());
  std::printf("surface B:          %s  (%lld points, %lld duplicates merged; CRS %s)\n",
              r.file_b.c_str(), static_cast<long long>(s.n_points_b),
              static_cast<long long>(s.n_duplicates_b), DescribeCrs(r.crs_b).c_str());
  std::printf("frame:              %s\n", r.frame.Describe().c_str());
  std::printf("volume mode:        %s  (%s)\n", VolumeModeName(s.volume_mode),
              union_mode ? "the paper's: on the triangulation of A and B together"
                         : "exact: on the common refinement of both triangulations");
  if (r.options.weight == WeightMode::kMask) {
    std::printf("weights:            mask  (1 inside the %zu-vertex polygon of %s)\n",
                r.options.mask_polygon.size(), r.mask_file.c_str());
  } else {
    std::printf("weights:            %s\n", WeightModeName(r.options.weight));
  }
  std::printf("rho_d   (ρd):       %.10g %s  (volume between the surfaces over the overlap)\n",
              s.rho_d, volume.c_str());
  std::printf(
      "rho'_d  (ρ'd):      %.10g %s  (mean |dz| at the %lld sample nodes in the overlap)\n",
      s.rho_d_axial, length.c_str(), static_cast<long long>(s.n_overlap_nodes));
  std::printf("rho_s   (ρs):       %.10g  (1 / ρd; 1 when ρd = 0)\n", s.rho_s);
  const bool hull = s.domain_kind == DomainKind::kHull;
  std::printf("domain:             %s  (%s)\n", DomainKindName(s.domain_kind),
              hull ? "the whole convex hulls"
                   : "without the triangles that bridge voids, holes and concave outlines");
  std::printf("overlap area:       %.10g %s  (common part of the two %s)\n", s.overlap_area,
              area.c_str(), hull ? "convex hulls" : "data domains");
  std::printf("domain area A / B:  %.10g / %.10g %s  (excluded from the hulls: %.10g / %.10g)\n",
              s.domain_area_a, s.domain_area_b, area.c_str(), s.excluded_area_a,
              s.excluded_area_b);
  if (r.options.weight != WeightMode::kUniform) {
    std::printf("weight integral:    %.10g %s%s\n", s.weight_integral, area.c_str(),
                r.options.weight == WeightMode::kPerPoint ? " × weight" : "");
  }
  std::printf("mean |dz|:          %.10g %s  (ρd / weight integral)\n", s.mean_abs_dz,
              length.c_str());
  std::printf("signed volume:      %.10g %s  (B − A)\n", s.signed_volume + 0.0, volume.c_str());
  std::printf("volume above:       %.10g %s  (B above A, \"fill\")\n", s.volume_above,
              volume.c_str());
  std::printf("volume below:       %.10g %s  (B below A, \"cut\")\n", s.volume_below,
              volume.c_str());
  if (HasChange(r)) {
    const double lod = s.level_of_detection;
    std::printf("level of detection: %.10g %s  (|dz| <= L counts as no change)\n", lod,
                length.c_str());
    std::printf("fill:               %.10g %s  ± %.10g  (B above A by more than L; ± L × area)\n",
                s.fill_detected, volume.c_str(), lod * s.fill_area);
    std::printf("cut:                %.10g %s  ± %.10g  (B below A by more than L)\n",
                s.cut_detected, volume.c_str(), lod * s.cut_area);
    std::printf("net:                %.10g %s  ± %.10g  (fill − cut)\n",
                s.fill_detected - s.cut_detected + 0.0, volume.c_str(),
                lod * (s.fill_area + s.cut_area));
    std::printf("fill / cut area:    %.10g / %.10g %s  (where |dz| > L)\n", s.fill_area,
                s.cut_area, area.c_str());
  }
  if (r.uncertainty.active) {
    std::printf("%s\n", ChangeUncertaintySummary(r.config, r.uncertainty, r.metric ? "m" : "data units").c_str());
  }
  std::printf("%s %lld\n", union_mode ? "union triangles:   " : "overlay cells:     ",
              static_cast<long long>(s.n_cells));
  std::printf("walk steps:         %lld\n", static_cast<long long>(s.walk_steps));
  std::printf("time read:          %.6f s\n", r.read_s);
  std::printf("time triangulate:   %.6f s\n", s.timings.triangulate);
  std::printf("time domain:        %.6f s\n", s.timings.domain);
  std::printf("time spanning tree: %.6f s\n", s.timings.spanning_tree);
  std::printf("time locate:        %.6f s\n", s.timings.locate);
  std::printf("time interpolate:   %.6f s\n", s.timings.interpolate);
  std::printf("time volume:        %.6f s\n", s.timings.volume);
  std::printf("time total:         %.6f s\n", r.total_s);
}

double Seconds(std::chrono::steady_clock::duration d) {
  return std::chrono::duration<double>(d).count();
}

}  // namespace

int RunMeasure(const std::vector<std::string>& args) {
  if (args.size() < 2)
    throw UsageError(args.empty() ? "measure: missing A and B" : "measure: missing B");
  if (args.size() > 2) throw UsageError("measure: too many arguments");
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  MeasureReport report;
  report.file_a = args[0];
  report.file_b = args[1];
  // Flags first: a bad flag value is reported before any file is read.
  MeasureOptions& options = report.options;
  options.volume = ParseVolumeMode(FLAGS_volume);
  options.domain = DomainRuleFromFlags(FLAGS_domain, FLAGS_domain_max_edge_spacings,
                                       FLAGS_domain_min_thinness);
  ParseWeights(FLAGS_weights, &report);
  const AlignConfig config = MeasureConfig(report.file_a, report.file_b);
  // Cut/fill is integrated on the overlay's cells: always there, absent from union.
  options.detect_change = options.volume == VolumeMode::kOverlay;
  options.level_of_detection = config.terrain.lod;
  if (!options.detect_change && config.origin.count("lod") != 0) {
    throw InputError(config.Where("lod") +
                     ": cut/fill beyond a level of detection needs --volume=overlay");
  }
  const bool sigma = !config.terrain.sigma_reference.empty() || !config.terrain.sigma_moving.empty();
  if (config.terrain.lod_confidence > 0 && !sigma) {
    throw InputError(config.Where("lod_confidence") +
                     " needs the DEMs' vertical errors: give --sigma_reference and/or --sigma_moving");
  }
  if (sigma && !options.detect_change) {
    const char* key = config.terrain.sigma_reference.empty() ? "sigma_moving" : "sigma_reference";
    throw InputError(config.Where(key) + ": the change budget needs --volume=overlay");
  }
  options.keep_node_gaps = sigma;  // the budget weights dz at A's nodes by their areas
  TerrainInputs inputs = ReadTerrainInputs(config);
  report.frame = inputs.frame;
  report.crs_a = inputs.reference_crs;
  report.crs_b = inputs.moving_crs;
  report.metric = inputs.frame.kind != GeoFrame::kAsGiven ||
                  (inputs.reference_crs.kind == CrsKind::kProjected &&
                   inputs.reference_crs.metres_per_unit == 1.0);
  if (options.weight == WeightMode::kMask && inputs.frame.kind != GeoFrame::kAsGiven) {
    // The polygon is drawn in A's lon/lat: its vertices go where A went.
    std::vector<std::array<double, 3>> vertices;
    for (const auto& p : options.mask_polygon) vertices.push_back({p[0], p[1], 0.0});
    PointsToFrame(inputs.frame, inputs.reference_crs, &vertices);
    for (std::size_t i = 0; i < vertices.size(); ++i) {
      options.mask_polygon[i] = {vertices[i][0], vertices[i][1]};
    }
  }
  const Surface& a = inputs.reference;
  const Surface& b = inputs.moving;
  const Clock::time_point read = Clock::now();
  report.summary = Measure(a, b, report.options);
  report.config = config;
  report.uncertainty = AnalyseChangeUncertainty(config, a, b, inputs.sigma_reference,
                                                inputs.sigma_moving, report.summary, report.options);
  const Clock::time_point done = Clock::now();
  report.read_s = Seconds(read - start);
  report.total_s = Seconds(done - start);
  // A height field has one z per xy: repeated xy samples are merged with
  // their heights averaged, which users should know about.
  const std::pair<const std::string*, int64_t> merged[] = {
      {&report.file_a, report.summary.n_duplicates_a}, {&report.file_b, report.summary.n_duplicates_b}};
  for (const auto& [file, count] : merged) {
    if (count > 0) {
      LOG(WARNING) << *file << ": " << count << (count == 1 ? " sample repeats" : " samples repeat")
                   << " the xy of another; their heights are averaged";
    }
  }
  LOG(INFO) << "measured " << report.file_b << " against " << report.file_a << " in "
            << report.total_s << " s";
  if (FLAGS_json) {
    PrintJson(report);
  } else {
    PrintText(report);
  }
  return 0;
}

}  // namespace surfreg
