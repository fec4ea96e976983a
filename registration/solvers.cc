#include "registration/solvers.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <ceres/ceres.h>

#include "registration/volume_cost/volume_cost.h"

namespace surfreg {

int CeresThreads(int requested) {
  const int cores = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return std::min(ExecutionFor(requested).threads, cores);
}

namespace {

// A trust-region step may not leave less than this share of the starting
// overlap's node weight (a cost that is a mean over the overlap can be
// lowered by sliding almost all of it away).
constexpr double kMinKeptOverlap = 0.25;

// The free parameters as the solver's vector x = T θ_free: by default T
// scales rotations by a length (rotations × scale, translations), so x is
// a vector of lengths; Whiten makes it a whitening of a curvature.
struct ParameterMap {
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 6, 6>;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;
  std::vector<int> free;  // indices into (rx, ry, rz, tx, ty, tz)
  double rotation_scale = 1.0;
  std::array<double, 6> fixed{};  // full θ supplying the locked values
  Matrix to_x, from_x;            // T and T⁻¹

  ParameterMap(const AlignOptions& options, double scale, const std::array<double, 6>& theta0)
      : rotation_scale(scale), fixed(theta0) {
    for (int k = 0; k < 6; ++k) {
      if (options.free[k]) free.push_back(k);
    }
    to_x = Matrix::Zero(size(), size());
    from_x = Matrix::Zero(size(), size());
    for (int i = 0; i < size(); ++i) to_x(i, i) = Factor(free[i]), from_x(i, i) = 1 / Factor(free[i]);
  }
  int size() const { return static_cast<int>(free.size()); }
  double Factor(int k) const { return k < 3 ? rotation_scale : 1.0; }
  std::array<double, 6> Full(const double* x) const {
    std::array<double, 6> theta = fixed;
    const Vector t = from_x * Eigen::Map<const Vector>(x, size());
    for (int i = 0; i < size(); ++i) theta[free[i]] = t[i];
    return theta;
  }
  std::vector<double> Reduce(const std::array<double, 6>& theta) const {
    Vector t(size());
    for (int i = 0; i < size(); ++i) t[i] = theta[free[i]];
    const Vector x = to_x * t;
    return std::vector<double>(x.data(), x.data() + size());
  }
  // d/dx of what has derivative `d` (all six) in θ.
  void DerivativeOfX(const double* d, double* out) const {
    Vector df(size());
    for (int i = 0; i < size(); ++i) df[i] = d[free[i]];
    Eigen::Map<Vector>(out, size()) = from_x.transpose() * df;
  }
  // T = Lᵀ with H = L Lᵀ (θ units): a solver that sees H as the identity.
  // False (and T unchanged) if H is not positive definite.
  bool Whiten(const Eigen::MatrixXd& h) {
    Eigen::LLT<Eigen::MatrixXd> llt(h);
    if (llt.info() != Eigen::Success) return false;
    const Matrix upper = llt.matrixU();
    const Matrix inverse = upper.inverse();
    if (!upper.allFinite() || !inverse.allFinite()) return false;
    to_x = upper, from_x = inverse;
    return true;
  }
};

class LogCallback : public ceres::IterationCallback {
 public:
  explicit LogCallback(const SolveContext& context) : context_(context) {}
  // A solve in rounds: number on from `offset`; `skip_first`: a later
  // round's iteration 0 repeats the previous round's last.
  void set_iteration_offset(int offset, bool skip_first) {
    offset_ = offset;
    skip_first_ = skip_first;
  }
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& summary) override {
    if (skip_first_ && summary.iteration == 0) return ceres::SOLVER_CONTINUE;
    AlignOptions::Iteration entry;
    entry.level = context_.level;
    entry.start = context_.start;
    entry.cost_name = context_.cost;
    entry.iteration = offset_ + summary.iteration;
    entry.cost = summary.cost;
    entry.step_norm = summary.step_norm;
    entry.gradient_norm = summary.gradient_max_norm;
    entry.seconds = context_.seconds_offset + summary.cumulative_time_in_seconds;
    if (context_.log != nullptr) context_.log->push_back(entry);
    if (context_.options->on_iteration) context_.options->on_iteration(entry);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const SolveContext& context_;
  int offset_ = 0;
  bool skip_first_ = false;
};

// Evaluates all node residuals once per new θ; the cost functions read them.
class AxialEvaluation : public ceres::EvaluationCallback {
 public:
  // `min_active_weight`: a θ whose overlap holds less node weight than this
  // is infeasible. Only the nodes in the overlap have residuals, so without
  // it a step that slides B off A zeroes the cost and looks like the best
  // possible solution.
  AxialEvaluation(PairState& state, const AxialSettings& settings, const ParameterMap& map,
                  const double* x, double min_active_weight)
      : state_(state), settings_(settings), map_(map), x_(x),
        min_active_weight_(min_active_weight) {}

