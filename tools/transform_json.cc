#include "tools/transform_json.h"

#include <cmath>
#include <string>
#include <vector>

#include "tools/json_writer.h"
#include "tools/transform_file.h"

namespace surfreg {
namespace {

std::string Numbers(const double* values, int n) {
  std::vector<std::string> out;
  for (int k = 0; k < n; ++k) out.push_back(JsonNumber(values[k]));
  return JsonArray(out);
}

template <typename T, typename Write>
JsonObject PerParameter(const std::array<T, 6>& values, Write write) {
  JsonObject json;
  for (int k = 0; k < 6; ++k) write(&json, kParameterNames[k], values[k]);
  return json;
}

}  // namespace

JsonObject MeasuresJson(const MeasureSummary& s, double overlap_fraction) {
  JsonObject json;
  json.Number("rho_d", s.rho_d)
      .Number("rho_d_axial", s.rho_d_axial)
      .Number("mean_abs_dz", s.mean_abs_dz)
      .Number("overlap_area", s.overlap_area)
      .Number("overlap_fraction", overlap_fraction)
      .Int("n_overlap_nodes", s.n_overlap_nodes);
  return json;
}

JsonObject StddevJson(const std::array<double, 6>& stddev) {
  return PerParameter(stddev, [](JsonObject* j, const char* key, double v) { j->Number(key, v); });
}

// Rows rx, ry, rz, tx, ty, tz (radians, data units); null where undefined.
std::string CovarianceJson(const Eigen::Matrix<double, 6, 6>& c) {
  std::vector<std::string> rows;
  for (int i = 0; i < 6; ++i) {
    std::vector<std::string> row;
    for (int j = 0; j < 6; ++j) row.push_back(std::isfinite(c(i, j)) ? JsonNumber(c(i, j)) : "null");
    rows.push_back(JsonArray(row));
  }
  return JsonArray(rows);
}

std::string TransformJson(const AlignConfig& config, const AlignResult& r,
                          const std::string& extra_members) {
  std::vector<std::string> rows;
  for (int i = 0; i < 4; ++i) {
    const double row[4] = {r.matrix(i, 0), r.matrix(i, 1), r.matrix(i, 2), r.matrix(i, 3)};
    rows.push_back(Numbers(row, 4));
  }
  std::vector<std::string> free;
  for (int k = 0; k < 6; ++k) {
    if (config.options.free[k]) free.push_back(JsonString(kParameterNames[k]));
  }
  const auto number = [](JsonObject* j, const char* key, double v) { j->Number(key, v); };
  const auto boolean = [](JsonObject* j, const char* key, bool v) {
    j->Raw(key, v ? "true" : "false");
  };
  JsonObject json;
  json.Raw("matrix", JsonArray(rows))
      .String("pdal_matrix", MatrixOneLine(r.matrix))
      .Raw("rotation_vector", Numbers(r.rotation_vector.data(), 3))
      .Raw("quaternion", Numbers(r.quaternion.data(), 4))
      .Raw("euler_deg", Numbers(r.euler_deg.data(), 3))
      .Raw("translation", Numbers(r.translation.data(), 3))
      .Raw("centre", Numbers(r.centre.data(), 3))
      .Object("stddev", PerParameter(r.stddev, number))
      .String("stddev_source", r.stddev_source)
      .Raw("covariance", CovarianceJson(r.covariance))
      .Object("before", MeasuresJson(r.before, r.overlap_fraction_before))
      .Object("after", MeasuresJson(r.after, r.overlap_fraction_after))
      .Number("sampling_gap", r.sampling_gap)
      .Number("density_ratio", r.density_ratio)
      .String("chord_correction", r.chord_correction)
      .String("solve_cost", r.solve_cost)
      .Int("iterations", r.iterations)
      .String("termination", r.termination)
      .Fixed("seconds", r.seconds, 6)
      .String("verdict", VerdictName(r.verdict))
      .String("verdict_reason", r.verdict_reason)
      .Object("observability", PerParameter(r.observability, number))
      .Object("constrained", PerParameter(r.constrained, boolean))
      .Number("condition_number", r.condition_number)
      .Int("folded_triangles", r.folded_triangles)
      .Int("remeshes", r.remeshes)
      .String("cost", AlignConfigValue(config, "cost"))
      .Raw("free", JsonArray(free))
      .String("reference", config.reference)
      .String("moving", config.moving);
  if (r.stable.done) {
    const StableTerrain& st = r.stable;
    JsonObject stable;
    stable.String("mode", "auto")
        .Number("stable_share", st.stable_share)
        .Int("stable_samples", st.stable_samples)
        .Int("changed_samples", st.changed_samples)
        .Int("regions", st.regions)
        .Int("rounds", st.rounds)
        .Raw("settled", st.settled ? "true" : "false")
        .Number("centre", st.centre)
        .Number("noise_sigma", st.noise_sigma)
        .String("warning", st.warning);
    json.Object("stable", stable);
  } else {
    json.Object("stable", JsonObject().String("mode", "all"));
  }
  if (r.holdout.done) {
    const HoldoutCheck& h = r.holdout;
    JsonObject holdout;
    holdout.Number("fraction", h.fraction)
        .Int("samples", h.samples)
        .Object("before", DzStatisticsJson(h.before))
        .Object("after", DzStatisticsJson(h.after))
        .Number("robust_rmse_before", h.robust_before)
        .Number("robust_rmse_after", h.robust_after)
        .Raw("improved", h.improved ? "true" : "false");
    json.Object("holdout", holdout);
  }
  std::string text = json.str();
  if (!extra_members.empty()) text.insert(text.size() - 1, ", " + extra_members);
  return text + "\n";
}

}  // namespace surfreg
