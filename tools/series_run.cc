#include "tools/series_run.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/raster_io.h"
#include "io/surface_reader.h"
#include "io/surface_writer.h"
#include "measure/input_error.h"
#include "measure/tasks.h"
#include "registration/align.h"
#include "terrain/geo_frame.h"
#include "terrain/series_epochs.h"
#include "tools/json_writer.h"
#include "tools/transform_file.h"
#include "tools/transform_json.h"

namespace surfreg {
namespace {

// The DoD of epochs k, k + 1 on epoch k's grid: dz (later − earlier) at
// its valid cells, which are its samples (Surface::raster_cell), nodata
// elsewhere and outside the overlap.
void WriteDod(const SeriesConfig& config, const Surface& earlier, Raster grid, const std::vector<double>& dz,
              const std::string& path) {
  if (earlier.raster_cell.empty() || grid.columns <= 0) {
    throw InputError(config.Where("dod_dir") + ": " + earlier.source + " was not read as a raster");
  }
  grid.values.assign(static_cast<std::size_t>(grid.columns) * static_cast<std::size_t>(grid.rows), std::nan(""));
  for (std::size_t i = 0; i < earlier.raster_cell.size() && i < dz.size(); ++i) {
    const RasterCell& cell = earlier.raster_cell[i];
    grid.values[static_cast<std::size_t>(cell.row) * static_cast<std::size_t>(grid.columns) + cell.column] = dz[i];
  }
  WriteGeoTiff(path, grid, config.Where("dod_dir"), std::max(1, config.options.align.num_threads));
}

// Each epoch against the one before it, the later brought onto the earlier
// by the joint relative motion (as `align` would): dz at the earlier
// epoch's samples, in its frame, so that its DoD lies on its own grid.
std::vector<ConsecutiveChange> Consecutive(const SeriesConfig& config, const std::vector<Surface>& epochs,
                                           const std::vector<Raster>& grids, const SeriesResult& result) {
  const SeriesOptions& options = config.options;
  const int count = static_cast<int>(epochs.size()) - 1;
  const int threads = ExecutionFor(options.align.num_threads).threads;
  const int at_once = SeriesPairsAtOnce(epochs, count, threads);  // one thread each when several
  MeasureOptions measure;
  measure.domain = options.align.domain;
  measure.threads = at_once > 1 ? 1 : threads;
  measure.allow_empty_overlap = true;
  measure.keep_node_gaps = true;
  std::vector<ConsecutiveChange> changes(std::max(0, count));
  std::vector<std::vector<double>> dz(changes.size());  // side by side: the DoDs are written in turn after
  ForEachItem(ExecutionFor(at_once), count, [&](int k) {
    ConsecutiveChange& change = changes[k];
    change.from = k;
    change.to = k + 1;
    const Eigen::Matrix4d onto_from = result.epochs[k].matrix.inverse() * result.epochs[k + 1].matrix;
    change.measure = Measure(epochs[k], TransformSurface(epochs[k + 1], onto_from), measure);
    change.dz = ComputeDzStatistics(change.measure.dz_a, {}, ExecutionFor(measure.threads));
    change.dod = DodPath(config, k);
    if (at_once == 1 && !change.dod.empty()) {  // one at a time: written now, none kept
      WriteDod(config, epochs[k], grids[k], change.measure.dz_a, change.dod);
    } else {
      dz[k] = std::move(change.measure.dz_a);
    }
    change.measure.dz_a.clear();
    change.measure.dz_b.clear();
    change.measure.node_area_a.clear();
  });
  for (int k = 0; at_once > 1 && k < count; ++k) {
    if (!changes[k].dod.empty()) WriteDod(config, epochs[k], grids[k], dz[k], changes[k].dod);
  }
  return changes;
}

std::string Numbers3(const std::array<double, 3>& v) {
  return JsonArray({JsonNumber(v[0]), JsonNumber(v[1]), JsonNumber(v[2])});
}

std::string SeriesJson(const SeriesRun& run) {
  const SeriesResult& r = run.result;
  std::vector<std::string> epochs, pairs, consecutive;
  for (std::size_t k = 0; k < r.epochs.size(); ++k) {
    const SeriesEpoch& e = r.epochs[k];
    JsonObject o;
    o.Int("index", static_cast<int64_t>(k))
        .String("file", run.config.surfaces[k])
        .Raw("matrix", JsonMatrix4(e.matrix))
        .String("pdal_matrix", MatrixOneLine(e.matrix))
        .Raw("euler_deg", Numbers3(e.euler_deg))
        .Raw("translation", Numbers3(e.translation))
        .Raw("centre", Numbers3(e.centre))
        .Object("stddev", StddevJson(e.stddev))
        .Raw("covariance", CovarianceJson(e.covariance))
        .String("verdict", VerdictName(e.verdict))
        .String("verdict_reason", e.verdict_reason)
        .Int("pairs", e.pairs);
    const std::string aligned = AlignedEpochPath(run.config, static_cast<int>(k));
    if (!aligned.empty()) o.String("aligned", aligned);
    epochs.push_back(o.str());
  }
  for (const SeriesPair& p : r.pairs) {
    const double smaller_before = std::min(p.before.domain_area_a, p.before.domain_area_b);
    const double smaller_after = std::min(p.after.domain_area_a, p.after.domain_area_b);
    JsonObject pairwise;
    pairwise.Raw("matrix", JsonMatrix4(p.pairwise.matrix))
        .Object("stddev", StddevJson(p.pairwise.stddev))
        .String("verdict", VerdictName(p.pairwise.verdict))
        .String("verdict_reason", p.pairwise.verdict_reason)
        .Fixed("seconds", p.pairwise.seconds, 6);
    JsonObject o;
    o.Int("reference", p.reference)
        .Int("moving", p.moving)
        .Number("overlap", p.overlap)
        .Raw("used", p.used ? "true" : "false")
        .String("reason", p.reason)
        .Object(
            "before",
            MeasuresJson(p.before, smaller_before > 0 ? p.before.overlap_area / smaller_before : 0))
        .Object("after",
                MeasuresJson(p.after, smaller_after > 0 ? p.after.overlap_area / smaller_after : 0))
        .Number("misclosure_deg", p.misclosure_deg)
        .Number("misclosure_shift", p.misclosure_shift)
        .Number("misclosure_chi2", p.misclosure_chi2)
        .Object("pairwise", pairwise);
    pairs.push_back(o.str());
  }
  for (const ConsecutiveChange& c : run.consecutive) {
    JsonObject o;
    o.Int("from", c.from)
        .Int("to", c.to)
        .Number("overlap_area", c.measure.overlap_area)
        .Number("mean_abs_dz", c.measure.mean_abs_dz)
        .Number("net_volume", c.measure.signed_volume)
        .Number("fill_volume", c.measure.volume_above)
        .Number("cut_volume", c.measure.volume_below)
        .Object("dz", DzStatisticsJson(c.dz));
    if (!c.dod.empty()) o.String("dod", c.dod);
    if (!run.config.days.empty()) {
      const double years = (run.config.days[c.to] - run.config.days[c.from]) / 365.25;
      o.String("from_date", run.config.dates[c.from])
          .String("to_date", run.config.dates[c.to])
          .Number("years", years)
          .Number("net_volume_per_year", c.measure.signed_volume / years)
          .Number("mean_dz_per_year", c.dz.mean / years)
          .Number("median_dz_per_year", c.dz.median / years);
    }
    consecutive.push_back(o.str());
  }
  JsonObject json;
  json.Int("reference", r.reference)
      .String("frame", r.frame)
      .Number("pair_correlation", r.pair_correlation)
      .Raw("epochs", JsonArray(epochs))
      .Raw("pairs", JsonArray(pairs))
      .Raw("consecutive", JsonArray(consecutive))
      .Int("iterations", r.iterations)
      .String("termination", r.termination)
      .Fixed("pairwise_seconds", r.pairwise_seconds, 6)
      .Fixed("seconds", r.seconds, 6);
  return json.str() + "\n";
}

}  // namespace

SeriesRun AlignSeriesFiles(SeriesConfig config, std::optional<std::vector<Surface>> epochs,
                           const std::function<void(const std::string&)>& on_stage) {
  SeriesRun run;
  run.config = std::move(config);
  if (on_stage) on_stage("reading " + std::to_string(run.config.surfaces.size()) + " epochs");
  if (epochs && !run.config.dod_dir.empty()) {
    throw InputError(run.config.Where("dod_dir") +
                     ": the DoDs are drawn on the epochs' raster files; give the files, not surfaces");
  }
  std::vector<Raster> grids(run.config.surfaces.size());  // none for surfaces given (no DoDs then)
  if (epochs) {
    run.epochs = std::move(*epochs);
  } else {
    ReadOptions read;
    read.classes = run.config.classes;
    read.columns = run.config.columns;
    read.threads = run.config.options.align.num_threads;
    SeriesEpochs read_epochs =
        ReadSeriesEpochs(run.config.surfaces, read, run.config.crs, run.config.Where("crs"), run.config.frame);
    run.epochs = std::move(read_epochs.surfaces);
    grids = std::move(read_epochs.grids);
    run.frame = read_epochs.frame;
    run.units = read_epochs.units;
  }
  SeriesOptions options = run.config.options;
  options.on_stage = on_stage;
  run.result = AlignSeries(run.epochs, options);
  run.result.frame = run.frame.Describe();
  if (on_stage) on_stage("measuring consecutive epochs");
  run.consecutive = Consecutive(run.config, run.epochs, grids, run.result);
  for (std::size_t k = 0; k < run.epochs.size(); ++k) {
    const std::string path = AlignedEpochPath(run.config, static_cast<int>(k));
    if (path.empty()) continue;
    WriteSurface(path, TransformSurface(run.epochs[k], run.result.epochs[k].matrix),
                 run.config.Where("aligned_dir"),
                 {"surfreg series: " + run.config.surfaces[k] + " in the frame of " +
                      run.config.surfaces[run.result.reference],
                  "coordinates: " + (run.frame.kind == GeoFrame::kAsGiven ? std::string("as the inputs'")
                                                                          : run.frame.Describe())});
  }
  run.json = SeriesJson(run);
  if (!run.config.output.empty())
    WriteFileAtomically(run.config.output, run.json, run.config.Where("output"));
  return run;
}

std::string SeriesSummary(const SeriesRun& run) {
  const SeriesResult& r = run.result;
  std::string text;
  char line[512];
  std::snprintf(line, sizeof line, "reference:   epoch %d (%s)\n", r.reference,
                run.config.surfaces[r.reference].c_str());
  text += line;
  if (run.frame.kind != GeoFrame::kAsGiven) text += "frame:       " + run.frame.Describe() + "\n";
  for (std::size_t k = 0; k < r.epochs.size(); ++k) {
    const SeriesEpoch& e = r.epochs[k];
    const double angle = Eigen::AngleAxisd(e.matrix.topLeftCorner<3, 3>()).angle() * 180 / M_PI;
    const double shift = std::hypot(e.translation[0], e.translation[1], e.translation[2]);
    const double sigma_shift = std::sqrt(e.stddev[3] * e.stddev[3] + e.stddev[4] * e.stddev[4] +
                                         e.stddev[5] * e.stddev[5]);
    std::snprintf(line, sizeof line,
                  "epoch %zu:     rotation %.4f deg, shift %.4g (sigma %.2g), %d pairs, %s  %s\n",
                  k, angle, shift, sigma_shift, e.pairs, VerdictName(e.verdict),
                  run.config.surfaces[k].c_str());
    text += line;
  }
  for (const SeriesPair& p : r.pairs) {
    if (!p.used) {
      std::snprintf(line, sizeof line, "pair %d-%d:    overlap %.2f, not used: %s\n", p.reference,
                    p.moving, p.overlap, p.reason.c_str());
    } else {
      std::snprintf(line, sizeof line,
                    "pair %d-%d:    overlap %.2f, mean |dz| %.4g -> %.4g, misclosure %.4f deg %.3g "
                    "(chi2 %.2f)\n",
                    p.reference, p.moving, p.overlap, p.before.mean_abs_dz, p.after.mean_abs_dz,
                    p.misclosure_deg, p.misclosure_shift, p.misclosure_chi2);
    }
    text += line;
  }
  for (const ConsecutiveChange& c : run.consecutive) {
    std::snprintf(line, sizeof line, "change %d-%d:  %s, net volume %.4g\n", c.from, c.to,
                  DzStatisticsLine(c.dz, run.units).c_str(), c.measure.signed_volume);
    text += line;
    if (!c.dod.empty()) text += "             DoD " + c.dod + "\n";
    if (run.config.days.empty()) continue;
    const double years = (run.config.days[c.to] - run.config.days[c.from]) / 365.25;
    std::snprintf(line, sizeof line, "             over %.3f years: median dz %.4g %s/year, net volume %.4g/year\n",
                  years, c.dz.median / years, run.units.c_str(), c.measure.signed_volume / years);
    text += line;
  }
  std::snprintf(line, sizeof line, "time:        %.2f s (pairwise alignments %.2f s)\n", r.seconds,
                r.pairwise_seconds);
  text += line;
  if (!run.config.output.empty()) text += "output:      " + run.config.output + "\n";
  return text;
}

}  // namespace surfreg
