#pragma once
// The --json output of the subcommands: one JSON object per run on stdout,
// keys in the order added, written as {"key": value, "key": value}.
//
// Numbers never come out as nan or inf (not JSON): a non-finite value is
// written as null.
#include <gflags/gflags_declare.h>

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "measure/dz_statistics.h"

DECLARE_bool(json);  // every subcommand: print one JSON object instead of text

namespace surfreg {

// `text` as a JSON string literal: quotes, backslashes and control
// characters escaped; other bytes (UTF-8, or a file name's own) unchanged.
std::string JsonString(const std::string& text);

// Full precision: 17 significant digits ("%.17g"), so the text reads back as
// the same double; -0 is written as 0; NaN and infinities as null.
std::string JsonNumber(double value);

// "%.<decimals>f" (e.g. timings in seconds); NaN and infinities as null.
std::string JsonFixed(double value, int decimals);

// [a, b, c] from values already in JSON form.
std::string JsonArray(const std::vector<std::string>& values);

// [a, b, c] of numbers, each as JsonNumber writes it.
std::string JsonNumbers(const std::vector<double>& values);

class JsonObject {
 public:
  // `json` is a value already in JSON form (a number, array, object, ...).
  JsonObject& Raw(const std::string& key, const std::string& json);
  JsonObject& String(const std::string& key, const std::string& value) {
    return Raw(key, JsonString(value));
  }
  JsonObject& Int(const std::string& key, int64_t value) { return Raw(key, std::to_string(value)); }
  JsonObject& Number(const std::string& key, double value) { return Raw(key, JsonNumber(value)); }
  JsonObject& Fixed(const std::string& key, double value, int decimals) {
    return Raw(key, JsonFixed(value, decimals));
  }
  JsonObject& Object(const std::string& key, const JsonObject& value) {
    return Raw(key, value.str());
  }

  std::string str() const { return "{" + body_ + "}"; }

 private:
  std::string body_;
};

// A 4 × 4 matrix as 4 rows of 4 numbers (row-major), full precision.
std::string JsonMatrix4(const Eigen::Matrix4d& m);

// count, mean, median, nmad, stddev, rmse, le90 of dz statistics.
JsonObject DzStatisticsJson(const DzStatistics& s);

}  // namespace surfreg
