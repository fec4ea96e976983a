#include "measure/measure_keys.h"

#include <cmath>

namespace surfreg {
namespace {

using namespace config_value;

const Names<DomainKind> kDomains = {{"data", DomainKind::kData}, {"hull", DomainKind::kHull}};
const Names<VolumeMode> kVolumes = {{"overlay", VolumeMode::kOverlay}, {"union", VolumeMode::kUnion}};
const Names<WeightMode> kWeights = {{"uniform", WeightMode::kUniform}, {"per_point", WeightMode::kPerPoint}};

}  // namespace

const std::vector<DomainRuleEntry>& DomainRuleKeys() {
  static const std::vector<DomainRuleEntry> keys = {
      {{"domain", "one of data, hull",
        "where the surfaces are compared: data (each mesh without the triangles that bridge "
        "voids, nodata holes and concave outlines) or hull (the whole convex hulls)"},
       [](const Value& v, DomainRule* d) { d->kind = Choice(v, kDomains); },
       [](const DomainRule& d) { return NameOf(d.kind, kDomains); }},
      {{"domain_max_edge_spacings", "a number in [1, 100]",
        "data domain of scattered samples: a triangle whose longest edge is more local sample "
        "spacings than this bridges a gap"},
       [](const Value& v, DomainRule* d) { d->max_edge_spacings = Number(v, 1, 100); },
       [](const DomainRule& d) { return Text(d.max_edge_spacings); }},
      {{"domain_min_thinness", "a number in [0, 0.5]",
        "data domain of scattered samples: outline triangles thinner than this (height over "
        "longest edge, per longest edge) are peeled"},
       [](const Value& v, DomainRule* d) { d->min_boundary_thinness = Number(v, 0, 0.5); },
       [](const DomainRule& d) { return Text(d.min_boundary_thinness); }},
  };
  return keys;
}

const std::vector<MeasureOptionEntry>& MeasureOptionKeys() {
  static const std::vector<MeasureOptionEntry> keys = [] {
    std::vector<MeasureOptionEntry> all = {
        {{"volume", "one of overlay, union",
          "overlay: the exact volume on the two meshes' common refinement; union: the paper's, on the "
          "Delaunay triangulation of both samples"},
         [](const Value& v, MeasureOptions* o) { o->volume = Choice(v, kVolumes); },
         [](const MeasureOptions& o) { return NameOf(o.volume, kVolumes); }},
        {{"weights", "one of uniform, per_point",
          "mu: uniform, or the samples' weights (4th .xyz column, PLY 'weight'), interpolated on A's mesh"},
         [](const Value& v, MeasureOptions* o) { o->weight = Choice(v, kWeights); },
         [](const MeasureOptions& o) { return NameOf(o.weight, kWeights); }},
        {{"lod", "a number >= 0",
          "level of detection (data units): fill and cut count only where |dz| exceeds it"},
         [](const Value& v, MeasureOptions* o) {
           o->level_of_detection = Number(v, 0, HUGE_VAL);
           o->detect_change = true;
         },
         [](const MeasureOptions& o) { return Text(o.level_of_detection); }},
        {{"min_overlap_fraction", "a number in [0, 1]",
          "an overlap smaller than this share of the smaller domain is refused as a sliver"},
         [](const Value& v, MeasureOptions* o) { o->min_overlap_fraction = Number(v, 0, 1); },
         [](const MeasureOptions& o) { return Text(o.min_overlap_fraction); }},
        {{"threads", kThreadsType,
          "threads for the measure (default: every core); the results are the same bits for any number"},
         [](const Value& v, MeasureOptions* o) { o->threads = ThreadCount(v); },
         [](const MeasureOptions& o) { return ThreadText(o.threads); }},
    };
    for (const DomainRuleEntry& entry : DomainRuleKeys()) {
      all.push_back({entry.key, [&entry](const Value& v, MeasureOptions* o) { entry.set(v, &o->domain); },
                     [&entry](const MeasureOptions& o) { return entry.get(o.domain); }});
    }
    return all;
  }();
  return keys;
}

}  // namespace surfreg
