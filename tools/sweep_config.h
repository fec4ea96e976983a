#pragma once
// The config of `surfreg sweep` (docs/sweeps.md): surface pairs with an
// optional known motion, base solver settings, the settings to sweep (lists
// of values), the initial perturbations, the success thresholds, and the
// outputs. A commented example: configs/sweep_example.yaml.
//
//   pairs:                       # one or more
//     - name: volcano            # optional (default pair1, pair2, ...)
//       reference: a.xyz
//       moving: b.xyz
//       truth: {rotation_deg: [rx, ry, rz], translation: [tx, ty, tz]}
//       # or truth: {matrix: [[4 numbers] x 4]}, or truth: {file: t.json}
//   settings: {cost: axial, max_iterations: 30}   # any align key
//   sweep: {loss: [none, huber], levels: [1, 2]}  # align keys, lists of values
//   perturbations: {rotation_deg: [0, 2, 4], shift_spacings: [0, 2, 4],
//                   directions: 4, seed: 1}
//   success: {rotation_deg: 0.1, spacings: 0.5}
//   jobs: 2                      # parallel runs; default: the number of cores
//   output: out/sweep.csv        # the per-run CSV; the other outputs are named after it
//
// Settings and swept values are applied through tools/align_config.h
// (ApplyAlignFlag), so they are checked, and misspelt keys suggested,
// exactly as for `surfreg align`. The keys that name files written by
// align (output, aligned, log), the inputs (reference, moving), the initial
// motion (set by truth and perturbations), threads (runs are parallel, each
// single-threaded) and progress are not settings of a sweep.
//
// Error policy: InputError with one line "FILE:LINE: key 'a.b': what".
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tools/align_config.h"

namespace surfreg {

// A known motion of a pair: moving → reference, input coordinates.
struct SweepTruth {
  enum class Kind { kNone, kMatrix, kAboutCentroid };
  Kind kind = Kind::kNone;
  Eigen::Matrix4d matrix = Eigen::Matrix4d::Identity();  // kMatrix (also from a transform JSON)
  // kAboutCentroid: p ↦ R(ω)(p − c) + c + t, c the moving surface's centroid
  // (mean of its points), ω the rotation vector in degrees: the convention
  // of align's initial_rotation_deg / initial_translation.
  std::array<double, 3> rotation_deg{};
  std::array<double, 3> translation{};
};

// The 4×4 matrix of `truth` (identity for kNone) given the moving centroid.
Eigen::Matrix4d TruthMatrix(const SweepTruth& truth, const Eigen::Vector3d& moving_centroid);

struct SweepPair {
  std::string name;               // CSV column `pair`: letters, digits, '_', '-', '.'
  std::string reference, moving;  // surface files, relative to the current directory
  SweepTruth truth;
  std::string where;  // "FILE:LINE: key 'pairs[1]'"
};

// A swept align key and its values, as YAML text ("huber", "2", "[rx, ry]").
struct SweptKey {
  std::string key;
  std::vector<std::string> values;
  std::string where;  // "FILE:LINE: key 'sweep.loss'"
};

struct SweepConfig {
  std::string file;  // the config file ("" when parsed from text without one)
  std::vector<SweepPair> pairs;
  // The settings shared by every run (reference, moving unset); origin[key]
  // says where each was set.
  AlignConfig base;
  std::vector<SweptKey> swept;  // grid order: the first key varies slowest
  // Perturbation magnitudes, paired level by level (equal lengths after
  // parsing; a single value given for one list is repeated): rotation by
  // rotation_deg[i] degrees and shift by shift_spacings[i] mean sample
  // spacings of the reference.
  std::vector<double> rotation_deg = {0};
  std::vector<double> shift_spacings = {0};
  int directions = 1;  // random directions per magnitude
  uint64_t seed = 1;
  // A run succeeds when align says converged_improved and, if the pair has
  // a truth, its rotation error < success_rotation_deg and translation
  // error < success_spacings mean sample spacings.
  double success_rotation_deg = 0.1;
  double success_spacings = 0.5;
  int jobs = 0;                               // parallel runs; 0 = the number of cores
  std::string output;                         // the per-run CSV (required)
  std::string output_where = "key 'output'";  // "FILE:LINE: key 'output'", or the flag
};

// Parses `yaml_text` (`file` names it in messages). Throws InputError.
SweepConfig ParseSweepConfig(const std::string& yaml_text, const std::string& file);

// Reads and parses the file at `path`; read errors name "flag '--config'".
SweepConfig ReadSweepConfig(const std::string& path);

}  // namespace surfreg
