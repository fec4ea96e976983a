#pragma once
// The transform JSON of `surfreg align` (docs/align.md): matrix (4x4 row-major,
// moving -> reference, input coordinates), rotation_vector, quaternion,
// euler_deg, translation, centre, stddev, before/after measures, iterations,
// termination, seconds, verdict, observability, the cost and free parameters,
// and the two input files. One object and a newline. Used by `align` (one
// pair) and by the batch and sweep commands (one file per pair).
#include <array>
#include <string>

#include <Eigen/Core>

#include "registration/align.h"
#include "tools/align_config.h"
#include "tools/json_writer.h"

namespace surfreg {

// `extra_members`: more members already in JSON form ("\"terrain\": {...}"),
// appended after the standard keys ("" = none).
std::string TransformJson(const AlignConfig& config, const AlignResult& result,
                          const std::string& extra_members = "");

// Its parts, for other documents with motions (series): rho_d, rho_d_axial,
// mean_abs_dz, overlap_area, overlap_fraction, n_overlap_nodes of a measure;
// {"rx": ..., "tz": ...} of standard deviations (radians, data units); the
// 6 × 6 covariance as rows, null where undefined.
JsonObject MeasuresJson(const MeasureSummary& s, double overlap_fraction);
JsonObject StddevJson(const std::array<double, 6>& stddev);
std::string CovarianceJson(const Eigen::Matrix<double, 6, 6>& c);

}  // namespace surfreg
