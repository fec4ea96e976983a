// surfreg align --config FILE.yaml [--key=value ...] | REFERENCE MOVING [--key=value ...]:
// rigid registration of MOVING onto REFERENCE (registration/align.h), with the
// settings of tools/align_config.h; writes the transform JSON, the aligned
// surface and a per-iteration CSV where asked, and prints a summary.
#include <gflags/gflags.h>
#include <glog/logging.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "measure/input_error.h"
#include "registration/align.h"
#include "tools/align_config.h"
#include "tools/align_run.h"
#include "tools/commands.h"
#include "tools/json_writer.h"
#include "tools/progress_lines.h"
#include "terrain/terrain.h"

// Every config key is a flag. Non-boolean flags are strings, so that
// tools/align_config.cc parses values from files and flags alike (same
// checks, same messages); "" (the default) means "not given". The defaults
// are AlignOptions' (docs/align.md), not repeated here.
DECLARE_bool(quiet);  // tools/run_measure.cc
DEFINE_string(config, "", "align: the YAML config file (instead of REFERENCE MOVING)");
DEFINE_string(reference, "", "align: the fixed surface file");
DEFINE_string(moving, "", "align: the surface file moved onto the reference");
DEFINE_string(cost, "", "align: volume (rho_d per overlap area) | axial (rho'_d, least squares)");
DEFINE_bool(prealign, true, "align: volume cost: first solve with the axial cost (coarsest level)");
DEFINE_string(loss, "", "align: none | huber | soft_l1 | cauchy (axial cost)");
DEFINE_string(loss_scale, "", "align: robust loss scale, data units");
DEFINE_string(trust_region, "", "align: levenberg_marquardt | dogleg (axial cost)");
DEFINE_string(line_search, "", "align: lbfgs | bfgs | nonlinear_cg (volume cost)");
DEFINE_string(linear_solver, "", "align: dense_qr | dense_normal_cholesky | cgnr (axial cost)");
DEFINE_string(max_iterations, "", "align: solver iterations per level and start");
DEFINE_string(function_tolerance, "", "align: relative cost decrease to stop");
DEFINE_string(trim_fraction, "", "align: fraction of worst residuals dropped");
DEFINE_string(normal_distance, "", "align, jaw: weight gaps by cos(slope) (true | false)");
DEFINE_string(slope_weight, "", "align: volume cost weighted by cos(reference slope)^this (0 = off)");
DEFINE_string(axial_nodes, "", "align: axial cost residuals at both surfaces' nodes or only the sparser one's (both | sparser)");
DEFINE_string(density_correction, "", "align: correct the sparser surface's chords when its area per sample is this many times the other's (0 = off)");
DEFINE_string(sparser_nodes_ratio, "", "align: solve surfaces this many times apart in area per sample (terrain) with the axial cost at the sparser one's nodes (0 = never)");
DEFINE_string(gap_weight, "", "align: volume cost weighted by f / (f + local interpolation gap), f = this x its median (0 = off)");
DEFINE_string(free, "", "align: free parameters, e.g. all, translation, rotation,tz, rx,ry,tz");
DEFINE_string(levels, "", "align: coarse-to-fine levels");
DEFINE_string(level_factor, "", "align: subsampling factor between levels");
DEFINE_string(subsample, "", "align: fraction of each cloud's points used at the finest level");
DEFINE_string(multi_start, "", "align: extra starts around the initial motion");
DEFINE_string(multi_start_angle_deg, "", "align: rotation of the extra starts");
DEFINE_string(multi_start_shift, "", "align: shift of the extra starts");
DEFINE_string(wide_search, "", "align: try many coarse starts first (auto | always | never)");
DEFINE_string(initial_rotation_deg, "", "align: initial rotation vector rx,ry,rz in degrees");
DEFINE_string(initial_translation, "", "align: initial shift tx,ty,tz of the moving centroid");
DEFINE_string(initial_transform, "", "align: the start from a transform file (align JSON or 4x4 text matrix)");
DEFINE_string(mask, "", "align: mask file ('x y' text or a vector file such as .gpkg): weight 1 inside, 0 outside");
DEFINE_string(mask_mode, "", "measure, align: include (the mask is stable terrain) or exclude (it is unstable: left out)");
DEFINE_string(mask_layer, "", "measure, align: the layer of a vector mask file (default: the first)");
DEFINE_string(classes, "", "measure, align, transform: LAS inputs: keep only these classifications, e.g. 2 or 2,9");
DEFINE_string(columns, "", "measure, align, transform: text clouds: the x,y,z[,weight] columns by name or 1-based position");
DEFINE_string(max_fold_fraction, "", "align: area share of moving triangles that may fold");
DEFINE_string(domain, "",
              "measure, align, triangulate: data (default: without the triangles that bridge "
              "voids, nodata holes and concave outlines) | hull (the whole convex hulls)");
