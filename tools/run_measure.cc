// surfreg measure A B [--volume=overlay|union] [--weights=uniform|per_point|mask:POLYGON_FILE]
// [--domain=data|hull] [--lod=L] [--reference_crs=CRS] [--moving_crs=CRS] [--frame=auto|enu|utm]
// [--band=N] [--window=C,R,W,H] [--json]: the volume between two surfaces and the measures
// derived from it (measure/measures.h), cut/fill beyond a level of detection, with counts and
// per-stage timings. Both surfaces are read as `align` reads them (terrain/terrain.h: rasters with
// their band, window and CRS) and measured in one metric frame.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "tools/commands.h"
#include "io/interrupt.h"
#include "tools/json_writer.h"
#include "tools/measure_parts.h"
#include "tools/measure_run.h"
#include "tools/measure_tiled.h"
#include "tools/progress_lines.h"
#include "tools/sweep.h"
#include "tools/key_flags.h"
#include "terrain/change_uncertainty.h"

// The run itself is tools/measure_run.cc (shared with the Python module);
// its settings are these flags, the library's measure keys and the align
// keys of MeasureKeys(), found by name (tools/key_flags.cc makes those).
DEFINE_bool(quiet, false, "measure, align, sweep, transform, asymmetry, jaw: no progress lines on stderr (errors and warnings still)");
DEFINE_string(weights, "uniform",
              "measure, align: the weight of the integrals: uniform, per_point (the samples' weights, "
              "interpolated linearly) or mask:FILE (1 inside the mask, 0 outside: 'x y' text, "
              "one vertex per line, '>' between rings, '#' comments; or a vector file such as "
              ".gpkg, .shp, .geojson; holes and several parts by the even-odd rule)");

DEFINE_int32(tile, 0,
             "measure: measure two DEMs in tiles of this many cells of A a side (16 to 32768; 0: "
             "untiled), each read as a window: memory bounded by the tile, the same results");
DEFINE_string(partial, "",
              "measure: with --shard=K/N (tiled), where the shard's partial result goes (P.json), "
              "for 'surfreg merge OUT.json P1.json ...'");
DECLARE_string(shard);  // tools/run_sweep.cc: "K/N"
DECLARE_bool(resume);   // tools/run_sweep.cc

DEFINE_string(max_memory, "",
              "measure, align: a memory budget such as 512M or 2G, from which the tile side is chosen "
              "(two DEMs in one projected CRS; about 700 bytes per cell of a tile); align: the "
              "motion solved on patches within it");

namespace surfreg {
namespace {

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
  if (!r.b_reprojected_from.empty()) {
    std::printf("reprojected:        B from %s into A's %s\n", r.b_reprojected_from.c_str(), r.crs_a.name.c_str());
  }
  std::printf("volume mode:        %s  (%s)\n", VolumeModeName(s.volume_mode),
              union_mode ? "the paper's: on the triangulation of A and B together"
                         : "exact: on the common refinement of both triangulations");
  if (r.options.weight == WeightMode::kMask) {
    std::printf("weights:            mask  (%s the %zu ring%s, %zu vertices, of %s)\n",
                r.options.mask_mode == MaskMode::kExclude ? "1 outside" : "1 inside",
                r.options.mask.size(), r.options.mask.size() == 1 ? "" : "s", MaskVertices(r.options),
                r.mask_file.c_str());
  } else {
    std::printf("weights:            %s\n", WeightModeName(r.options.weight));
  }
  if (r.tile > 0) {
    std::printf("tiles:              %lld of %d x %d cells of A  (read and measured one at a time)\n",
                static_cast<long long>(r.tiles), r.tile, r.tile);
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

// A line per stage on stderr, with the time left if the run goes as a
// typical one does: from the start for clouds of 200,000 samples or more
// (about a second of work), else once the measure has run for a second.
void PrintMeasureProgress(const MeasureProgress& p) {
  if (FLAGS_quiet || (p.seconds < 1.0 && p.points < 200000)) return;
  if (p.done > 0) {
    std::fprintf(stderr, "measure: %s (%.0f%% done, %.1f s, about %.1f s left)\n", p.stage,
                 100 * p.done, p.seconds, p.seconds * (1 - p.done) / p.done);
  } else {
    std::fprintf(stderr, "measure: %s (%.1f s)\n", p.stage, p.seconds);
  }
}

}  // namespace

int RunMeasure(const std::vector<std::string>& args) {
  if (args.size() < 2)
    throw UsageError(args.empty() ? "measure: missing A and B" : "measure: missing B");
  if (args.size() > 2) throw UsageError("measure: too many arguments");
  std::vector<Setting> settings;  // the flags given on the command line
  for (const std::string& key : MeasureKeys()) {
    gflags::CommandLineFlagInfo info;
    CHECK(gflags::GetCommandLineFlagInfo(key.c_str(), &info)) << "no flag --" << key;
    if (!info.is_default) settings.push_back({key, info.current_value, "flag '--" + key + "'"});
  }
  const TiledParts parts = TiledPartsOf(
      FLAGS_shard, FLAGS_partial, FLAGS_resume, [](const std::string& key) { return "flag '--" + key + "'"; },
      "--partial=P.json");
  if (!FLAGS_quiet && LargeInputs({args[0], args[1]})) PrintReadingLine("measure", {args[0], args[1]});
  const MeasureReport report =
      MeasureSurfaces({args[0], {}}, {args[1], {}}, settings, PrintMeasureProgress, &parts);
  ThrowIfInterrupted();  // no report of an interrupted run
  if (parts.shards > 1) {
    if (FLAGS_quiet) return 0;
    std::fprintf(stderr,
                 "measure: shard %d/%d: %lld tiles in %s; join the %d shards with 'surfreg merge "
                 "OUT.json P1.json ...' (and --dod=DOD.tif for their DoD bands)\n",
                 parts.shard, parts.shards, static_cast<long long>(report.tiles),
                 parts.partial.c_str(), parts.shards);
    return 0;
  }
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
    std::printf("%s\n", MeasureJson(report).c_str());
  } else {
    PrintText(report);
  }
  return 0;
}

int RunMergeMeasureParts(const std::vector<std::string>& args) {
  return MergeMeasureParts(args, KeyFlag("dod"), FLAGS_json, PrintText);
}

}  // namespace surfreg
