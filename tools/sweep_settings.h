#pragma once
// What a sweep's partial file (RUNS.csv.partial) records of the settings it
// was written with, so that `sweep --resume` refuses to continue it with
// others: the base align settings (every key a sweep takes, swept keys
// aside: their values are columns of each row), the pairs' files and
// truths, and the success thresholds. The perturbation grid is checked row
// by row (SweepRunFields). The record is a block of comment lines before
// the CSV header:
//
//   # surfreg sweep setting: max_iterations=50
#include <map>
#include <string>

#include "tools/sweep_config.h"

namespace surfreg {

// name -> value, e.g. "max_iterations" -> "50", "pair moved" -> "a.xyz b.xyz ...".
std::map<std::string, std::string> SweepSettings(const SweepConfig& config);

// 16 hex digits identifying the sweep: a hash of SweepSettings, the swept
// keys and their values, and the perturbation grid. Every row carries it
// (column `sweep`), so that `merge` can refuse the shards of two sweeps.
std::string SweepFingerprint(const SweepConfig& config);

// The comment block for the partial file (each line ends with '\n').
std::string SweepSettingsComment(const SweepConfig& config);

// Splits `text` (a partial file) into its leading comment block, parsed
// into *recorded, and returns the rest (the CSV). A file without the block
// leaves *recorded empty.
std::string SplitSweepSettings(const std::string& text, std::map<std::string, std::string>* recorded);

// Throws InputError naming the first setting that differs between what
// `path` recorded and `config` ("max_iterations: 50 there, 10 now").
// Nothing is checked when nothing was recorded.
void CheckSweepSettings(const std::map<std::string, std::string>& recorded,
                        const SweepConfig& config, const std::string& path);

}  // namespace surfreg