DEFINE_string(domain_max_edge_spacings, "",
              "measure, align, triangulate: data domain: longest edge in local spacings (4)");
DEFINE_string(domain_min_thinness, "",
              "measure, align, triangulate: data domain: outline slivers thinner are peeled (0.1)");
DEFINE_bool(covariance, true, "align: compute the parameters' standard deviations");
DEFINE_string(stddev, "", "align: standard deviations of the motion: sandwich | information");
DEFINE_string(stddev_subsamples, "", "align: standard deviations from this many block half-sample alignments (0: as --stddev says)");
DEFINE_string(stable, "", "align: auto (find the stable terrain, fit on it) | all (the whole overlap)");
DEFINE_string(stable_sigmas, "", "align: stable auto: robust sigmas from the stable median that seed a change region");
DEFINE_string(stable_grow_sigmas, "", "align: stable auto: robust sigmas a change region grows through");
DEFINE_string(holdout, "", "align: fit on the reference less this share of its tiles; report dz there before/after");
DEFINE_string(holdout_seed, "", "align: which tiles are held out (integer seed)");
DEFINE_string(holdout_verdict, "", "align: converged_improved only if the held-out tiles improved too (true | false)");
DEFINE_string(threads, "", "align: threads");
DEFINE_string(cell_kernel, "", "align: volume cost cell kernel: best | scalar | avx2 | avx512");
DEFINE_string(output, "", "align: write the transform JSON here");
DEFINE_string(matrix_txt, "", "align: write the moving->reference 4x4 matrix here as text");
DEFINE_string(aligned, "", "align: write the aligned moving surface here (.ply, .xyz, .txt; .tif: on a raster reference's grid)");
DEFINE_string(stable_map, "", "align: write the reference's samples flagged stable (1), changed (0) or outside (2) here (.xyz; .tif on a raster reference's grid)");
DEFINE_string(log, "", "align: write a per-iteration CSV here");
DEFINE_bool(progress, false, "align: print a line per solver iteration on stderr");
// Terrain keys (tools/align_config_terrain.cc).
DEFINE_string(reference_crs, "", "measure (of A), align: CRS of the reference (EPSG:..., WKT, lonlat) if its file has none");
DEFINE_string(moving_crs, "", "measure (of B), align: CRS of the moving surface if its file has none");
DEFINE_string(frame, "", "measure, align: auto | enu | utm: metric frame for lon/lat inputs");
DEFINE_string(band, "", "measure, align: raster band of raster inputs");
DEFINE_string(window, "", "measure, align: column,row,columns,rows read from raster inputs");
DEFINE_string(lod, "", "measure, align: level of detection for cut/fill (data units)");
DEFINE_string(dod, "", "align: write the difference after alignment as GeoTIFF (reference grid)");
DEFINE_string(sigma_reference, "", "measure, align: the reference DEM's vertical standard error: a number or a sigma raster on its grid");
DEFINE_string(sigma_moving, "", "measure, align: the moving DEM's vertical standard error: a number or a sigma raster on its grid");
DEFINE_string(lod_confidence, "", "measure, align: threshold change at t(confidence) x sigma_DoD, e.g. 0.95 (needs a sigma)");
DEFINE_string(dod_sigma, "", "align: write the DoD's propagated standard error as GeoTIFF (reference grid)");
DEFINE_string(dod_thresholded, "", "align: write the DoD with undetected change set to 0 as GeoTIFF");
DEFINE_string(dod_png, "", "align: write a map of the difference after alignment (.png)");
DEFINE_string(histogram_png, "", "align: write dz histograms before/after on stable terrain (.png)");
DEFINE_string(change_csv, "", "align: write x,y,z,dz_before,dz_after,stable per reference sample");
DEFINE_string(known_matrix, "", "align: the true moving->reference matrix (16 numbers), to report errors");
DEFINE_string(mask_raster, "", "align: stable-terrain raster (reference CRS): weight 1 on non-zero cells");
DEFINE_string(tile_stats, "", "align (with --max_memory): write dz after alignment per tile as CSV");
DEFINE_string(patch_shifts, "", "align (with --max_memory): write each sampled patch's own shift against the whole motion as CSV");
DEFINE_string(manifest, "", "align: CSV of pairs (reference,moving,output[,aligned]) to align in turn");

