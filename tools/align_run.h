#pragma once
// `surfreg align` (one pair) as a function: reading or taking the two
// surfaces, the alignment, the terrain analysis, the output files the
// settings ask for, and the transform JSON. The CLI (tools/run_align.cc)
// and the Python module (tools/python) both call it, so their results
// cannot drift apart.
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "registration/align.h"
#include "tools/align_config.h"
#include "tools/align_tiled.h"
#include "terrain/terrain.h"

namespace surfreg {

struct AlignRun {
  AlignConfig config;    // as run (a mask raster turns the weight to per_point)
  bool terrain = false;  // config.terrain.Active: change and dz statistics too
  TerrainInputs inputs;  // the two surfaces as aligned (in the metric frame if terrain)
  AlignResult result;
  TerrainReport report;  // when `terrain`
  std::string json;      // the transform JSON, newline-terminated (tools/transform_json.h)
  // With max_memory (tools/align_tiled.h): the sample and the whole pair
  // after the motion; `inputs` then holds no surfaces.
  std::optional<TiledAlignReport> tiled;
};

// Aligns config.moving onto config.reference with `config` (already through
// FinishAlignConfig); a `reference` or `moving` given is used instead of
// reading that file (config's name then only names it). Writes the
// files config names (output, aligned, log, terrain outputs) atomically.
// `on_iteration` (may be empty) sees every solver iteration. Bad input
// throws InputError.
AlignRun AlignSurfaces(AlignConfig config, std::optional<Surface> reference,
                       std::optional<Surface> moving,
                       const std::function<void(const AlignOptions::Iteration&)>& on_iteration);

// Turns config.initial_matrix (if any) into
// options->initial_reference_from_moving, taken in the coordinates Align
// gets the surfaces in (for terrain inputs, the metric frame).
void ApplyInitialTransform(const AlignConfig& config, AlignOptions* options);

// The per-iteration progress line of `align` ("align: level 1/3 start 0 ...").
std::string AlignProgressLine(const AlignOptions::Iteration& it, int levels);

}  // namespace surfreg
