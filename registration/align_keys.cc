#include "registration/align_keys.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "measure/measure_keys.h"

namespace surfreg {
namespace {

using namespace config_value;

constexpr double kPi = 3.14159265358979323846;

const Names<CostKind> kCosts = {{"auto", CostKind::kAuto},
                                {"volume", CostKind::kVolume},
                                {"axial", CostKind::kAxial},
                                {"axial_sparser", CostKind::kAxialSparser}};
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
const Names<CellKernelChoice> kCellKernels = {{"best", CellKernelChoice::kBest},
                                               {"scalar", CellKernelChoice::kScalar},
                                               {"avx2", CellKernelChoice::kAvx2},
                                               {"avx512", CellKernelChoice::kAvx512}};
const Names<MaskMode> kMaskModes = {{"include", MaskMode::kInclude}, {"exclude", MaskMode::kExclude}};
const Names<ceres::LinearSolverType> kLinearSolvers = {
    {"dense_qr", ceres::DENSE_QR}, {"dense_normal_cholesky", ceres::DENSE_NORMAL_CHOLESKY}, {"cgnr", ceres::CGNR}};

// free: parameter names (rx ... tz) and groups (rotation, translation, all),
// united; at least one.
std::array<bool, 6> FreeParameters(const Value& v) {
  std::array<bool, 6> free = {false, false, false, false, false, false};
  const std::vector<std::string> items = Items(v);
  if (items.empty()) Reject(v);
  for (const std::string& item : items) {
    const auto set = [&free](int first, int last) {
      for (int k = first; k < last; ++k) free[k] = true;
    };
    if (item == "all") {
      set(0, 6);
    } else if (item == "rotation") {
      set(0, 3);
    } else if (item == "translation") {
      set(3, 6);
    } else {
      const auto* name = std::find(kParameterNames.begin(), kParameterNames.end(), item);
      if (name == kParameterNames.end()) Reject(v);
      const int k = static_cast<int>(name - kParameterNames.begin());
      set(k, k + 1);
    }
  }
  return free;
}

// "all" or "[rx, tz]"
std::string FreeText(const std::array<bool, 6>& free) {
  if (std::all_of(free.begin(), free.end(), [](bool b) { return b; })) return "all";
  std::string out;
  for (int k = 0; k < 6; ++k) {
    if (free[k]) out += std::string(out.empty() ? "" : ", ") + kParameterNames[k];
  }
  return "[" + out + "]";
}

// A key of the data domain (measure/measure_keys.h) as an option key.
AlignOptionEntry Domain(const char* name) {
  for (const DomainRuleEntry& entry : DomainRuleKeys()) {
    if (name == std::string(entry.key.name)) {
      return {entry.key, [&entry](const Value& v, AlignOptions* o) { entry.set(v, &o->domain); },
              [&entry](const AlignOptions& o) { return entry.get(o.domain); }};
    }
  }
  throw std::logic_error(std::string("no domain key ") + name);
}

}  // namespace

const std::vector<AlignOptionEntry>& AlignOptionKeys() {
  static const std::vector<AlignOptionEntry> keys = {
      {{"cost", "one of auto, volume, axial, axial_sparser",
        "auto: volume, or axial_sparser for terrain of two resolutions (2.5 x apart in area per sample, of mixed "
        "curvature); volume: rho_d per unit overlap area; axial: least squares on the vertical gaps at both "
        "surfaces' nodes (rho'_d); axial_sparser: the axial cost at the sparser surface's nodes only"},
       [](const Value& v, AlignOptions* o) { o->cost = Choice(v, kCosts); },
       [](const AlignOptions& o) { return NameOf(o.cost, kCosts); }},
      {{"prealign", "true or false",
        "volume cost: first solve with the axial cost on the coarsest level"},
       [](const Value& v, AlignOptions* o) { o->prealign = Boolean(v); },
       [](const AlignOptions& o) { return Text(o.prealign); }},
      {{"loss", "one of none, huber, soft_l1, cauchy", "robust loss of the axial residuals"},
       [](const Value& v, AlignOptions* o) { o->loss = Choice(v, kLosses); },
       [](const AlignOptions& o) { return NameOf(o.loss, kLosses); }},
      {{"loss_scale", "a number >= 0",
        "scale of the robust loss (data units); 0 = 3 x 1.4826 x median |residual|"},
       [](const Value& v, AlignOptions* o) { o->loss_scale = Number(v, 0, HUGE_VAL); },
       [](const AlignOptions& o) { return Text(o.loss_scale); }},
      {{"trust_region", "one of levenberg_marquardt, dogleg", "trust-region step (axial cost)"},
       [](const Value& v, AlignOptions* o) { o->axial_solver.trust_region_strategy_type = Choice(v, kTrustRegions); },
       [](const AlignOptions& o) { return NameOf(o.axial_solver.trust_region_strategy_type, kTrustRegions); }},
      {{"line_search", "one of lbfgs, bfgs, nonlinear_cg", "line-search direction (volume cost)"},
       [](const Value& v, AlignOptions* o) { o->volume_solver.line_search_direction_type = Choice(v, kLineSearches); },
       [](const AlignOptions& o) { return NameOf(o.volume_solver.line_search_direction_type, kLineSearches); }},
      {{"linear_solver", "one of dense_qr, dense_normal_cholesky, cgnr",
        "linear solver of the trust-region steps (axial cost, prealignment)"},
       [](const Value& v, AlignOptions* o) { o->axial_solver.linear_solver_type = Choice(v, kLinearSolvers); },
       [](const AlignOptions& o) { return NameOf(o.axial_solver.linear_solver_type, kLinearSolvers); }},
      {{"max_iterations", "an integer >= 1", "solver iterations per level and start"},
       [](const Value& v, AlignOptions* o) {
         o->axial_solver.max_num_iterations = o->volume_solver.max_num_iterations = Integer(v, 1);
       },
       [](const AlignOptions& o) { return std::to_string(o.axial_solver.max_num_iterations); }},
      {{"function_tolerance", "a number in (0, 1)",
        "a solve stops when an iteration lowers its cost by less than this fraction of it (both solvers; "
        "unset, the axial cost's is 1e-12)"},
       [](const Value& v, AlignOptions* o) {
         o->axial_solver.function_tolerance = o->volume_solver.function_tolerance =
             Number(v, 0, 1, "()");
       },
       [](const AlignOptions& o) { return Text(o.volume_solver.function_tolerance); }},
      {{"trim_fraction", "a number in [0, 0.5)",
        "fraction of the largest axial residuals dropped at each evaluation"},
       [](const Value& v, AlignOptions* o) { o->trim_fraction = Number(v, 0, 0.5, "[)"); },
       [](const AlignOptions& o) { return Text(o.trim_fraction); }},
      {{"normal_distance", "true or false",
        "axial gaps weighted by cos(slope): the distance along the normal"},
       [](const Value& v, AlignOptions* o) { o->normal_distance = Boolean(v); },
       [](const AlignOptions& o) { return Text(o.normal_distance); }},
      {{"slope_weight", "a number in [0, 8]",
        "volume cost: weight by cos(reference slope)^this; 0 = plain volume"},
       [](const Value& v, AlignOptions* o) { o->slope_weight = Number(v, 0, 8); },
       [](const AlignOptions& o) { return Text(o.slope_weight); }},
      {{"gap_weight", "a number in [0, 100]",
        "volume cost: weight by f / (f + local interpolation gap), f = this x its median; 0 = off"},
       [](const Value& v, AlignOptions* o) { o->gap_weight = Number(v, 0, 100); },
       [](const AlignOptions& o) { return Text(o.gap_weight); }},
      {{"density_weight", "0 or a number in [1, 1e6]",
        "volume cost: where the reference's area per sample varies this many times (90th / 10th percentile; a "
        "mesh's vertices), weight each place by its sample density, so each sample counts alike; 0 = off"},
       [](const Value& v, AlignOptions* o) {
         const double r = Number(v, 0, 1e6);
         if (r != 0 && r < 1) Reject(v);
         o->density_weight = r;
       },
       [](const AlignOptions& o) { return Text(o.density_weight); }},
      {{"density_correction", "0 or a number in [1, 1e6]",
        "correct the sparser surface's chords for its curvature when its area per sample is this many times the "
        "other's; 0 = off"},
       [](const Value& v, AlignOptions* o) {
         const double r = Number(v, 0, 1e6);
         if (r != 0 && r < 1) Reject(v);
         o->density_correction = r;
       },
       [](const AlignOptions& o) { return Text(o.density_correction); }},
      {{"free", "a list of rx, ry, rz, tx, ty, tz, rotation, translation, all",
        "the parameters the solver may change (the others keep their initial value)"},
       [](const Value& v, AlignOptions* o) { o->free = FreeParameters(v); },
       [](const AlignOptions& o) { return FreeText(o.free); }},
      {{"levels", "an integer in [1, 8]", "coarse-to-fine levels"},
       [](const Value& v, AlignOptions* o) { o->levels = Integer(v, 1, 8); },
       [](const AlignOptions& o) { return std::to_string(o.levels); }},
      {{"level_factor", "a number in [1.5, 64]", "subsampling factor between levels"},
       [](const Value& v, AlignOptions* o) { o->level_factor = Number(v, 1.5, 64); },
       [](const AlignOptions& o) { return Text(o.level_factor); }},
      {{"subsample", "a number in (0, 1]",
        "fraction of each cloud's points solved on at the finest level"},
       [](const Value& v, AlignOptions* o) { o->subsample = Number(v, 0, 1, "(]"); },
       [](const AlignOptions& o) { return Text(o.subsample); }},
      {{"multi_start", "an integer in [0, 1000]", "extra starts around the initial motion"},
       [](const Value& v, AlignOptions* o) { o->multi_start = Integer(v, 0, 1000); },
       [](const AlignOptions& o) { return std::to_string(o.multi_start); }},
      {{"multi_start_angle_deg", "a number in [0, 90]", "rotation of the extra starts (degrees)"},
       [](const Value& v, AlignOptions* o) { o->multi_start_angle_deg = Number(v, 0, 90); },
       [](const AlignOptions& o) { return Text(o.multi_start_angle_deg); }},
      {{"multi_start_shift", "a number >= 0",
        "shift of the extra starts (data units); 0 = 5 mean sample spacings"},
       [](const Value& v, AlignOptions* o) { o->multi_start_shift = Number(v, 0, HUGE_VAL); },
       [](const AlignOptions& o) { return Text(o.multi_start_shift); }},
      {{"stddev", "one of sandwich, information",
        "standard deviations of the motion: sandwich (the cost's curvature and the spread of its "
        "gradient over tiles ~10 sample spacings wide) or information (from the axial residuals' information matrix)"},
       [](const Value& v, AlignOptions* o) { o->stddev_method = Choice(v, kStddevMethods); },
       [](const AlignOptions& o) { return NameOf(o.stddev_method, kStddevMethods); }},
      {{"stddev_subsamples", "an integer in [0, 1000]",
        "standard deviations from this many alignments on block half-samples of the reference "
        "(0: as `stddev` says)"},
       [](const Value& v, AlignOptions* o) { o->stddev_subsamples = Integer(v, 0, 1000); },
       [](const AlignOptions& o) { return std::to_string(o.stddev_subsamples); }},
      {{"holdout", "a number in [0, 0.9)",
        "held-out check: fit on the reference less this share of its 8 x 8 tiles (seeded), then "
        "report dz there before and after; 0 = off"},
       [](const Value& v, AlignOptions* o) { o->holdout_fraction = Number(v, 0, 0.9, "[)"); },
       [](const AlignOptions& o) { return Text(o.holdout_fraction); }},
      {{"holdout_seed", "an integer >= 0", "which tiles are held out"},
       [](const Value& v, AlignOptions* o) { o->holdout_seed = static_cast<uint64_t>(Integer(v, 0)); },
       [](const AlignOptions& o) { return std::to_string(o.holdout_seed); }},
      {{"holdout_verdict", "true or false",
        "the verdict is converged_improved only if the held-out tiles improved too"},
       [](const Value& v, AlignOptions* o) { o->holdout_verdict = Boolean(v); },
       [](const AlignOptions& o) { return std::string(o.holdout_verdict ? "true" : "false"); }},
      {{"wide_search", "one of auto, always, never",
        "try 50 starts (12° and 24° about 12 axes, and the centroids matched) on a coarse "
        "subsample and solve from the best: always, or (auto) when the alignment from the initial "
        "motion fails, does not improve, or leaves the surfaces apart (with stable auto: apart on "
        "the stable terrain)"},
       [](const Value& v, AlignOptions* o) { o->wide_search = Choice(v, kWideSearches); },
       [](const AlignOptions& o) { return NameOf(o.wide_search, kWideSearches); }},
      {{"initial_rotation_deg", "a list of 3 numbers [rx, ry, rz]",
        "initial rotation vector (degrees), about the moving centroid"},
       [](const Value& v, AlignOptions* o) {
         const std::array<double, 3> deg = Vector3(v);
         for (int k = 0; k < 3; ++k) o->initial_rotation[k] = deg[k] * kPi / 180;
       },
       [](const AlignOptions& o) { return Text(o.initial_rotation, 180 / kPi); }},
      {{"initial_translation", "a list of 3 numbers [tx, ty, tz]",
        "initial shift of the moving centroid (data units)"},
       [](const Value& v, AlignOptions* o) { o->initial_translation = Vector3(v); },
       [](const AlignOptions& o) { return Text(o.initial_translation); }},
      {{"mask_mode", "one of include, exclude",
        "include: the mask is the stable terrain; exclude: it is the unstable areas, left out"},
       [](const Value& v, AlignOptions* o) { o->mask_mode = Choice(v, kMaskModes); },
       [](const AlignOptions& o) { return NameOf(o.mask_mode, kMaskModes); }},
      {{"stable", "one of auto, all",
        "auto: fit, exclude the regions whose gaps changed (beyond stable_sigmas robust sigmas, grown "
        "to stable_grow_sigmas), fit again on the rest, until the set settles; all: the whole overlap. "
        "Inside the mask or weights, if any"},
       [](const Value& v, AlignOptions* o) { o->stable.mode = Choice(v, kStableModes); },
       [](const AlignOptions& o) { return NameOf(o.stable.mode, kStableModes); }},
      {{"stable_sigmas", "a number in [1, 100]",
        "stable auto: a change region holds a gap this many robust sigmas from the stable median"},
       [](const Value& v, AlignOptions* o) { o->stable.seed_sigmas = Number(v, 1, 100); },
       [](const AlignOptions& o) { return Text(o.stable.seed_sigmas); }},
      {{"stable_grow_sigmas", "a number in [0.5, 100]",
        "stable auto: a change region grows through neighbours this many robust sigmas out, on its side"},
       [](const Value& v, AlignOptions* o) { o->stable.grow_sigmas = Number(v, 0.5, 100); },
       [](const AlignOptions& o) { return Text(o.stable.grow_sigmas); }},
      Domain("domain"),
      Domain("domain_max_edge_spacings"),
      Domain("domain_min_thinness"),
      {{"max_fold_fraction", "a number in [0, 1]",
        "share of the moving surface's area that may fold over (slivers: re-triangulated)"},
       [](const Value& v, AlignOptions* o) { o->max_fold_fraction = Number(v, 0, 1); },
       [](const AlignOptions& o) { return Text(o.max_fold_fraction); }},
      {{"covariance", "true or false", "compute the parameters' standard deviations"},
       [](const Value& v, AlignOptions* o) { o->compute_covariance = Boolean(v); },
       [](const AlignOptions& o) { return Text(o.compute_covariance); }},
      {{"threads", kThreadsType, "threads for the solver and the measures (all: every core)"},
       [](const Value& v, AlignOptions* o) { o->num_threads = ThreadCount(v); },
       [](const AlignOptions& o) { return ThreadText(o.num_threads); }},
      {{"cell_kernel", "one of best, scalar, avx2, avx512",
        "volume cost: the kernel of the cell integrals (best: the widest this CPU runs; the others for "
        "comparison, the same cost to rounding)"},
       [](const Value& v, AlignOptions* o) { o->cell_kernel = Choice(v, kCellKernels); },
       [](const AlignOptions& o) { return NameOf(o.cell_kernel, kCellKernels); }},
  };
  return keys;
}

const AlignOptionEntry* FindAlignOption(const std::string& name) {
  for (const AlignOptionEntry& entry : AlignOptionKeys()) {
    if (name == entry.key.name) return &entry;
  }
  return nullptr;
}

void SetAlignOption(const std::string& name, Value value, AlignOptions* options) {
  SetOption(AlignOptionKeys(), name, std::move(value), options);
}

std::string AlignOptionValue(const AlignOptions& options, const std::string& name) {
  const AlignOptionEntry* entry = FindAlignOption(name);
  if (entry == nullptr) throw InputError("unknown key " + Quote(name));
  return entry->get(options);
}

}  // namespace surfreg