  void PrepareForEvaluation(bool evaluate_jacobians, bool new_evaluation_point) override {
    if (new_evaluation_point) {
      UpdateStats stats;
      ok_ = state_.Update(map_.Full(x_), &stats);
      refused_folds_ += stats.remesh_refused ? 1 : 0;
      have_jacobians_ = false;
      if (ok_) {
        ComputeAxialResiduals(state_, settings_, evaluate_jacobians, &residuals);
        have_jacobians_ = evaluate_jacobians;
        ok_ = residuals.active_weight >= min_active_weight_;
      }
    } else if (ok_ && evaluate_jacobians && !have_jacobians_) {
      ComputeAxialResiduals(state_, settings_, true, &residuals);
      have_jacobians_ = true;
    }
  }
  bool ok() const { return ok_; }
  int refused_folds() const { return refused_folds_; }
  AxialResiduals residuals;

 private:
  PairState& state_;
  const AxialSettings& settings_;
  const ParameterMap& map_;
  const double* x_;
  double min_active_weight_;
  bool ok_ = false, have_jacobians_ = false;
  int refused_folds_ = 0;
};

// The residuals of nodes [begin, end): one node per block under a robust
// loss (the loss acts on each block's norm), else a run of nodes, since
// Ceres' per-block overhead (~1,600 instructions) exceeded the residual's
// own work.
class NodeResiduals : public ceres::CostFunction {
 public:
  NodeResiduals(const AxialEvaluation& evaluation, const ParameterMap& map, std::size_t begin,
                std::size_t end)
      : evaluation_(evaluation), map_(map), begin_(begin), end_(end) {
    set_num_residuals(static_cast<int>(end - begin));
    mutable_parameter_block_sizes()->push_back(map.size());
  }
  bool Evaluate(double const* const* /*parameters*/, double* residuals,
                double** jacobians) const override {
    if (!evaluation_.ok()) return false;  // folded: an infeasible step
    const AxialResiduals& all = evaluation_.residuals;
    for (std::size_t k = begin_; k < end_; ++k) residuals[k - begin_] = all.r[k];
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      const int n = map_.size();
      double* out = jacobians[0];
      for (std::size_t k = begin_; k < end_; ++k, out += n) map_.DerivativeOfX(all.jacobian[k].data(), out);
    }
    return true;
  }