namespace surfreg {
namespace {

using Clock = std::chrono::steady_clock;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Settings: the config file or the two arguments, then the flags given.
AlignConfig LoadConfig(const std::vector<std::string>& args) {
  const bool has_config = !FLAGS_config.empty();
  if (has_config && !args.empty()) {
    throw UsageError("align: give either --config FILE.yaml or REFERENCE MOVING, not both");
  }
  if (!has_config && args.size() != 2) {
    if (args.size() > 2) throw UsageError("align: too many arguments");
    if (args.empty()) throw UsageError("align: missing REFERENCE MOVING or --config FILE.yaml");
    const std::string& only = args[0];
    const bool yaml = (only.size() > 5 && only.compare(only.size() - 5, 5, ".yaml") == 0) ||
                      (only.size() > 4 && only.compare(only.size() - 4, 4, ".yml") == 0);
    throw UsageError(yaml ? "align: missing MOVING (for a config file: --config " + only + ")"
                          : "align: missing MOVING");
  }
  AlignConfig config;
  if (has_config) {
    ApplyAlignConfigFile(FLAGS_config, &config);
  } else {
    ApplyAlignArguments(args[0], args[1], &config);
  }
  for (const AlignConfigKey& key : AlignConfigKeys()) {
    gflags::CommandLineFlagInfo info;
    CHECK(gflags::GetCommandLineFlagInfo(key.name, &info)) << "no flag for key " << key.name;
    if (!info.is_default) ApplyAlignFlag(key.name, info.current_value, &config);
  }
  FinishAlignConfig(&config);
  return config;
}

// Per iteration on stderr: always with `progress`, otherwise once the run
// has taken more than a second (a quiet fast run, a visible slow one).
void PrintProgress(const AlignOptions::Iteration& it, const AlignConfig& config,
                   Clock::time_point start) {
  if (FLAGS_quiet || (!config.progress && Since(start) < 1.0)) return;
  // Stamped on the command's clock, as the stage lines are: a wide search
  // or a stable-terrain round restarts the solve's own.
  AlignOptions::Iteration stamped = it;
  stamped.seconds = Since(start);
  std::fputs(AlignProgressLine(stamped, config.options.levels).c_str(), stderr);
}

void PrintSummary(const AlignConfig& config, const TerrainInputs& inputs, const AlignResult& r) {
  const Surface& reference = inputs.reference;
  const Surface& moving = inputs.moving;
  // A tiled run holds no whole surface: its sample's sizes are in its own lines.
  const auto points = [](const Surface& s) {
    return s.size() > 0 ? "  (" + std::to_string(s.size()) + " points)" : std::string();
  };
  std::printf("reference:    %s%s\n", config.reference.c_str(), points(reference).c_str());
  std::printf("moving:       %s%s\n", config.moving.c_str(), points(moving).c_str());
  std::printf("cost:         %s, free %s\n", AlignConfigValue(config, "cost").c_str(),
              AlignConfigValue(config, "free").c_str());
  std::fputs(r.FullReport(LengthUnit(inputs)).c_str(), stdout);
  for (const char* key : {"output", "matrix_txt", "aligned", "log"}) {
    const std::string path = AlignConfigValue(config, key);
    if (!path.empty()) std::printf("%-13s %s\n", (std::string(key) + ":").c_str(), path.c_str());
  }
}

}  // namespace

int RunAlign(const std::vector<std::string>& args) {
  if (!FLAGS_manifest.empty()) return RunAlignManifest(args);  // tools/run_batch.cc
  const Clock::time_point start = Clock::now();
  AlignConfig config = LoadConfig(args);
  // The long stages around the solve, as the iterations: once past a second,
  // or from the start for large inputs (their reading is the first stage).
  const bool large = LargeInputs({config.reference, config.moving});
  if (!FLAGS_quiet && large) PrintReadingLine("align", {config.reference, config.moving});
  config.options.on_stage = [progress = config.progress || large, start](const char* stage, double) {
    // A wide search is announced however short the run.
    const bool wide = std::string(stage).rfind("wide search", 0) == 0;
    if (!FLAGS_quiet && (progress || wide || Since(start) >= 1.0)) {
      std::fprintf(stderr, "align: %s (%.1f s)\n", stage, Since(start));
    }
  };
  const AlignRun run = AlignSurfaces(
      config, std::nullopt, std::nullopt,
      [&config, start](const AlignOptions::Iteration& it) { PrintProgress(it, config, start); });
  const AlignResult& result = run.result;
  LOG(INFO) << "aligned " << config.moving << " onto " << config.reference << ": "
            << VerdictName(result.verdict) << " in " << Since(start) << " s";
  if (result.verdict == Verdict::kFailed || result.verdict == Verdict::kIllConditioned) {
    LOG(WARNING) << "align: " << VerdictName(result.verdict) << ": " << result.verdict_reason;
  }
  if (FLAGS_json) {
    std::printf("%s", run.json.c_str());
  } else {
    PrintSummary(run.config, run.inputs, result);
    if (run.tiled) {
      std::fputs(TiledAlignSummary(*run.tiled).c_str(), stdout);
    } else if (run.terrain) {
      std::printf("%s\n", TerrainSummary(run.config, run.inputs, run.report).c_str());
    }
  }
  // A script must be able to tell a failed alignment (e.g. a mask outside
  // the data) from a good one; the outputs above are written all the same.
  return result.verdict == Verdict::kFailed ? 3 : 0;
}

}  // namespace surfreg
