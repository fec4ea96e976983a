#pragma once
// The steps of an alignment before its result (registration/align.cc, the
// pipeline): checking the inputs, preparing the levels and the solve's
// context, and solving from each start through every level. Internal.
#include <array>
#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include "measure/measures.h"
#include "measure/surface.h"
#include "registration/align_options.h"
#include "registration/chord_bias.h"
#include "registration/pair_state.h"
#include "registration/solvers.h"

namespace surfreg {
namespace align_steps {

using Clock = std::chrono::steady_clock;
inline double Seconds(Clock::time_point from) {
  return std::chrono::duration<double>(Clock::now() - from).count();
}

// One level of the coarse-to-fine solve: both sides prepared.
struct Level {
  ReferenceSide reference;
  MovingSide moving;
  DensityCorrection density;  // what CorrectDensityBias did to the two
};

// The volume cost's prealignment on fixed subsamples of both surfaces
// (align_steps.cc PrealignSides): `sides` for the axial solve (empty: it
// runs on the coarsest level itself), `refine` the same weighted as the
// volume cost, for a volume solve there before the levels (empty: not worth
// it on clouds this small).
struct Prealignment {
  std::optional<Level> sides, refine;
};

// A per_point weight needs weights on the reference, not all zero.
void CheckPerPointWeights(const Surface& reference, const AlignOptions& options);

// The reference side PrepareReference(surface, 1, rule) builds, taken from
// the measure's preparation of the same surface by the same rule instead of
// triangulating it again; nothing if the surface has duplicate xy (the
// measure keeps them as one vertex, the side drops them and re-meshes).
std::optional<ReferenceSide> ReferenceSideOf(const PreparedSurface& prepared);

// Levels, coarsest first; all share the full cloud's centroid so θ means
// the same motion on every level. With `measure_reference` (and no
// subsampling), the reference is prepared for the measures there too
// (MeasureReference by `measure_options`), and the finest level's side
// taken from it.
std::vector<std::unique_ptr<Level>> PrepareLevels(const Surface& reference, const Surface& moving,
                                                  const AlignOptions& options,
                                                  const std::array<double, 3>& shift,
                                                  const MeasureOptions* measure_options = nullptr,
                                                  std::unique_ptr<MeasureReference>* measure_reference = nullptr);

// cost auto (align_options.h CostKind): surfaces kSparserNodesRatio or more
// apart in density whose curvature changes sign (the finest level's density
// check) are solved with the axial cost at the sparser surface's nodes
// (per-point weights: never).
bool SparserNodesChosen(const Level& finest, const AlignOptions& options);

// The solve's context: the options, and what the solve runs resolved from
// them and the data (the cost, the axial cost's nodes). `sparser_nodes`
// (SparserNodesChosen) also drops the volume cost's slope and gap weights
// from the levels.
SolveContext MakeContext(const AlignOptions* options, bool sparser_nodes,
                         const std::vector<std::unique_ptr<Level>>& levels, const Surface& reference);

// The start must not fold the moving surface; the axial cost's automatic
// loss scale is taken there (into context->loss_scale).
void CheckStart(const Level& finest, const std::array<double, 6>& theta0, const Surface& moving,
                SolveContext* context);

// What the starts (AlignOptions::multi_start, each through every level)
// found: the lowest final cost.
struct Starts {
  SolveResult best;
  bool have_best = false;
  // The volume cost's finest-level state at `best` and its overlay cache
  // (B's surface fixed as the solve ended): the sandwich σ evaluates there.
  std::shared_ptr<PairState> best_state;
  std::shared_ptr<VolumeCostCache> best_cache;
  int iterations = 0;
  int remeshes = 0;
  bool wide_search_ran = false;
};

// The wide search (if always), then every start through every level.
Starts SolveFromStarts(const Surface& reference, const Surface& moving,
                       const std::vector<std::unique_ptr<Level>>& levels, const std::array<double, 3>& shift,
                       const std::array<double, 6>& theta0, const AlignOptions& options, SolveContext& context,
                       Clock::time_point start);

}  // namespace align_steps
}  // namespace surfreg
