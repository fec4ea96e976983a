#pragma once
// Asymmetry indices across faces (docs/faces.md, "A cohort and its norms"):
// the indices of faces/asymmetry_index.h as one table row per face, the
// norms of a cohort (each index's mean and standard deviation over the
// faces of such a table), a face's z-scores against them, and the
// differences between two scans of one face (test–retest repeatability).
//
// Columns are named <region>_<statistic>: region `face` (the whole overlap),
// the standard regions and the user's, statistic rms, mean_abs, mean,
// max_abs or area (units, units² for area); a table also holds `file`,
// `points`, `angle_deg` (the refined plane against x = 0) and `noise_sigma`.
#include <string>
#include <vector>

#include "faces/asymmetry_index.h"

namespace surfreg {

struct IndexValue {
  std::string name;  // e.g. "lower_third_rms"
  double value = 0;
};

// The indices' columns, in order: for each region (face first), rms,
// mean_abs, mean, max_abs, area.
std::vector<IndexValue> IndexValues(const AsymmetryIndices& indices);

// The table's header line (no newline): file, points, angle_deg,
// noise_sigma, then IndexValues' names.
std::string IndexTableHeader(const AsymmetryIndices& indices);
// One row: `file` (quoted if it holds a comma or a quote), then the values
// (%.9g).
std::string IndexTableRow(const std::string& file, int64_t points, double angle_deg,
                          const AsymmetryIndices& indices);

struct AsymmetryNorms {
  std::string source;              // the table's file name, for messages
  int faces = 0;                   // rows
  std::vector<std::string> names;  // the numeric columns, in the table's order
  std::vector<double> mean, sd;    // per column (sd: sample, n − 1)
};

// Norms from a table's text (as IndexTableHeader/IndexTableRow write it, or
// any CSV with a header and a `file` column: every other column must be
// numeric). Throws InputError "<source>:<line>: ..." for a row of the wrong
// width or a value that is not a number, "<source>: ..." for fewer than 2
// rows or no header.
AsymmetryNorms ParseAsymmetryNorms(const std::string& text, const std::string& source);

struct ZScore {
  std::string name;
  double value = 0, z = 0;  // z = (value − mean) / sd
};

// The z-score of every index of `values` that the norms hold with sd > 0
// (indices they lack, or with sd = 0, are left out). Throws InputError
// naming the norms' source when they share no index with `values` (a table
// of other regions).
std::vector<ZScore> ZScores(const AsymmetryNorms& norms, const std::vector<IndexValue>& values);

// Test–retest: b − a for every index of a (same order), by name. Throws
// InputError when the two do not hold the same indices (other regions).
std::vector<IndexValue> IndexDifferences(const std::vector<IndexValue>& a,
                                         const std::vector<IndexValue>& b);

}  // namespace surfreg
