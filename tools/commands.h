#pragma once
// The subcommands of the `surfreg` program (see surfreg_main.cc for the
// dispatch table). Each Run function gets the positional arguments after the
// command name (flags are already parsed by gflags) and returns the exit code.
// Bad input is reported by throwing InputError (exit 2), bad usage by
// throwing UsageError (exit 2, with the command's usage line).
#include <stdexcept>
#include <string>
#include <vector>

namespace surfreg {

class UsageError : public std::runtime_error {
 public:
  explicit UsageError(const std::string& message) : std::runtime_error(message) {}
};

// triangulate FILE [--json]: reads a surface, triangulates it, reports counts
// and timings.
int RunTriangulate(const std::vector<std::string>& args);

// measure A B [--volume=overlay|union] [--weights=uniform|per_point|
// mask:POLYGON_FILE] [--lod=L] [--reference_crs, --moving_crs, --frame,
// --band, --window] [--json]: reads two surfaces as align does (rasters,
// CRSs, one metric frame: terrain/terrain.h), compares B with A
// (measure/measures.h: ρd, ρ'd, ρs, signed and cut/fill volumes over the
// overlap of their data domains), reports the measures, the frame, counts
// and timings. Bad flag values, bad polygon files and CRSs that disagree
// are InputErrors (one line).
int RunMeasure(const std::vector<std::string>& args);

// align --config FILE.yaml | REFERENCE MOVING [--key=value ...] [--json]:
// rigid registration of MOVING onto REFERENCE (registration/align.h) with the
// settings of tools/align_config.h (every config key is also a flag; flags
// win). Writes the transform JSON, the aligned surface and a per-iteration
// CSV where asked (atomically), and prints a summary or, with --json, the
// transform JSON. Bad settings and files are InputErrors naming the key.
int RunAlign(const std::vector<std::string>& args);

// align --manifest=PAIRS.csv [--config BASE.yaml] [--key=value ...]
// [--shard=K/N] [--output=SUMMARY.csv]: aligns every pair of the manifest
// (columns reference, moving, output[, aligned]) with the same settings,
// writes one transform JSON per pair and a summary CSV (stdout without
// --output). tools/run_batch.cc.
int RunAlignManifest(const std::vector<std::string>& args);

// series --config FILE.yaml | E0 E1 ... [--key=value ...] [--json]: joint
// alignment of a series of surveys (registration/series.h) with the settings
// of tools/series_config.h; prints a summary or, with --json, the series
// JSON. tools/run_series.cc.
int RunSeries(const std::vector<std::string>& args);

// sweep --config SWEEP.yaml [--output=RUNS.csv] [--jobs=N] [--shard=K/N]
// [--resume]: runs a grid of surface pairs x solver settings x initial
// perturbations in parallel (tools/sweep.h); writes the per-run CSV, a
// ranking of the settings (Markdown, also on stdout) and PNG plots.
int RunSweep(const std::vector<std::string>& args);

// merge OUT.csv IN.csv...: joins CSVs of sweep or manifest shards (same
// header, rows keyed by run_id), sorted by run_id, written atomically.
int RunMerge(const std::vector<std::string>& args);

// merge OUT.json PART.json... [--dod=DOD.tif] [--json]: the shards of a
// tiled measure (measure --shard=K/N --partial=P.json) as one measure's
// report, OUT.json its --json document (tools/measure_parts.h). RunMerge
// calls it when the inputs are JSON. tools/run_measure.cc.
int RunMergeMeasureParts(const std::vector<std::string>& args);

// normalize MESH [--orientation=auto|as_is|RX,RY,RZ] [--depth_limit=D]
// [--output=FACE.xyz] [--json]: brings a face mesh or cloud into the standard
// face frame (faces/face_frame.h) and writes its visible height field.
// tools/run_normalize.cc.
int RunNormalize(const std::vector<std::string>& args);

// asymmetry FACE [--json] [--map=MAP.png] [...]: facial asymmetry, the
// measure between the face and its mirror image, first about x = 0 of the
// normalized frame, then about the symmetry plane optimized with Ceres
// (faces/symmetry.h). tools/run_asymmetry.cc.
int RunAsymmetry(const std::vector<std::string>& args);

// jaw --config JAW.yaml [--key=value ...]: jaw motion over a 3D sequence,
// the lower part's transform relative to the upper part in every frame
// (faces/jaw.h, tools/jaw_config.h); CSV, JSON and a plot.
// tools/run_jaw.cc.
int RunJaw(const std::vector<std::string>& args);

// transform INPUT --transform=T --output=OUT [--inverse] [--grid=REF]:
// applies a rigid transform file (align JSON or 4 x 4 text,
// tools/transform_file.h), or its inverse, to every point of a cloud or
// raster; writes a cloud, or a GeoTIFF resampled onto the input raster's
// grid or REF's (io/raster_resample.h). tools/run_transform.cc.
int RunTransform(const std::vector<std::string>& args);

}  // namespace surfreg