 private:
  const AxialEvaluation& evaluation_;
  const ParameterMap& map_;
  std::size_t begin_, end_;
};

// B's surface fixed at θ0 and located there (false if it folds there
// beyond the limit). A level or start begins on B's own mesh, which may fold
// at θ0 (junk, or steep triangles): fixed first, it re-meshes once, around
// the kept triangles, not freely and then again around them.
bool FixAt(PairState& state, const std::array<double, 6>& theta0, double max_slope_deg) {
  state.MoveTo(theta0);
  state.FixSurface(max_slope_deg);
  if (state.Update(theta0)) return true;
  // The kept triangles overlap at θ0: B's own Delaunay there first.
  state.ReleaseSurface();
  if (!state.Update(theta0)) return false;
  state.FixSurface(max_slope_deg);
  return true;
}

std::unique_ptr<ceres::LossFunction> MakeLoss(LossKind kind, double scale) {
  switch (kind) {
    case LossKind::kNone: return nullptr;
    case LossKind::kHuber: return std::make_unique<ceres::HuberLoss>(scale);
    case LossKind::kSoftL1: return std::make_unique<ceres::SoftLOneLoss>(scale);
    case LossKind::kCauchy: return std::make_unique<ceres::CauchyLoss>(scale);
  }
  return nullptr;
}

void FillResult(const ParameterMap& map, const std::vector<double>& x, double initial_cost,
                double final_cost, int iterations, ceres::TerminationType termination,
                bool usable, const std::string& message, SolveResult* result) {
  result->theta = map.Full(x.data());
  result->initial_cost = initial_cost;
  result->final_cost = final_cost;
  result->iterations = iterations;
  result->converged = termination == ceres::CONVERGENCE || termination == ceres::USER_SUCCESS;
  result->usable = usable;
  result->message = message;
}

}  // namespace

double AutomaticLossScale(const PairState& state, const AxialSettings& settings, double floor) {
  AxialResiduals residuals;
  ComputeAxialResiduals(state, settings, false, &residuals);
  std::vector<double> magnitudes;
  for (std::size_t k = 0; k < residuals.r.size(); ++k) {
    if (residuals.active[k]) magnitudes.push_back(std::fabs(residuals.r[k]));
  }
  if (magnitudes.empty()) return floor;
  std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2,
                   magnitudes.end());
  const double median = magnitudes[magnitudes.size() / 2];
  return median > 0 ? 3.0 * 1.4826 * median : floor;
}

SolveResult SolveAxial(PairState& state, const SolveContext& context,
                       const std::array<double, 6>& theta0) {
  const AlignOptions& options = *context.options;
  ParameterMap map(options, context.rotation_scale, theta0);
  std::vector<double> x = map.Reduce(theta0);
  const std::size_t nodes = state.reference().xy.size() + state.moving().points.size();

  double scale = context.loss_scale > 0 ? context.loss_scale : options.loss_scale;
  if (options.loss != LossKind::kNone && !(scale > 0)) {
    scale = state.Update(theta0) ? AutomaticLossScale(state, context.axial, 1e-12) : 1.0;
  }
  std::unique_ptr<ceres::LossFunction> loss = MakeLoss(options.loss, scale);
  // The cost is a mean over Ω (see AxialSettings::normalize_count); with the
  // taper (axial_cost.h), continuous as nodes enter and leave Ω.
  AxialSettings settings = context.axial;
  {
    AxialResiduals start;
    if (state.Update(theta0)) {
      ComputeAxialResiduals(state, settings, false, &start);
      settings.normalize_count = start.active_weight;
    }
  }
  // Steps that lose most of the overlap are refused (see AxialEvaluation).
  AxialEvaluation evaluation(state, settings, map, x.data(),
                             kMinKeptOverlap * settings.normalize_count);
  ceres::Problem::Options problem_options;
  problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  problem_options.evaluation_callback = &evaluation;
  ceres::Problem problem(problem_options);
  const std::size_t run = loss ? 1 : 256;
  for (std::size_t k = 0; k < nodes; k += run) {
    problem.AddResidualBlock(new NodeResiduals(evaluation, map, k, std::min(nodes, k + run)),
                             loss.get(), x.data());
  }

  ceres::Solver::Options solver = options.axial_solver;
  if (context.prealignment) {
    solver.function_tolerance = std::max(solver.function_tolerance, kPrealignTolerance);
    solver.parameter_tolerance = kPrealignTolerance;
  }
  // One Ceres thread: the evaluation callback does the work, on every
  // thread; the blocks only copy it out. Ceres on several threads sums the
  // blocks' costs and gradients per thread, in an order that depends on the
  // thread count: the cost differed in its last bits from the one-thread
  // run's, and sometimes then the iterations (a face pair's rotation by 1e-12°).
  solver.num_threads = 1;
  LogCallback log(context);
  solver.callbacks.push_back(&log);
  // B's surface is fixed as in SolveVolume: a trust region compares the
  // cost at the trial point with the cost at the current one, which must be
  // of one surface (a whole re-mesh at trial points made Levenberg-Marquardt
  // alternate between two costs for 40 iterations on a face). Junk folds
  // re-mesh around the surface and change nothing; a step that turns an
  // active triangle over is refused (the radius shrinks). The solve travels
  // far, so it goes in rounds: stopped against such a fold, or with other
  // triangles steep at its end than at its start, it fixes the surface again
  // there and goes on.
  constexpr int kMaxRounds = 6;
  constexpr double kMaxSlopeDeg = 80.0;
  FixAt(state, theta0, kMaxSlopeDeg);
  ceres::Solver::Summary summary;
  double initial_cost = 0;
  int iterations = 0, rounds = 0;
  for (int round = 0; round < kMaxRounds; ++round) {
    ++rounds;
    log.set_iteration_offset(iterations, round > 0);
    const int refused_before = evaluation.refused_folds();
    ceres::Solve(solver, &problem, &summary);
    if (round == 0) initial_cost = summary.initial_cost;
    iterations += static_cast<int>(summary.iterations.size()) - 1;
    if (!summary.IsSolutionUsable() || !std::isfinite(summary.final_cost) || round + 1 == kMaxRounds) break;
    const uint64_t key = state.surface_key();
    if (!state.Update(map.Full(x.data()))) break;
    state.FixSurface(kMaxSlopeDeg);
    const bool refused = evaluation.refused_folds() > refused_before;
    if (!refused && state.surface_key() == key) break;
  }
  state.ReleaseSurface();
  SolveResult result;
  FillResult(map, x, initial_cost, summary.final_cost, iterations, summary.termination_type,
             summary.IsSolutionUsable() && std::isfinite(summary.final_cost), summary.message,
             &result);
  result.rounds = rounds;
  return result;
}

