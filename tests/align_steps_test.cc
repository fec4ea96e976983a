// The alignment's preparation (registration/align_steps.h): the reference
// side taken from the measures' preparation of the same surface must be the
// side PrepareReference builds, field by field, for every kind of surface
// the alignment takes: an irregular cloud with weights, a raster with a
// nodata hole, the convex-hull domain; and nothing with duplicate xy.
#include "registration/align_steps.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "measure/measures.h"
#include "measure/spanning_tree.h"
#include "registration/pair_state.h"
#include "testing/surface_pairs.h"

namespace surfreg {
namespace {

void ExpectSameSide(const ReferenceSide& shared, const ReferenceSide& own) {
  ASSERT_EQ(shared.xy.size(), own.xy.size());
  for (std::size_t v = 0; v < own.xy.size(); ++v) {
    EXPECT_EQ(shared.xy[v].x, own.xy[v].x) << v;
    EXPECT_EQ(shared.xy[v].y, own.xy[v].y) << v;
  }
  EXPECT_EQ(shared.z, own.z);
  EXPECT_EQ(shared.weight, own.weight);
  EXPECT_EQ(shared.mesh.triangles, own.mesh.triangles);
  EXPECT_EQ(shared.mesh.neighbors, own.mesh.neighbors);
  EXPECT_EQ(shared.tree.order, own.tree.order);
  EXPECT_EQ(shared.tree.parent, own.tree.parent);
  EXPECT_EQ(shared.hull_area, own.hull_area);
  EXPECT_EQ(shared.domain, own.domain);
  EXPECT_EQ(shared.domain_vertex, own.domain_vertex);
}

std::optional<ReferenceSide> SharedSide(const Surface& surface, const DomainRule& rule) {
  MeasureOptions options;
  options.domain = rule;
  const MeasureReference reference(surface, options);
  return align_steps::ReferenceSideOf(reference.prepared());
}

TEST(AlignStepsTest, ReferenceSideFromTheMeasurePreparationOfACloudWithWeights) {
  const auto points = testing::SampleUniform(testing::SmoothTerrain, 3000, 0, 100, 0, 100, 3);
  std::vector<double> weight(points.size());
  for (std::size_t i = 0; i < weight.size(); ++i)
    weight[i] = 0.5 + 0.001 * static_cast<double>(i % 997);
  const Surface surface = MakeSurface(points, weight, "cloud");
  for (DomainKind kind : {DomainKind::kData, DomainKind::kHull}) {
    DomainRule rule;
    rule.kind = kind;
    const std::optional<ReferenceSide> shared = SharedSide(surface, rule);
    ASSERT_TRUE(shared.has_value());
    ExpectSameSide(*shared, PrepareReference(surface, 1.0, rule));
  }
}

TEST(AlignStepsTest, ReferenceSideFromTheMeasurePreparationOfARasterWithAHole) {
  std::vector<std::array<double, 3>> points;
  std::vector<RasterCell> cells;
  for (int r = 0; r < 25; ++r) {
    for (int c = 0; c < 25; ++c) {
      if (r >= 8 && r < 12 && c >= 5 && c < 14) continue;  // nodata
      points.push_back({2.0 * c, 2.0 * r, testing::SmoothTerrain(2.0 * c, 2.0 * r)});
      cells.push_back({c, r});
    }
  }
  Surface raster = MakeSurface(points, {}, "dem.tif");
  raster.raster_cell = cells;
  const std::optional<ReferenceSide> shared = SharedSide(raster, DomainRule());
  ASSERT_TRUE(shared.has_value());
  const ReferenceSide own = PrepareReference(raster);
  ExpectSameSide(*shared, own);
  // The hole is outside the data domain (not bridged by hull triangles).
  int out = 0;
  for (uint8_t in : own.domain) out += in == 0;
  EXPECT_GT(out, 0);
}

TEST(AlignStepsTest, NoSharedReferenceSideWithDuplicateXy) {
  auto points = testing::SampleUniform(testing::SmoothTerrain, 500, 0, 100, 0, 100, 4);
  points.push_back({points[7][0], points[7][1], points[7][2] + 1.0});
  EXPECT_FALSE(SharedSide(MakeSurface(points, {}, "twice"), DomainRule()).has_value());
}

}  // namespace
}  // namespace surfreg
