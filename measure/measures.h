#pragma once
// The one-call comparison of two surfaces (Dyshkant 2010; docs/method.md, How a comparison runs):
// triangulate each (a raster on its own cells, measure/grid_mesh.h), locate
// each cloud in the other's mesh (walking in EMST order), interpolate, and
// integrate the gap d = F̂_B − F̂_A over the overlap Ω with weight μ. Ω is
// the intersection of the two surfaces' data domains
// (measure/domain.h: the triangles that are data, not filler across voids,
// nodata holes and concave outlines), or with DomainKind::kHull the paper's
// Conv(A) ∩ Conv(B):
//
//   ρd  = ∫∫_Ω |d| μ            volume between the surfaces (units³)
//   ρ'd = mean |d| over the sample nodes of A and B inside Ω (units): a
//         node of A counts when it is a corner of one of A's domain triangles
//         and lies in B's closed domain (inside, on an edge or at a corner
//         of one of B's domain triangles); likewise B's nodes
//   ρs  = 1 / ρd (1 when ρd = 0)
//
// B is brought into A's local frame (A's origin), so both are compared in
// one set of coordinates; results are in the data's units.
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "measure/domain.h"
#include "measure/mask_region.h"
#include "measure/surface.h"

namespace surfreg {

enum class VolumeMode {
  // Exact: ∫|d|μ on the common refinement of the two triangulations, where
  // both interpolants are linear on each cell (docs/method.md, default).
  kOverlay,
  // The paper's: the Delaunay triangulation of A ∪ B with each surface known
  // at every node (one given, one interpolated). Approximates ρd, since F̂_A
  // is not linear on the union's triangles. Over the data domain: the nodes
  // in Ω, and the union triangles whose centroid is in Ω.
  kUnion,
};

enum class WeightMode {
  kUniform,   // μ = 1
  kPerPoint,  // μ = the samples' weights, interpolated linearly on A's mesh
              // (B's if only B has weights); exact for the linear μ
  kMask,      // μ = 1 on the region of `mask` (see mask_mode), 0 elsewhere
};

// Where a Measure is (MeasureOptions::on_progress).
struct MeasureProgress {
  const char* stage = "";  // "triangulating", "data domains and spanning trees", ...
  double done = 0;         // share of a typical run's time spent before this stage, 0-1
  double seconds = 0;      // since the start of Measure
  int64_t points = 0;      // samples of both surfaces: how long the run will be
};

struct MeasureOptions {
  VolumeMode volume = VolumeMode::kOverlay;
  // Which triangles of each mesh are surface (measure/domain.h): the data
  // domain (default) or the whole convex hull (the paper's Ω). `grid` is
  // set per surface from Surface::raster_grid() (raster cells).
  DomainRule domain;
  WeightMode weight = WeightMode::kUniform;
  // For WeightMode::kMask: rings in input coordinates (not local), combined
  // by the even–odd rule (measure/mask_region.h: holes, several parts); one
  // ring is a plain polygon. kExclude takes the complement (within A).
  std::vector<MaskRing> mask;
  MaskMode mask_mode = MaskMode::kInclude;
  // An overlap smaller than this fraction of the smaller domain's area (the
  // convex hull's with kHull) is reported as an error (a sliver, or surfaces
  // that do not overlap):
  // the measures of a sliver rest on a handful of nodes and mean little.
  double min_overlap_fraction = 1e-4;
  // Threads for every stage (0: every core the process may use). The
  // results are the same bits for any count: work is cut into chunks by the
  // input's size alone and their sums added in order (measure/tasks.h).
  int threads = 0;
  // Change detection (terrain): also compute fill and cut counting only
  // where |d| > level_of_detection (L >= 0; at L = 0 the areas of gain and
  // loss). Overlay mode only.
  bool detect_change = false;
  double level_of_detection = 0.0;
  // Keep d at every sample of A (MeasureSummary::dz_a): the DoD on A's
  // nodes, e.g. on a reference raster's cells; and each node's share of
  // the overlap's area (MeasureSummary::node_area_a).
  bool keep_node_gaps = false;
  // One tile of a larger measure (terrain/tiled_measure.h): a surface with
  // an empty data domain, or an empty or sliver overlap, gives zero
  // measures instead of an InputError (the whole is judged, not the tile).
  bool allow_empty_overlap = false;
  // Two rasters sampling one grid are measured from their cells (closed
  // form per cell, no triangulation: measure/grid_pair.h), equal to the
  // general path to rounding; false takes the general path (comparisons).
  bool grid_shortcut = true;
  // Called at the start of each stage (from the calling thread), e.g. for a
  // progress line with an estimate of the time left.
  std::function<void(const MeasureProgress&)> on_progress;