namespace {

class VolumeFunction : public ceres::FirstOrderFunction {
 public:
  VolumeFunction(PairState& state, const ParameterMap& map, const Execution& execution, const MaskRegion* mask,
                 VolumeCostCache& cache)
      : state_(state), map_(map), execution_(execution), mask_(mask), cache_(cache) {}
  bool Evaluate(const double* x, double* cost, double* gradient) const override {
    UpdateStats stats;
    if (!state_.Update(map_.Full(x), &stats)) {
      refused_folds_ += stats.remesh_refused ? 1 : 0;
      return false;
    }
    // Incremental: the overlay's combinatorics are kept between evaluations.
    const VolumeCostValue value = cache_.Evaluate(state_, gradient != nullptr, execution_, mask_);
    if (!(value.area > 0)) return false;
    *cost = value.PerArea();
    if (gradient != nullptr) {
      const Eigen::Matrix<double, 6, 1> g = value.PerAreaGradient();
      map_.DerivativeOfX(g.data(), gradient);
    }
    return std::isfinite(*cost);
  }
  int NumParameters() const override { return map_.size(); }
  // Evaluations refused for slivers of B that fold there, which a re-mesh
  // would have let through (a tilt past what B can take is not counted: it
  // is just an infeasible step, and re-meshing would not change it).
  int refused_folds() const { return refused_folds_; }

