#include "tools/align_config.h"

#include <sys/stat.h>
#include <glog/logging.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <utility>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "tools/align_config_values.h"
#include "tools/config_table.h"
#include "tools/config_value.h"
#include "io/raster_io.h"
#include "io/raster_resample.h"
#include "tools/yaml_value.h"
#include "io/polygon_reader.h"
#include "io/surface_reader.h"
#include "io/surface_reader_internal.h"
#include "io/surface_writer.h"
#include "tools/transform_file.h"

namespace surfreg {
namespace {

constexpr double kPi = 3.14159265358979323846;

using namespace config_value;  // the value parsers shared with the terrain keys

const Names<CostKind> kCosts = {{"axial", CostKind::kAxial}, {"volume", CostKind::kVolume}};
const Names<AlignOptions::AxialNodes> kAxialNodes = {{"both", AlignOptions::AxialNodes::kBoth},
                                                     {"sparser", AlignOptions::AxialNodes::kSparser}};
const Names<AlignOptions::WideSearch> kWideSearches = {{"auto", AlignOptions::WideSearch::kAuto},
                                                      {"always", AlignOptions::WideSearch::kAlways},
                                                      {"never", AlignOptions::WideSearch::kNever}};
const Names<LossKind> kLosses = {{"none", LossKind::kNone},
                                 {"huber", LossKind::kHuber},
                                 {"soft_l1", LossKind::kSoftL1},
                                 {"cauchy", LossKind::kCauchy}};
const Names<AlignOptions::StddevMethod> kStddevMethods = {
    {"sandwich", AlignOptions::StddevMethod::kSandwich},
    {"information", AlignOptions::StddevMethod::kInformation}};
const Names<ceres::TrustRegionStrategyType> kTrustRegions = {
    {"levenberg_marquardt", ceres::LEVENBERG_MARQUARDT}, {"dogleg", ceres::DOGLEG}};
const Names<ceres::LineSearchDirectionType> kLineSearches = {
    {"lbfgs", ceres::LBFGS}, {"bfgs", ceres::BFGS}, {"nonlinear_cg", ceres::NONLINEAR_CONJUGATE_GRADIENT}};
const Names<StableOptions::Mode> kStableModes = {{"auto", StableOptions::Mode::kAuto},
                                                 {"all", StableOptions::Mode::kAll}};
const Names<bool> kWeightModes = {{"uniform", false}, {"per_point", true}};
const Names<CellKernelChoice> kCellKernels = {{"best", CellKernelChoice::kBest},
                                               {"scalar", CellKernelChoice::kScalar},
                                               {"avx2", CellKernelChoice::kAvx2},
                                               {"avx512", CellKernelChoice::kAvx512}};
const Names<MaskMode> kMaskModes = {{"include", MaskMode::kInclude}, {"exclude", MaskMode::kExclude}};
const Names<DomainKind> kDomains = {{"data", DomainKind::kData}, {"hull", DomainKind::kHull}};
const Names<ceres::LinearSolverType> kLinearSolvers = {
    {"dense_qr", ceres::DENSE_QR}, {"dense_normal_cholesky", ceres::DENSE_NORMAL_CHOLESKY}, {"cgnr", ceres::CGNR}};

using C = AlignConfig;
const config_table::Table<AlignConfig>& Table() {
  static const std::vector<KeyEntry> table = {
      {{"reference", "a surface file (.xyz .txt .csv .ply .off .obj .las, or a GDAL raster)",
        "the fixed surface"},
       [](const Value& v, C* c) { c->reference = Path(v, true); },
       [](const C& c) { return c.reference; }},
      {{"moving", "a surface file (.xyz .txt .csv .ply .off .obj .las, or a GDAL raster)",
        "the surface moved onto the reference"},
       [](const Value& v, C* c) { c->moving = Path(v, true); },
       [](const C& c) { return c.moving; }},
      {{"cost", "one of axial, volume",
        "axial: least squares on the vertical gaps at the nodes (rho'_d); volume: rho_d per "
        "unit overlap area"},
       [](const Value& v, C* c) { c->options.cost = Choice(v, kCosts); },
       [](const C& c) { return NameOf(c.options.cost, kCosts); }},
      {{"prealign", "true or false",
        "volume cost: first solve with the axial cost on the coarsest level"},
       [](const Value& v, C* c) { c->options.prealign = Boolean(v); },
       [](const C& c) { return Text(c.options.prealign); }},
      {{"loss", "one of none, huber, soft_l1, cauchy", "robust loss of the axial residuals"},
       [](const Value& v, C* c) { c->options.loss = Choice(v, kLosses); },
       [](const C& c) { return NameOf(c.options.loss, kLosses); }},
      {{"loss_scale", "a number >= 0",
        "scale of the robust loss (data units); 0 = 3 x 1.4826 x median |residual|"},
       [](const Value& v, C* c) { c->options.loss_scale = Number(v, 0, HUGE_VAL); },
       [](const C& c) { return Text(c.options.loss_scale); }},
      {{"trust_region", "one of levenberg_marquardt, dogleg", "trust-region step (axial cost)"},
       [](const Value& v, C* c) { c->options.axial_solver.trust_region_strategy_type = Choice(v, kTrustRegions); },
       [](const C& c) { return NameOf(c.options.axial_solver.trust_region_strategy_type, kTrustRegions); }},
      {{"line_search", "one of lbfgs, bfgs, nonlinear_cg", "line-search direction (volume cost)"},
       [](const Value& v, C* c) { c->options.volume_solver.line_search_direction_type = Choice(v, kLineSearches); },
       [](const C& c) { return NameOf(c.options.volume_solver.line_search_direction_type, kLineSearches); }},
      {{"linear_solver", "one of dense_qr, dense_normal_cholesky, cgnr",
        "linear solver of the trust-region steps (axial cost, prealignment)"},
       [](const Value& v, C* c) { c->options.axial_solver.linear_solver_type = Choice(v, kLinearSolvers); },
       [](const C& c) { return NameOf(c.options.axial_solver.linear_solver_type, kLinearSolvers); }},
      {{"max_iterations", "an integer >= 1", "solver iterations per level and start"},
       [](const Value& v, C* c) {
         c->options.axial_solver.max_num_iterations = c->options.volume_solver.max_num_iterations = Integer(v, 1);
       },
       [](const C& c) { return std::to_string(c.options.axial_solver.max_num_iterations); }},
      {{"function_tolerance", "a number in (0, 1)",
        "a solve stops when an iteration lowers its cost by less than this fraction of it (both solvers; "
        "unset, the axial cost's is 1e-12)"},
       [](const Value& v, C* c) {
         c->options.axial_solver.function_tolerance = c->options.volume_solver.function_tolerance =
             Number(v, 0, 1, "()");
       },
       [](const C& c) { return Text(c.options.volume_solver.function_tolerance); }},
      {{"trim_fraction", "a number in [0, 0.5)",
        "fraction of the largest axial residuals dropped at each evaluation"},
       [](const Value& v, C* c) { c->options.trim_fraction = Number(v, 0, 0.5, "[)"); },
       [](const C& c) { return Text(c.options.trim_fraction); }},
      {{"normal_distance", "true or false",
        "axial gaps weighted by cos(slope): the distance along the normal"},
       [](const Value& v, C* c) { c->options.normal_distance = Boolean(v); },
       [](const C& c) { return Text(c.options.normal_distance); }},
      {{"slope_weight", "a number in [0, 8]",
        "volume cost: weight by cos(reference slope)^this; 0 = plain volume"},
       [](const Value& v, C* c) { c->options.slope_weight = Number(v, 0, 8); },
       [](const C& c) { return Text(c.options.slope_weight); }},
      {{"gap_weight", "a number in [0, 100]",
        "volume cost: weight by f / (f + local interpolation gap), f = this x its median; 0 = off"},
       [](const Value& v, C* c) { c->options.gap_weight = Number(v, 0, 100); },
       [](const C& c) { return Text(c.options.gap_weight); }},
      {{"axial_nodes", "one of both, sparser",
        "axial cost: residuals at both surfaces' nodes, or only at the sparser surface's (different resolutions)"},
       [](const Value& v, C* c) { c->options.axial_nodes = Choice(v, kAxialNodes); },
       [](const C& c) { return NameOf(c.options.axial_nodes, kAxialNodes); }},
      {{"density_correction", "0 or a number in [1, 1e6]",
        "correct the sparser surface's chords for its curvature when its area per sample is this many times the "
        "other's; 0 = off"},
       [](const Value& v, C* c) {
         const double r = Number(v, 0, 1e6);
         if (r != 0 && r < 1) Reject(v);
         c->options.density_correction = r;
       },
       [](const C& c) { return Text(c.options.density_correction); }},
      {{"sparser_nodes_ratio", "0 or a number in [1, 1e6]",
        "cost volume: surfaces this many times apart in area per sample, of mixed curvature (terrain), are solved "
        "with the axial cost at the sparser one's nodes; 0 = never"},
       [](const Value& v, C* c) {
         const double r = Number(v, 0, 1e6);
         if (r != 0 && r < 1) Reject(v);
         c->options.sparser_nodes_ratio = r;
       },
       [](const C& c) { return Text(c.options.sparser_nodes_ratio); }},
      {{"free", "a list of rx, ry, rz, tx, ty, tz, rotation, translation, all",
        "the parameters the solver may change (the others keep their initial value)"},
       [](const Value& v, C* c) { c->options.free = FreeParameters(v); },
       [](const C& c) { return FreeText(c.options.free); }},
      {{"levels", "an integer in [1, 8]", "coarse-to-fine levels"},
       [](const Value& v, C* c) { c->options.levels = Integer(v, 1, 8); },
       [](const C& c) { return std::to_string(c.options.levels); }},
      {{"level_factor", "a number in [1.5, 64]", "subsampling factor between levels"},
       [](const Value& v, C* c) { c->options.level_factor = Number(v, 1.5, 64); },
       [](const C& c) { return Text(c.options.level_factor); }},
      {{"subsample", "a number in (0, 1]",
        "fraction of each cloud's points solved on at the finest level"},
       [](const Value& v, C* c) { c->options.subsample = Number(v, 0, 1, "(]"); },
       [](const C& c) { return Text(c.options.subsample); }},
      {{"multi_start", "an integer in [0, 1000]", "extra starts around the initial motion"},
       [](const Value& v, C* c) { c->options.multi_start = Integer(v, 0, 1000); },
       [](const C& c) { return std::to_string(c.options.multi_start); }},
      {{"multi_start_angle_deg", "a number in [0, 90]", "rotation of the extra starts (degrees)"},
       [](const Value& v, C* c) { c->options.multi_start_angle_deg = Number(v, 0, 90); },
       [](const C& c) { return Text(c.options.multi_start_angle_deg); }},
      {{"multi_start_shift", "a number >= 0",
        "shift of the extra starts (data units); 0 = 5 mean sample spacings"},
       [](const Value& v, C* c) { c->options.multi_start_shift = Number(v, 0, HUGE_VAL); },
       [](const C& c) { return Text(c.options.multi_start_shift); }},
      {{"stddev", "one of sandwich, information",
        "standard deviations of the motion: sandwich (the cost's curvature and the spread of its "
        "gradient over tiles ~10 sample spacings wide) or information (from the axial residuals' information matrix)"},
       [](const Value& v, C* c) { c->options.stddev_method = Choice(v, kStddevMethods); },
       [](const C& c) { return NameOf(c.options.stddev_method, kStddevMethods); }},
      {{"stddev_subsamples", "an integer in [0, 1000]",
        "standard deviations from this many alignments on block half-samples of the reference "
        "(0: as `stddev` says)"},
       [](const Value& v, C* c) { c->options.stddev_subsamples = Integer(v, 0, 1000); },
       [](const C& c) { return std::to_string(c.options.stddev_subsamples); }},
      {{"holdout", "a number in [0, 0.9)",
        "held-out check: fit on the reference less this share of its 8 x 8 tiles (seeded), then "
        "report dz there before and after; 0 = off"},
       [](const Value& v, C* c) { c->options.holdout_fraction = Number(v, 0, 0.9, "[)"); },
       [](const C& c) { return Text(c.options.holdout_fraction); }},
      {{"holdout_seed", "an integer >= 0", "which tiles are held out"},
       [](const Value& v, C* c) { c->options.holdout_seed = static_cast<uint64_t>(Integer(v, 0)); },
       [](const C& c) { return std::to_string(c.options.holdout_seed); }},
      {{"holdout_verdict", "true or false",
        "the verdict is converged_improved only if the held-out tiles improved too"},
       [](const Value& v, C* c) { c->options.holdout_verdict = Boolean(v); },
       [](const C& c) { return std::string(c.options.holdout_verdict ? "true" : "false"); }},
      {{"wide_search", "one of auto, always, never",
        "try 50 starts (12° and 24° about 12 axes, and the centroids matched) on a coarse "
        "subsample and solve from the best: always, or (auto) when the alignment from the initial "
        "motion fails or does not improve"},
       [](const Value& v, C* c) { c->options.wide_search = Choice(v, kWideSearches); },
       [](const C& c) { return NameOf(c.options.wide_search, kWideSearches); }},
      {{"initial_rotation_deg", "a list of 3 numbers [rx, ry, rz]",
        "initial rotation vector (degrees), about the moving centroid"},
       [](const Value& v, C* c) {
         const std::array<double, 3> deg = Vector3(v);
         for (int k = 0; k < 3; ++k) c->options.initial_rotation[k] = deg[k] * kPi / 180;
       },
       [](const C& c) { return Text(c.options.initial_rotation, 180 / kPi); }},
      {{"initial_translation", "a list of 3 numbers [tx, ty, tz]",
        "initial shift of the moving centroid (data units)"},
       [](const Value& v, C* c) { c->options.initial_translation = Vector3(v); },
       [](const C& c) { return Text(c.options.initial_translation); }},
      {{"initial_transform", "a transform file (align JSON or 4 x 4 text), or nothing",
        "the start: the moving -> reference matrix in the file (not with initial_rotation_deg "
        "or initial_translation)"},
       [](const Value& v, C* c) { c->initial_transform = Path(v, false); },
       [](const C& c) { return c.initial_transform; }},
      {{"classes", "a list of LAS classifications (integers 0 to 255), or nothing",
        "LAS inputs: keep only the points of these classes (e.g. [2] for ground); nothing = all"},
       [](const Value& v, C* c) { c->classes = Classes(v); },
       [](const C& c) { return ListText(c.classes); }},
      {{"columns", "a list of 3 or 4 column names or 1-based positions, or nothing",
        "text clouds: the columns of x, y, z and optionally the weight; other columns are "
        "ignored; nothing = 3 columns (x y z) or 4 (x y z weight)"},
       [](const Value& v, C* c) { c->columns = Columns(v); },
       [](const C& c) { return ListText(c.columns); }},
      {{"mask", "a polygon file ('x y' text, or a vector file: .gpkg .shp .geojson ...), or nothing",
        "weight 1 on the mask's polygons (holes and several parts: even-odd), 0 elsewhere"},
       [](const Value& v, C* c) { c->mask = Path(v, false); },
       [](const C& c) { return c.mask; }},
      {{"mask_mode", "one of include, exclude",
        "include: the mask is the stable terrain; exclude: it is the unstable areas, left out"},
       [](const Value& v, C* c) { c->options.mask_mode = Choice(v, kMaskModes); },
       [](const C& c) { return NameOf(c.options.mask_mode, kMaskModes); }},
      {{"mask_layer", "a layer name, or nothing",
        "vector masks: the layer to read (nothing = the first)"},
       [](const Value& v, C* c) { c->mask_layer = Scalar(v); },
       [](const C& c) { return c.mask_layer; }},
      {{"weights", "one of uniform, per_point",
        "mu: uniform, or the reference's per-sample weights (4th .xyz column, PLY 'weight')"},
       [](const Value& v, C* c) { c->per_point_weights = Choice(v, kWeightModes); },
       [](const C& c) { return std::string(c.per_point_weights ? "per_point" : "uniform"); }},
      {{"stable", "one of auto, all",
        "auto: fit, exclude the regions whose gaps changed (beyond stable_sigmas robust sigmas, grown "
        "to stable_grow_sigmas), fit again on the rest, until the set settles; all: the whole overlap. "
        "Inside the mask or weights, if any"},
       [](const Value& v, C* c) { c->options.stable.mode = Choice(v, kStableModes); },
       [](const C& c) { return NameOf(c.options.stable.mode, kStableModes); }},
      {{"stable_sigmas", "a number in [1, 100]",
        "stable auto: a change region holds a gap this many robust sigmas from the stable median"},
       [](const Value& v, C* c) { c->options.stable.seed_sigmas = Number(v, 1, 100); },
       [](const C& c) { return Text(c.options.stable.seed_sigmas); }},
      {{"stable_grow_sigmas", "a number in [0.5, 100]",
        "stable auto: a change region grows through neighbours this many robust sigmas out, on its side"},
       [](const Value& v, C* c) { c->options.stable.grow_sigmas = Number(v, 0.5, 100); },
       [](const C& c) { return Text(c.options.stable.grow_sigmas); }},
      {{"domain", "one of data, hull",
        "where the surfaces are compared: data (each mesh without the triangles that bridge "
        "voids, nodata holes and concave outlines) or hull (the whole convex hulls)"},
       [](const Value& v, C* c) { c->options.domain.kind = Choice(v, kDomains); },
       [](const C& c) { return NameOf(c.options.domain.kind, kDomains); }},
      {{"domain_max_edge_spacings", "a number in [1, 100]",
        "data domain of scattered samples: a triangle whose longest edge is more local sample "
        "spacings than this bridges a gap"},
       [](const Value& v, C* c) { c->options.domain.max_edge_spacings = Number(v, 1, 100); },
       [](const C& c) { return Text(c.options.domain.max_edge_spacings); }},
      {{"domain_min_thinness", "a number in [0, 0.5]",
        "data domain of scattered samples: outline triangles thinner than this (height over "
        "longest edge, per longest edge) are peeled"},
       [](const Value& v, C* c) { c->options.domain.min_boundary_thinness = Number(v, 0, 0.5); },
       [](const C& c) { return Text(c.options.domain.min_boundary_thinness); }},
      {{"max_fold_fraction", "a number in [0, 1]",
        "share of the moving surface's area that may fold over (slivers: re-triangulated)"},
       [](const Value& v, C* c) { c->options.max_fold_fraction = Number(v, 0, 1); },
       [](const C& c) { return Text(c.options.max_fold_fraction); }},
      {{"covariance", "true or false", "compute the parameters' standard deviations"},
       [](const Value& v, C* c) { c->options.compute_covariance = Boolean(v); },
       [](const C& c) { return Text(c.options.compute_covariance); }},
      {{"threads", "an integer >= 1", "threads for the solver and the measures"},
       [](const Value& v, C* c) { c->options.num_threads = Integer(v, 1); },
       [](const C& c) { return std::to_string(c.options.num_threads); }},
      {{"cell_kernel", "one of best, scalar, avx2, avx512",
        "volume cost: the kernel of the cell integrals (best: the widest this CPU runs; the others for "
        "comparison, the same cost to rounding)"},
       [](const Value& v, C* c) { c->options.cell_kernel = Choice(v, kCellKernels); },
       [](const C& c) { return NameOf(c.options.cell_kernel, kCellKernels); }},
      {{"output", "a file name, or nothing", "the transform JSON"},
       [](const Value& v, C* c) { c->output = Path(v, false); },
       [](const C& c) { return c.output; }},
      {{"matrix_txt", "a file name, or nothing",
        "the moving -> reference matrix as text: 4 lines of 4 numbers"},
       [](const Value& v, C* c) { c->matrix_txt = Path(v, false); },
       [](const C& c) { return c.matrix_txt; }},
      {{"aligned", "a file name ending in .ply, .xyz, .txt or .las (or .tif, raster reference), or nothing",
        "the moving surface after the motion (input coordinates; .tif: resampled onto the "
        "reference's grid; .las from a LAS moving file: all its points, attributes kept)"},
       [](const Value& v, C* c) { c->aligned = Path(v, false); },
       [](const C& c) { return c.aligned; }},
      {{"stable_map", "a file name (.xyz, .txt, .csv; .tif or .png on a raster reference's grid), or nothing",
        "stable auto: the reference's samples flagged 1 stable, 0 changed (left out of the fit), 2 outside "
        "the overlap; a GeoTIFF has 1, 0 and nodata; a PNG maps them blue, red and grey"},
       [](const Value& v, C* c) { c->stable_map = Path(v, false); },
       [](const C& c) { return c.stable_map; }},
      {{"log", "a file name, or nothing", "per-iteration CSV"},
       [](const Value& v, C* c) { c->log = Path(v, false); },
       [](const C& c) { return c.log; }},
      {{"progress", "true or false", "a line per solver iteration on stderr"},
       [](const Value& v, C* c) { c->progress = Boolean(v); },
       [](const C& c) { return Text(c.progress); }},
  };
  static const config_table::Table<AlignConfig> all = [] {
    std::vector<KeyEntry> keys = table;
    keys.insert(keys.end(), TerrainKeyTable().begin(), TerrainKeyTable().end());
    return config_table::Table<AlignConfig>(std::move(keys));
  }();
  return all;
}


// The key named first (as a whole word) in `message`, or "": to say where a
// setting that AlignOptions::IsValid rejects came from.
std::string FirstKeyIn(const std::string& message) {
  const auto word = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  std::size_t first = std::string::npos;
  std::string found;
  for (const std::string& key : Table().names()) {
    for (std::size_t at = message.find(key); at != std::string::npos && at < first;
         at = message.find(key, at + 1)) {
      const std::size_t end = at + key.size();
      if ((at == 0 || !word(message[at - 1])) && (end == message.size() || !word(message[end]))) {
        first = at;
        found = key;
      }
    }
  }
  return found;
}


// Same file: the same name, or (both existing) the same inode.
bool SameFile(const std::string& a, const std::string& b) {
  struct stat sa, sb;
  return a == b || (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 &&
                    sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino);
}

// A surface format, or a GeoTIFF on a raster reference's grid.
void CheckAlignedPath(const std::string& path, const std::string& reference,
                      const std::string& where) {
  if (IsGeoTiffPath(path) && !IsRasterPath(reference)) {
    throw InputError(where + ": a GeoTIFF '" + path +
                     "' is resampled onto the reference's grid, but the reference is no raster");
  }
  if (!IsGeoTiffPath(path) && !IsWritableSurfacePath(path)) {
    throw InputError(where + ": cannot write a surface as '" + path +
                     "' (expected a name ending in .ply, .xyz, .txt or .las, or .tif for a raster reference)");
  }
}

// One start: a transform file or the rotation and shift keys, read here so
// that a bad file stops the run before anything is read or written.
void ReadInitialTransform(AlignConfig* config) {
  config->initial_matrix.clear();
  if (config->initial_transform.empty()) return;
  for (const char* key : {"initial_rotation_deg", "initial_translation"}) {
    if (AlignConfigValue(*config, key) != "[0, 0, 0]") {
      throw InputError(config->Where("initial_transform") + " and " + config->Where(key) +
                       " both set the start: give one of them");
    }
  }
  const Eigen::Matrix4d m =
      ReadTransformFile(config->initial_transform, config->Where("initial_transform"));
  for (int k = 0; k < 16; ++k) config->initial_matrix.push_back(m(k / 4, k % 4));
}

}  // namespace

const std::vector<AlignConfigKey>& AlignConfigKeys() { return Table().keys(); }

std::string AlignConfigValue(const AlignConfig& config, const std::string& key) {
  return Table().Get(config, key);
}

std::string NearestAlignKey(const std::string& name) { return Table().Nearest(name); }

std::string NearestKey(const std::string& name, const std::vector<std::string>& keys) {
  std::string wanted = name;
  for (char& c : wanted) {
    c = c == '-' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, wanted.size() / 3) + 1, best_edits = 0;
  for (const std::string& key : keys) {
    const std::size_t edits = EditDistance(wanted, key);
    // "iterations" for "max_iterations": a part of a key is close enough.
    const bool part = wanted.size() >= 3 && (key.find(wanted) != std::string::npos ||
                                             wanted.find(key) != std::string::npos);
    const std::size_t distance = part ? std::min<std::size_t>(edits, 1) : edits;
    // Among equally close keys the fewest edits win: 'mask_mode' for
    // 'mask_mod', not 'mask', which is only a part of it.
    if (distance < best_distance || (distance == best_distance && !best.empty() && edits < best_edits)) {
      best = key;
      best_distance = distance;
      best_edits = edits;
    }
  }
  return best;
}

void ApplyAlignYaml(const std::string& yaml_text, const std::string& file, AlignConfig* config) {
  Table().ApplyYaml(yaml_text, file, config);
}

void ApplyAlignConfigFile(const std::string& path, AlignConfig* config) { Table().ApplyFile(path, config); }

void ApplyAlignFlag(const std::string& key, const std::string& value, AlignConfig* config) {
  Table().ApplyFlag(key, value, config);
}

void ApplyAlignSetting(const std::string& key, const std::string& value, const std::string& where,
                       AlignConfig* config) {
  Table().Set(key, value, where, config);
}

void ApplyAlignArguments(const std::string& reference, const std::string& moving,
                         AlignConfig* config) {
  Table().Set("reference", reference, "argument REFERENCE", config);
  Table().Set("moving", moving, "argument MOVING", config);
}

void FinishAlignConfig(AlignConfig* config) {
  const std::string source = config->config_file.empty() ? "" : config->config_file + ": ";
  for (const char* key : {"reference", "moving"}) {
    if (AlignConfigValue(*config, key).empty()) {
      throw InputError(source + "no '" + key + "' surface given (add '" + key +
                       ": FILE' to the config or give --" + key + "=FILE)");
    }
  }
  // Outputs must not overwrite an input or each other.
  std::vector<std::pair<std::string, std::string>> files = {{"reference", config->reference},
                                                            {"moving", config->moving}};
  if (!config->mask.empty()) files.emplace_back("mask", config->mask);
  if (!config->initial_transform.empty()) {
    files.emplace_back("initial_transform", config->initial_transform);
  }
  if (!config->terrain.mask_raster.empty()) {
    files.emplace_back("mask_raster", config->terrain.mask_raster);
  }
  for (const char* key : {"sigma_reference", "sigma_moving"}) {  // σ rasters are inputs too
    const std::string& text = std::string(key) == "sigma_reference" ? config->terrain.sigma_reference
                                                                     : config->terrain.sigma_moving;
    if (IsRasterPath(text)) files.emplace_back(key, text);
  }
  const bool has_sigma = !config->terrain.sigma_reference.empty() || !config->terrain.sigma_moving.empty();
  for (const char* key : {"lod_confidence", "dod_sigma"}) {
    if (!has_sigma && config->origin.count(key) != 0 && !AlignConfigValue(*config, key).empty() &&
        AlignConfigValue(*config, key) != "0") {
      throw InputError(config->Where(key) +
                       " needs the DEMs' vertical errors: give sigma_reference and/or sigma_moving");
    }
  }
  for (const char* key :
       {"output", "matrix_txt", "aligned", "log", "stable_map", "dod", "dod_png", "histogram_png", "change_csv", "dod_sigma",
        "dod_thresholded", "tile_stats", "patch_shifts"}) {
    const std::string path = AlignConfigValue(*config, key);
    if (path.empty()) continue;
    const std::string where = config->Where(key);
    if (std::string(key) == "aligned") CheckAlignedPath(path, config->reference, where);
    CheckTerrainOutput(key, path, where);
    CheckOutputPath(path, where);
    for (const auto& [other, other_path] : files) {
      if (SameFile(path, other_path)) {
        throw InputError(where + ": '" + path + "' is also the " + other + " file");
      }
    }
    files.emplace_back(key, path);
  }
  if (config->per_point_weights) {
    // One μ at a time: a mask or a stable-terrain raster is a weight of its own.
    for (const char* other : {"mask", "mask_raster"}) {
      if (!AlignConfigValue(*config, other).empty()) {
        throw InputError(config->Where("weights") + ": per_point cannot be combined with '" +
                         other + "' (" + config->Where(other) + ")");
      }
    }
    config->options.weight = WeightMode::kPerPoint;
  }
  // An explicit cost is solved as given: the switch to the sparser nodes'
  // axial cost on terrain of two resolutions applies to the default only,
  // unless sparser_nodes_ratio is given too.
  if (config->origin.count("cost") != 0 && config->origin.count("sparser_nodes_ratio") == 0) {
    config->options.sparser_nodes_ratio = 0;
  }
  for (const char* key : {"mask_mode", "mask_layer"}) {
    if (config->mask.empty() && config->origin.count(key) != 0 &&
        AlignConfigValue(*config, key) != (std::string(key) == "mask_mode" ? "include" : "")) {
      throw InputError(config->Where(key) + ": needs a mask ('mask')");
    }
  }
  ReadInitialTransform(config);
  if (!config->mask.empty()) {
    try {
      MaskFile file = ReadMask(config->mask, config->mask_layer);
      config->options.mask = std::move(file.rings);
      config->mask_crs_wkt = std::move(file.crs_wkt);
    } catch (const InputError& e) {
      throw InputError(config->Where("mask") + ": " + e.what());
    }
    config->options.weight = WeightMode::kMask;
  }
  // The keys' own checks come first; this catches the combinations (and any
  // rule the table does not know), naming the key the message names.
  std::string error;
  if (!config->options.IsValid(&error)) {
    const std::string key = FirstKeyIn(error);
    throw InputError((key.empty() ? config->config_file.empty() ? "settings" : config->config_file
                                  : config->Where(key)) +
                     ": " + error);
  }
}

DomainRule DomainRuleFromFlags(const std::string& domain, const std::string& max_edge_spacings,
                               const std::string& min_thinness) {
  AlignConfig config;
  const std::pair<const char*, const std::string*> flags[] = {
      {"domain", &domain},
      {"domain_max_edge_spacings", &max_edge_spacings},
      {"domain_min_thinness", &min_thinness}};
  for (const auto& [key, text] : flags) {
    if (!text->empty()) ApplyAlignFlag(key, *text, &config);
  }
  return config.options.domain;
}

}  // namespace surfreg