  bool IsValid(std::string* error) const;
};

struct MeasureTimings {  // seconds, wall clock
  double triangulate = 0, domain = 0, spanning_tree = 0, locate = 0, interpolate = 0, volume = 0;
  double total = 0;
};

struct MeasureSummary {
  double rho_d = 0;          // ∫_Ω |d| μ, units³ (units² · μ)
  double rho_d_axial = 0;    // ρ'd: mean |d| at the nodes inside Ω, units
  double rho_s = 0;          // 1 / ρd, or 1 when ρd = 0
  double overlap_area = 0;   // |Ω|, units² (unweighted)
  double hull_area_a = 0, hull_area_b = 0;  // areas of the two meshes (convex hulls), units²
  // Areas of the two data domains (the hulls' with kHull), and what the
  // domains leave out of the hulls (hull area minus domain area), units².
  DomainKind domain_kind = DomainKind::kData;
  double domain_area_a = 0, domain_area_b = 0;
  double excluded_area_a = 0, excluded_area_b = 0;
  double weight_integral = 0;  // ∫_Ω μ (equals overlap_area for uniform μ)
  double mean_abs_dz = 0;    // ρd / ∫_Ω μ: mean vertical distance, units
  double signed_volume = 0;  // ∫_Ω (F̂_B − F̂_A) μ
  double volume_above = 0;   // ∫_Ω max(F̂_B − F̂_A, 0) μ: B above A ("fill")
  double volume_below = 0;   // ∫_Ω max(F̂_A − F̂_B, 0) μ: B below A ("cut")
  // With MeasureOptions::detect_change, beyond the level of detection L
  // (fill and cut equal volume_above and volume_below when L = 0):
  // fill ∫_{d>L} d μ, cut ∫_{d<−L} |d| μ, and the (weighted) areas where
  // change is detected. If every gap is known to ±L, each volume is known
  // to ± L times its area.
  double level_of_detection = 0;
  double fill_detected = 0, cut_detected = 0;
  double fill_area = 0, cut_area = 0;
  // d = F̂_B − F̂_A at each sample of A, in A's input order (NaN at the
  // nodes not in Ω, by the rule of ρ'd above);
  // filled only with MeasureOptions::keep_node_gaps.
  std::vector<double> dz_a;
  // The area each sample of A stands for, in A's input order (with
  // keep_node_gaps): a third of each of A's domain triangles whose three
  // corners are nodes in Ω (0 elsewhere, and at a repeated xy's other
  // samples). On a raster's cells away from Ω's outline it is the cell's
  // area exactly; its sum is |Ω| less the part along Ω's outline. The
  // cellwise change budgets (terrain/change_budget.h) weight dz_a by it.
  std::vector<double> node_area_a;
  // d at each sample of B, in B's input order (with keep_node_gaps): NaN
  // except at the nodes ρ'd counts for B, i.e. B's nodes in Ω that are not
  // also nodes of A (those are in dz_a). So every node of G1 ∪ G2 in Ω is
  // finite in exactly one of dz_a, dz_b (a tiled measure counts them so).
  std::vector<double> dz_b;
  int64_t n_points_a = 0, n_points_b = 0;          // input samples
  int64_t n_duplicates_a = 0, n_duplicates_b = 0;  // merged (heights averaged)
  int64_t n_overlap_nodes = 0;  // nodes of G1 ∪ G2 (as a set of xy) inside Ω
  int64_t n_cells = 0;          // overlay cells or union triangles inside Ω
  int64_t walk_steps = 0;       // triangles visited by all location walks
  VolumeMode volume_mode = VolumeMode::kOverlay;
  MeasureTimings timings;

  // A few lines for people: the measures in `units` (the data's length
  // unit: "m" for terrain in a metric frame), counts, timings.
  std::string BriefReport(const std::string& units = "units") const;
};

// Compares surface B with surface A. Throws InputError for invalid surfaces
// (see ValidateSurface), invalid options, a surface with an empty data
// domain, or an empty or sliver overlap.
MeasureSummary Measure(const Surface& a, const Surface& b,
                       const MeasureOptions& options = MeasureOptions());

// Surface A prepared once for several measures against it (an alignment's
// before and after): its spatial order, mesh, data domain and spanning
// tree, by options.domain. Keeps a reference to `a`, which must outlive it.
// Throws InputError as Measure does for A alone (an invalid surface or
// options; an empty data domain unless allow_empty_overlap).
struct SpanningTree;

// What a MeasureReference prepared of its surface, read-only and valid while
// it lives: in the surface's local frame, in Hilbert order (sorted index k
// is input index order[k]); merged duplicates share their mean height (and
// weight) and map to one vertex (mesh.vertex_of_input). For a caller that
// would otherwise triangulate the same surface again.
struct PreparedSurface {
  const std::vector<Point2>* xy = nullptr;
  const std::vector<double>* z = nullptr;
  const std::vector<double>* weight = nullptr;  // empty when the surface has none
  const std::vector<int32_t>* order = nullptr;
  const Triangulation* mesh = nullptr;  // with the raster's cells forced in, for a raster
  const SpanningTree* tree = nullptr;   // Euclidean MST over `mesh`
  const MeshDomain* domain = nullptr;   // by the options' rule
  double hull_area = 0;
};

class MeasureReference {
 public:
  MeasureReference(const Surface& a, const MeasureOptions& options);
  ~MeasureReference();
  MeasureReference(const MeasureReference&) = delete;
  MeasureReference& operator=(const MeasureReference&) = delete;

  const Surface& surface() const;
  PreparedSurface prepared() const;
  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// Measure(a.surface(), b, options), with A's preparation reused (the same
// summary; the timings then cover B's preparation only). options.domain
// must be the rule `a` was prepared with (std::invalid_argument if not).
MeasureSummary Measure(const MeasureReference& a, const Surface& b,
                       const MeasureOptions& options = MeasureOptions());

const char* VolumeModeName(VolumeMode mode);  // "overlay" | "union"
const char* WeightModeName(WeightMode mode);  // "uniform" | "per_point" | "mask"

}  // namespace surfreg