 private:
  PairState& state_;
  const ParameterMap& map_;
  Execution execution_;
  const MaskRegion* mask_;
  VolumeCostCache& cache_;  // bound to state_ (one state per solve)
  mutable int refused_folds_ = 0;
};

// The volume cost's Hessian in θ (free parameters) at the state's θ, as
// the axial cost sees it: JᵀJ / N of the vertical gaps at the active nodes,
// times 2φ(0)/σ = √(2/π)/σ for the L1 cost of gaps with a robust spread σ
// (E|r + δ| grows as δ²φ(0)/σ). Only its shape and scale matter: the volume
// solve runs in coordinates where it is the identity, since radians and
// lengths, and rotations coupled with translations, left L-BFGS creeping
// (on terrain 2-3× the iterations).
Eigen::MatrixXd AxialCurvature(const PairState& state, const SolveContext& context, const ParameterMap& map) {
  const int n = map.size();
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  AxialResiduals residuals;
  ComputeAxialResiduals(state, context.axial, true, &residuals);
  std::vector<double> magnitudes;
  for (std::size_t k = 0; k < residuals.r.size(); ++k) {
    if (!residuals.active[k]) continue;
    Eigen::VectorXd row(n);
    for (int i = 0; i < n; ++i) row[i] = residuals.jacobian[k][map.free[i]];
    h.noalias() += row * row.transpose();
    magnitudes.push_back(std::fabs(residuals.r[k]));
  }
  if (magnitudes.empty()) return h;
  h /= static_cast<double>(magnitudes.size());
  std::nth_element(magnitudes.begin(), magnitudes.begin() + magnitudes.size() / 2, magnitudes.end());
  const double sigma = 1.4826 * magnitudes[magnitudes.size() / 2];
  if (sigma > 0) h *= std::sqrt(2 / M_PI) / sigma;
  // A floor, in units where rotation and translation weigh alike, for
  // directions the gaps do not see (a plane's slide along itself).
  Eigen::VectorXd s(n);
  for (int i = 0; i < n; ++i) s[i] = map.Factor(map.free[i]);
  Eigen::MatrixXd scaled = s.cwiseInverse().asDiagonal() * h * s.cwiseInverse().asDiagonal();
  scaled += 1e-6 * scaled.trace() / n * Eigen::MatrixXd::Identity(n, n);
  return s.asDiagonal() * scaled * s.asDiagonal();
}

// The volume cost's own curvature at the state's θ (per unit area, all six
// parameters; registration/volume_cost/volume_hessian.h), from the overlay `cache`
// builds there; zero without an overlap.
Eigen::Matrix<double, 6, 6> FullVolumeCurvature(const PairState& state, const Execution& execution, VolumeCostCache& cache) {
  const double area = cache.Evaluate(state, false, execution).area;
  if (!(area > 0)) return Eigen::Matrix<double, 6, 6>::Zero();
  return cache.InteriorHessian(state, execution) / area;
}

// A curvature of all six parameters restricted to the free ones, with
// AxialCurvature's floor.
Eigen::MatrixXd FreeCurvature(const Eigen::Matrix<double, 6, 6>& full, const ParameterMap& map) {
  const int n = map.size();
  Eigen::MatrixXd scaled(n, n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      scaled(i, j) = full(map.free[i], map.free[j]) / (map.Factor(map.free[i]) * map.Factor(map.free[j]));
    }
  }
  scaled += 1e-6 * scaled.trace() / n * Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd s(n);
  for (int i = 0; i < n; ++i) s[i] = map.Factor(map.free[i]);
  return s.asDiagonal() * scaled * s.asDiagonal();
}

}  // namespace

