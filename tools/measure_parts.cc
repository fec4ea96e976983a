#include "tools/measure_parts.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <set>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "io/raster_io.h"
#include "io/surface_reader_internal.h"
#include "tools/json_writer.h"
#include "tools/measure_tiled.h"

namespace surfreg {
namespace {

namespace fs = std::filesystem;

constexpr const char* kKind = "surfreg tiled measure part";
constexpr int32_t kRowsPerRead = 256;  // DoD rows held at once when joining bands

std::string Numbers(const std::vector<double>& values) {
  std::vector<std::string> out;
  out.reserve(values.size());
  for (double v : values) out.push_back(JsonNumber(v));
  return JsonArray(out);
}

std::string Points(const std::vector<Point2>& points) {
  std::vector<std::string> out;
  for (const Point2& p : points) out.push_back(Numbers({p.x, p.y}));
  return JsonArray(out);
}

JsonObject CrsJson(const Crs& crs) {
  JsonObject o;
  o.Int("kind", static_cast<int>(crs.kind)).String("name", crs.name).String("wkt", crs.wkt);
  o.Number("metres_per_unit", crs.metres_per_unit);
  return o;
}

JsonObject ReportJson(const MeasureReport& r) {
  const GeoFrame& f = r.frame;
  JsonObject frame;
  frame.Int("kind", f.kind).Number("lat0", f.lat0).Number("lon0", f.lon0).Number("h0", f.h0);
  frame.Int("zone", f.zone).Int("northp", f.northp).String("datum", f.datum);
  frame.String("definition", f.definition);
  std::vector<std::string> rings;
  for (const MaskRing& ring : r.options.mask) {
    std::vector<Point2> points;
    for (const auto& v : ring) points.push_back({v[0], v[1]});
    rings.push_back(Points(points));
  }
  const MeasureOptions& o = r.options;
  JsonObject json;
  json.String("file_a", r.file_a).String("file_b", r.file_b).String("mask_file", r.mask_file);
  json.Object("crs_a", CrsJson(r.crs_a)).Object("crs_b", CrsJson(r.crs_b)).Object("frame", frame);
  json.Int("metric", r.metric).Int("weight", static_cast<int>(o.weight));
  json.Int("mask_mode", static_cast<int>(o.mask_mode)).Raw("mask", JsonArray(rings));
  json.Int("detect_change", o.detect_change).Number("level_of_detection", o.level_of_detection);
  json.Number("min_overlap_fraction", o.min_overlap_fraction).Int("tile", r.tile);
  json.Number("read_s", r.read_s).Number("total_s", r.total_s);
  const TerrainSettings& t = r.config.terrain;  // the change budget's settings, for the merged report
  json.String("sigma_reference", t.sigma_reference).String("sigma_moving", t.sigma_moving);
  json.Number("lod_confidence", t.lod_confidence);
  return json;
}

// Reading back: every failure is one line naming the file.
struct Reader {
  std::string path;
  [[noreturn]] void Fail(const std::string& what) const {
    throw InputError(path + ": " + what + " (not a partial of `surfreg measure --shard`?)");
  }
  YAML::Node At(const YAML::Node& node, const char* key) const {
    if (!node.IsMap() || !node[key]) Fail(std::string("no \"") + key + "\"");
    return node[key];
  }
  double Number(const YAML::Node& node) const {
    if (node.IsNull()) return std::numeric_limits<double>::quiet_NaN();
    if (!node.IsScalar()) Fail("a number expected");
    const std::string& text = node.Scalar();
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0') Fail("bad number '" + text + "'");
    return value;
  }
  double Number(const YAML::Node& node, const char* key) const { return Number(At(node, key)); }
  int64_t Int(const YAML::Node& node, const char* key) const {
    return static_cast<int64_t>(Number(node, key));
  }
  std::string String(const YAML::Node& node, const char* key) const {
    const YAML::Node value = At(node, key);
    if (!value.IsScalar()) Fail(std::string("\"") + key + "\" is no string");
    return value.Scalar();
  }
  std::vector<double> Numbers(const YAML::Node& node, std::size_t size) const {
    if (!node.IsSequence() || (size > 0 && node.size() != size)) Fail("a list of numbers expected");
    std::vector<double> out;
    for (const YAML::Node& item : node) out.push_back(Number(item));
    return out;
  }
  std::vector<Point2> Points(const YAML::Node& node) const {
    if (!node.IsSequence()) Fail("a list of points expected");
    std::vector<Point2> out;
    for (const YAML::Node& item : node) {
      const std::vector<double> p = Numbers(item, 2);
      out.push_back({p[0], p[1]});
    }
    return out;
  }
  Crs ReadCrs(const YAML::Node& node) const {
    Crs crs;
    crs.kind = static_cast<CrsKind>(Int(node, "kind"));
    crs.name = String(node, "name");
    crs.wkt = String(node, "wkt");
    crs.metres_per_unit = Number(node, "metres_per_unit");
    return crs;
  }
};

MeasureReport ReadReport(const Reader& in, const YAML::Node& node) {
  MeasureReport r;
  r.file_a = in.String(node, "file_a");
  r.file_b = in.String(node, "file_b");
  r.mask_file = in.String(node, "mask_file");
  r.crs_a = in.ReadCrs(in.At(node, "crs_a"));
  r.crs_b = in.ReadCrs(in.At(node, "crs_b"));
  const YAML::Node f = in.At(node, "frame");
  r.frame.kind = static_cast<GeoFrame::Kind>(in.Int(f, "kind"));
  r.frame.lat0 = in.Number(f, "lat0"), r.frame.lon0 = in.Number(f, "lon0");
  r.frame.h0 = in.Number(f, "h0");
  r.frame.zone = static_cast<int>(in.Int(f, "zone"));
  r.frame.northp = in.Int(f, "northp") != 0;
  r.frame.datum = in.String(f, "datum");
  r.frame.definition = in.String(f, "definition");
  r.metric = in.Int(node, "metric") != 0;
  MeasureOptions& o = r.options;
  o.weight = static_cast<WeightMode>(in.Int(node, "weight"));
  o.mask_mode = static_cast<MaskMode>(in.Int(node, "mask_mode"));
  for (const YAML::Node& ring : in.At(node, "mask")) {
    o.mask.emplace_back();
    for (const Point2& p : in.Points(ring)) o.mask.back().push_back({p.x, p.y});
  }
  o.detect_change = in.Int(node, "detect_change") != 0;
  o.level_of_detection = in.Number(node, "level_of_detection");
  o.min_overlap_fraction = in.Number(node, "min_overlap_fraction");
  r.tile = static_cast<int32_t>(in.Int(node, "tile"));
  r.read_s = in.Number(node, "read_s");
  r.total_s = in.Number(node, "total_s");
  r.config.terrain.sigma_reference = in.String(node, "sigma_reference");
  r.config.terrain.sigma_moving = in.String(node, "sigma_moving");
  r.config.terrain.lod_confidence = in.Number(node, "lod_confidence");
  return r;
}

// The directory `path` is in ("." for a bare name).
fs::path DirectoryOf(const std::string& path) {
  const fs::path parent = fs::path(path).parent_path();
  return parent.empty() ? fs::path(".") : parent;
}

}  // namespace

std::string PartJson(const TiledPartial& p, const std::string& settings, const MeasureReport* report,
                     const DodBand& dod, const std::string& json_path) {
  const TiledSums& t = p.sums;
  const MeasureSummary& s = t.sum;
  const MeasureTimings& time = s.timings;
  JsonObject sums;
  sums.Raw("volumes", Numbers({s.rho_d, s.overlap_area, s.weight_integral, s.signed_volume,
                               s.volume_above, s.volume_below, s.fill_detected, s.cut_detected,
                               s.fill_area, s.cut_area}));
  sums.Raw("counts", Numbers({static_cast<double>(s.n_cells), static_cast<double>(s.walk_steps),
                              static_cast<double>(s.n_points_a), static_cast<double>(s.n_points_b),
                              static_cast<double>(s.n_overlap_nodes),
                              static_cast<double>(t.complete_cells_a),
                              static_cast<double>(t.complete_cells_b)}));
  sums.Raw("timings", Numbers({time.triangulate, time.domain, time.spanning_tree, time.locate,
                               time.interpolate, time.volume}));
  sums.Raw("nodes", Numbers({t.gap_sum, t.node_weight, t.domain_area_a, t.domain_area_b}));
  sums.Raw("hull_a", Points(t.hull_a)).Raw("hull_b", Points(t.hull_b));
  const ChangeBudgetSums& b = t.budget;
  sums.Raw("budget", Numbers({p.budget ? 1.0 : 0.0, p.budget_sigma_dod, p.budget_threshold,
                              static_cast<double>(b.nodes), static_cast<double>(b.fill_nodes),
                              static_cast<double>(b.cut_nodes), b.fill, b.cut, b.fill_area, b.cut_area,
                              b.fill_var, b.cut_var, b.fill_sigma, b.cut_sigma}));
  const TiledMeasureStats& st = p.stats;
  sums.Raw("stats", Numbers({static_cast<double>(st.tiles), static_cast<double>(st.tiles_measured),
                             static_cast<double>(st.shared_moving_nodes),
                             static_cast<double>(st.merged_moving_nodes)}));
  std::vector<std::string> border, shared;
  border.reserve(p.border.size());
  for (const TiledBorderNode& n : p.border) {
    border.push_back(Numbers({static_cast<double>(n.column), static_cast<double>(n.row), n.dz,
                              n.area, n.weight, n.owned ? 1.0 : 0.0}));
  }
  for (const TiledSharedNode& n : p.shared) {
    shared.push_back(Numbers({static_cast<double>(n.column), static_cast<double>(n.row), n.dz,
                              n.weight, static_cast<double>(n.tile_row)}));
  }
  JsonObject band;
  if (!dod.path.empty()) {
    std::error_code error;
    const fs::path relative =
        fs::relative(fs::absolute(dod.path), fs::absolute(DirectoryOf(json_path)), error);
    band.String("path", error || relative.empty() ? dod.path : relative.string());
    band.Int("first_row", dod.first_row).Int("rows", dod.rows).Int("columns", dod.columns);
    band.Int("raster_rows", dod.raster_rows).String("crs_wkt", dod.crs_wkt);
    band.Raw("geotransform", Numbers({dod.geotransform.begin(), dod.geotransform.end()}));
  }
  JsonObject json;
  json.String("surfreg", kKind).Int("version", 1).String("settings", settings);
  json.Int("shard", p.shard).Int("shards", p.shards).Int("tile", p.tile);
  json.Raw("tile_rows", Numbers({static_cast<double>(p.tile_rows), static_cast<double>(p.first_row),
                                 static_cast<double>(p.end_row), static_cast<double>(p.band_end_row)}));
  json.Raw("moving_tile_rows",
           Numbers({static_cast<double>(p.moving_tile_rows), static_cast<double>(p.moving_first_row),
                    static_cast<double>(p.moving_end_row), p.moving_done ? 1.0 : 0.0}));
  json.Object("sums", sums).Raw("border", JsonArray(border)).Raw("shared", JsonArray(shared));
  json.Raw("report", report != nullptr ? ReportJson(*report).str() : "null");
  json.Raw("dod", dod.path.empty() ? "null" : band.str());
  return json.str() + "\n";
}

bool LooksLikePart(const std::string& path) {
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return false;
  int c = 0;
  while ((c = std::fgetc(f)) != EOF && (c == ' ' || c == '\n' || c == '\r' || c == '\t')) {
  }
  std::fclose(f);
  return c == '{';
}

PartFile ReadPart(const std::string& path) {
  const Reader in{path};
  YAML::Node root;
  try {
    root = YAML::Load(io_internal::ReadFile(path));
  } catch (const YAML::Exception& e) {
    in.Fail("not valid JSON (" + e.msg + ")");
  }
  if (!root.IsMap() || !root["surfreg"] || !root["surfreg"].IsScalar() ||
      root["surfreg"].Scalar() != kKind) {
    in.Fail("no \"surfreg\": \"" + std::string(kKind) + "\"");
  }
  if (in.Int(root, "version") != 1) in.Fail("a partial of another version of surfreg");
  PartFile file;
  file.path = path;
  file.settings = in.String(root, "settings");
  TiledPartial& p = file.part;
  p.shard = static_cast<int32_t>(in.Int(root, "shard"));
  p.shards = static_cast<int32_t>(in.Int(root, "shards"));
  p.tile = static_cast<int32_t>(in.Int(root, "tile"));
  const std::vector<double> rows = in.Numbers(in.At(root, "tile_rows"), 4);
  p.tile_rows = static_cast<int64_t>(rows[0]), p.first_row = static_cast<int64_t>(rows[1]);
  p.end_row = static_cast<int64_t>(rows[2]), p.band_end_row = static_cast<int64_t>(rows[3]);
  const std::vector<double> moving = in.Numbers(in.At(root, "moving_tile_rows"), 4);
  p.moving_tile_rows = static_cast<int64_t>(moving[0]);
  p.moving_first_row = static_cast<int64_t>(moving[1]);
  p.moving_end_row = static_cast<int64_t>(moving[2]);
  p.moving_done = moving[3] != 0.0;
  const YAML::Node sums = in.At(root, "sums");
  MeasureSummary& s = p.sums.sum;
  const std::vector<double> v = in.Numbers(in.At(sums, "volumes"), 10);
  s.rho_d = v[0], s.overlap_area = v[1], s.weight_integral = v[2], s.signed_volume = v[3];
  s.volume_above = v[4], s.volume_below = v[5], s.fill_detected = v[6], s.cut_detected = v[7];
  s.fill_area = v[8], s.cut_area = v[9];
  const std::vector<double> c = in.Numbers(in.At(sums, "counts"), 7);
  s.n_cells = static_cast<int64_t>(c[0]), s.walk_steps = static_cast<int64_t>(c[1]);
  s.n_points_a = static_cast<int64_t>(c[2]), s.n_points_b = static_cast<int64_t>(c[3]);
  s.n_overlap_nodes = static_cast<int64_t>(c[4]);
  p.sums.complete_cells_a = static_cast<int64_t>(c[5]);
  p.sums.complete_cells_b = static_cast<int64_t>(c[6]);
  const std::vector<double> t = in.Numbers(in.At(sums, "timings"), 6);
  s.timings.triangulate = t[0], s.timings.domain = t[1], s.timings.spanning_tree = t[2];
  s.timings.locate = t[3], s.timings.interpolate = t[4], s.timings.volume = t[5];
  const std::vector<double> nodes = in.Numbers(in.At(sums, "nodes"), 4);
  p.sums.gap_sum = nodes[0], p.sums.node_weight = nodes[1];
  p.sums.domain_area_a = nodes[2], p.sums.domain_area_b = nodes[3];
  p.sums.hull_a = in.Points(in.At(sums, "hull_a"));
  p.sums.hull_b = in.Points(in.At(sums, "hull_b"));
  const std::vector<double> b = in.Numbers(in.At(sums, "budget"), 14);
  p.budget = b[0] != 0.0, p.budget_sigma_dod = b[1], p.budget_threshold = b[2];
  ChangeBudgetSums& budget = p.sums.budget;
  budget.nodes = static_cast<int64_t>(b[3]), budget.fill_nodes = static_cast<int64_t>(b[4]);
  budget.cut_nodes = static_cast<int64_t>(b[5]);
  budget.fill = b[6], budget.cut = b[7], budget.fill_area = b[8], budget.cut_area = b[9];
  budget.fill_var = b[10], budget.cut_var = b[11], budget.fill_sigma = b[12], budget.cut_sigma = b[13];
  const std::vector<double> st = in.Numbers(in.At(sums, "stats"), 4);
  p.stats = {static_cast<int64_t>(st[0]), static_cast<int64_t>(st[1]), static_cast<int64_t>(st[2]),
             static_cast<int64_t>(st[3])};
  for (const YAML::Node& item : in.At(root, "border")) {
    const std::vector<double> n = in.Numbers(item, 6);
    p.border.push_back({static_cast<int32_t>(n[0]), static_cast<int32_t>(n[1]), n[2], n[3], n[4],
                        n[5] != 0.0});
  }
  for (const YAML::Node& item : in.At(root, "shared")) {
    const std::vector<double> n = in.Numbers(item, 5);
    p.shared.push_back({static_cast<int32_t>(n[0]), static_cast<int32_t>(n[1]), n[2], n[3],
                        static_cast<int64_t>(n[4])});
  }
  const YAML::Node report = in.At(root, "report");
  if (!report.IsNull()) file.report = ReadReport(in, report);
  const YAML::Node dod = in.At(root, "dod");
  if (!dod.IsNull()) {
    const fs::path band = in.String(dod, "path");
    file.dod.path = band.is_absolute() ? band.string() : (DirectoryOf(path) / band).string();
    file.dod.first_row = static_cast<int32_t>(in.Int(dod, "first_row"));
    file.dod.rows = static_cast<int32_t>(in.Int(dod, "rows"));
    file.dod.columns = static_cast<int32_t>(in.Int(dod, "columns"));
    file.dod.raster_rows = static_cast<int32_t>(in.Int(dod, "raster_rows"));
    file.dod.crs_wkt = in.String(dod, "crs_wkt");
    const std::vector<double> gt = in.Numbers(in.At(dod, "geotransform"), 6);
    std::copy(gt.begin(), gt.end(), file.dod.geotransform.begin());
  }
  return file;
}

void JoinDodBands(const std::vector<DodBand>& bands, const std::vector<TiledDodPatch>& patches,
                  const std::string& out, const std::string& label) {
  if (bands.empty()) throw InputError(label + ": no DoD bands to join");
  const DodBand& first = bands.front();
  int32_t rows = 0;
  for (const DodBand& b : bands) {
    if (b.first_row != first.first_row + rows || b.columns != first.columns) {
      throw InputError(label + ": the DoD band " + b.path + " does not follow the one before");
    }
    rows += b.rows;
  }
  std::array<double, 6> gt = first.geotransform;  // the band's corner: row first_row
  gt[0] += first.first_row * gt[2];
  gt[3] += first.first_row * gt[5];
  GeoTiffStreamWriter writer(out, first.columns, rows, gt, first.crs_wkt, label);
  auto patch = patches.begin();
  for (const DodBand& b : bands) {
    for (int32_t r = 0; r < b.rows; r += kRowsPerRead) {
      RasterReadOptions options;
      options.window = {0, r, b.columns, std::min(kRowsPerRead, b.rows - r)};
      Raster block = ReadRaster(b.path, options);
      const int32_t row0 = b.first_row + r, row1 = row0 + options.window.rows;
      for (; patch != patches.end() && patch->row < row1; ++patch) {
        if (patch->row < row0) continue;
        block.values[static_cast<std::size_t>(patch->row - row0) * b.columns + patch->column] = patch->dz;
      }
      writer.Write(0, row0 - first.first_row, b.columns, options.window.rows, block.values.data(),
                   block.values.size());
    }
  }
  writer.Finish();
}

int MergeMeasureParts(const std::vector<std::string>& args, const std::string& dod, bool json,
                      void (*print_text)(const MeasureReport&)) {
  CheckOutputPath(args[0], "argument OUT");
  if (!dod.empty()) CheckOutputPath(dod, "flag '--dod'");
  std::vector<PartFile> files;
  for (std::size_t i = 1; i < args.size(); ++i) {
    std::error_code ignored;
    if (fs::equivalent(args[0], args[i], ignored)) {
      throw InputError("argument OUT: '" + args[0] + "' is also input " + std::to_string(i) +
                       " ('" + args[i] + "'); write the merge to another file");
    }
    files.push_back(ReadPart(args[i]));
    const PartFile& f = files.back();
    if (f.settings != files.front().settings) {
      throw InputError(f.path + ": a part of another measure than " + files.front().path +
                       " (other inputs or settings)");
    }
    if (f.part.end_row != f.part.band_end_row || !f.part.moving_done || f.report.file_a.empty()) {
      throw InputError(f.path + ": an unfinished part (a checkpoint); resume its run first");
    }
  }
  std::vector<TiledPartial> parts;
  for (const PartFile& f : files) parts.push_back(f.part);
  std::vector<TiledDodPatch> patches;
  TiledPartial whole;
  try {
    whole = MergeTiledPartials(std::move(parts), &patches);
  } catch (const InputError& e) {
    throw InputError(std::string("merge: ") + e.what());
  }
  std::sort(files.begin(), files.end(),
            [](const PartFile& p, const PartFile& q) { return p.part.shard < q.part.shard; });
  MeasureReport report = files.front().report;
  report.read_s = report.total_s = 0;
  for (const PartFile& f : files) {
    report.read_s += f.report.read_s;
    report.total_s += f.report.total_s;
  }
  report.summary = FinishTiled(whole.sums, report.options, report.file_a, report.file_b);
  report.summary.timings.total = report.total_s;
  report.uncertainty = TiledChangeUncertainty(whole, report.config);
  report.tiles = whole.stats.tiles;
  if (!dod.empty()) {
    std::vector<DodBand> bands;
    for (const PartFile& f : files) {
      if (f.dod.path.empty()) {
        throw InputError("flag '--dod': " + f.path + " has no DoD (measured without --dod)");
      }
      if (f.dod.rows > 0) bands.push_back(f.dod);
    }
    JoinDodBands(bands, patches, dod, "flag '--dod'");
  }
  const std::string document = MeasureJson(report);
  WriteFileAtomically(args[0], document + "\n", "argument OUT");
  if (json) {
    std::printf("%s\n", document.c_str());
  } else {
    print_text(report);
  }
  return 0;
}

}  // namespace surfreg