SolveResult SolveVolume(PairState& state, const SolveContext& context,
                        const std::array<double, 6>& theta0, VolumeCostCache* keep,
                        const VolumeWhitening& whitening) {
  const AlignOptions& options = *context.options;
  ParameterMap map(options, context.rotation_scale, theta0);
  // Without a usable curvature (no gaps seen), the diagonal scaling.
  // B's surface is fixed for the solve (PairState::FixSurface): the line
  // search compares values, and another surface is another function (on a
  // face with noise a mid-search re-mesh of the whole of B changed the cost
  // by 2% and stopped the solve at its start). Junk re-meshes keep the active
  // triangles, so they change nothing; a trial step that turns an active
  // triangle over is refused (the line search shortens it). Active
  // triangles steeper than kMaxSlopeDeg at the start are left out, so only a
  // tilt of several degrees can do that; a solve stopped against such a fold
  // fixes the surface again there and goes on.
  constexpr int kMaxRounds = 6;
  constexpr double kMaxSlopeDeg = 80.0;
  // (If B folds at θ0 beyond the limit, the first evaluation fails.)
  std::optional<VolumeCostCache> own_cache;
  if (keep == nullptr) own_cache.emplace(kSolveDirtyFraction, options.cell_kernel);
  VolumeCostCache& cache = keep != nullptr ? *keep : *own_cache;
  if (FixAt(state, theta0, kMaxSlopeDeg)) {
    // Whitened by the volume cost's own curvature at the start (on the 120
    // peer pairs 18% fewer iterations than by the axial one, every motion
    // the same), or by the one given; by the axial one under a mask, or
    // where neither is positive definite.
    bool whitened = false;
    if (context.axial.mask == nullptr) {
      // A subsample's curvature is too low by about the ratio of the two
      // samplings' gaps (×15 from 5000 to 1e5 points: the first step
      // overshot and its line search took two evaluations, each repairing
      // a third of the overlay). The value here builds the overlay the
      // solve's first evaluation then only re-integrates.
      double scale = 1;
      if (whitening.given != nullptr && whitening.given_cost > 0) {
        const VolumeCostValue start = cache.Evaluate(state, false, ExecutionFor(options.num_threads), nullptr);
        if (start.PerArea() > 0) scale = std::clamp(whitening.given_cost / start.PerArea(), 0.01, 100.0);
      }
      whitened = whitening.given != nullptr && map.Whiten(FreeCurvature(scale * *whitening.given, map));
      if (!whitened) {
        whitened = map.Whiten(FreeCurvature(FullVolumeCurvature(state, ExecutionFor(options.num_threads), cache), map));
      }
    }
    if (!whitened) map.Whiten(AxialCurvature(state, context, map));
  }
  std::vector<double> x = map.Reduce(theta0);
  ceres::GradientProblemSolver::Options solver = options.volume_solver;
  // x holds the last accepted iterate even when a round ends in a failed line
  // search (against a fold): the next round goes on from there.
  solver.update_state_every_iteration = true;
  LogCallback log(context);
  solver.callbacks.push_back(&log);
  ceres::GradientProblemSolver::Summary summary;
  double initial_cost = 0;
  int iterations = 0, rounds = 0;
  bool moved = false;  // some round accepted a step
  for (int round = 0; round < kMaxRounds; ++round) {
    ++rounds;
    auto* function = new VolumeFunction(state, map, ExecutionFor(options.num_threads), context.axial.mask.get(), cache);
    ceres::GradientProblem problem(function);  // owns `function`
    log.set_iteration_offset(iterations, round > 0);
    ceres::Solve(solver, problem, x.data(), &summary);
    if (round == 0) initial_cost = summary.initial_cost;
    iterations += static_cast<int>(summary.iterations.size()) - 1;
    moved |= summary.iterations.size() > 1;
    if (!std::isfinite(summary.final_cost) || round + 1 == kMaxRounds) break;
    // Which triangles are too steep was decided where the solve started,
    // which depends on the path there; decided again at the solution, the
    // surface is the same from any start (unless a triangle's slope is
    // within the solution's own resolution of the limit). Solve again only
    // if that changed it, or if the solve stopped against a fold.
    const uint64_t key = state.surface_key();
    if (!state.Update(map.Full(x.data()))) break;
    state.FixSurface(kMaxSlopeDeg);
    if (function->refused_folds() == 0 && state.surface_key() == key) break;
  }
  // A failed line search after accepted steps leaves a usable (if not
  // converged) solution; a failure before any step does not.
  const bool usable = std::isfinite(summary.final_cost) &&
                      (summary.termination_type != ceres::FAILURE || moved);
  SolveResult result;
  if (whitening.want_final && usable && context.axial.mask == nullptr && state.Update(map.Full(x.data()))) {
    result.curvature = FullVolumeCurvature(state, ExecutionFor(options.num_threads), cache);
  }
  if (keep == nullptr) state.ReleaseSurface();
  FillResult(map, x, initial_cost, summary.final_cost, iterations, summary.termination_type, usable,
             summary.message, &result);
  result.rounds = rounds;
  return result;
}

Information AnalyseInformation(PairState& state, const SolveContext& context, bool covariance) {
  Information info;
  const AlignOptions& options = *context.options;
  const std::array<double, 6> theta = state.theta();
  ParameterMap map(options, context.rotation_scale, theta);
  const int n = map.size();
  AxialResiduals residuals;
  if (!state.Update(theta)) return info;
  ComputeAxialResiduals(state, context.axial, true, &residuals);
  Eigen::MatrixXd h = Eigen::MatrixXd::Zero(n, n);
  double sum_squares = 0;
  for (std::size_t k = 0; k < residuals.r.size(); ++k) {
    if (!residuals.active[k]) continue;
    Eigen::VectorXd row(n);
    for (int i = 0; i < n; ++i) row[i] = residuals.jacobian[k][map.free[i]] / map.Factor(map.free[i]);
    h.noalias() += row * row.transpose();
    sum_squares += residuals.r[k] * residuals.r[k];
  }
  for (int k = 0; k < 6; ++k) {
    info.observability[k] = options.free[k] ? 0.0 : 1.0;
    info.constrained[k] = !options.free[k];
  }
  if (n == 0) return info;
  // o_i = 1 / (H_ii (H⁻¹)_ii): 1 when parameter i is uncorrelated with the
  // others, → 0 when a combination of it and others leaves the cost flat.
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(h);
  const Eigen::VectorXd lambda = eigen.eigenvalues();
  const double largest = std::max(lambda.maxCoeff(), 0.0);
  const double floor = std::max(largest * 1e-15, std::numeric_limits<double>::min());
  info.condition_number = largest / std::max(lambda.minCoeff(), floor);
  for (int i = 0; i < n; ++i) {
    double inverse_ii = 0;
    for (int e = 0; e < n; ++e) {
      const double v = eigen.eigenvectors()(i, e);
      inverse_ii += v * v / std::max(lambda[e], floor);
    }
    const double o = h(i, i) > floor ? 1.0 / (h(i, i) * inverse_ii) : 0.0;
    info.observability[map.free[i]] = std::min(1.0, o);
    // Unconstrained: a noticeable part of the parameter lies in directions
    // along which the cost is flat to rounding.
    double null_weight = 0;
    for (int e = 0; e < n; ++e) {
      if (lambda[e] < 1e-10 * largest) null_weight += eigen.eigenvectors()(i, e) * eigen.eigenvectors()(i, e);
    }
    info.constrained[map.free[i]] = largest > 0 && null_weight < 0.01;
  }
  if (!covariance || residuals.active_count <= n) return info;

  // The Gauss-Newton covariance σ² H⁻¹ from the eigen-decomposition above
  // (H = JᵀJ of the same residuals, so this is what ceres::Covariance with
  // DENSE_SVD gave, at none of its cost: that built a second problem over
  // every residual block and took a third of a face alignment's time).
  // Rank deficient to ceres' default tolerance (reciprocal condition number
  // 1e-14): not defined.
  if (!(lambda.minCoeff() > 1e-14 * largest)) return info;
  const Eigen::MatrixXd inverse =
      eigen.eigenvectors() * lambda.cwiseInverse().asDiagonal() * eigen.eigenvectors().transpose();
  const double variance = sum_squares / static_cast<double>(residuals.active_count - n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < n; ++j) {
      info.covariance(map.free[i], map.free[j]) =
          variance * inverse(i, j) / (map.Factor(map.free[i]) * map.Factor(map.free[j]));
    }
  }
  info.covariance_ok = true;
  return info;
}

}  // namespace surfreg
