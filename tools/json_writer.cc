#include "tools/json_writer.h"

#include <gflags/gflags.h>

#include <cmath>
#include <cstdio>

DEFINE_bool(json, false, "print one JSON object on stdout instead of text");

namespace surfreg {

std::string JsonString(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\u%04x", c);
      out += escaped;
    } else {
      out += c;  // UTF-8 passes through; other bytes are the file name's own
    }
  }
  return out + "\"";
}

std::string JsonNumber(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.17g", value + 0.0);  // + 0.0: -0 -> 0
  return buffer;
}

std::string JsonFixed(double value, int decimals) {
  if (!std::isfinite(value)) return "null";
  char buffer[400];  // %.Nf of 1e308 has 309 digits before the point
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

std::string JsonNumbers(const std::vector<double>& values) {
  std::vector<std::string> items;
  items.reserve(values.size());
  for (double v : values) items.push_back(JsonNumber(v));
  return JsonArray(items);
}

std::string JsonArray(const std::vector<std::string>& values) {
  std::string out = "[";
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i > 0) out += ", ";
    out += values[i];
  }
  return out + "]";
}

JsonObject& JsonObject::Raw(const std::string& key, const std::string& json) {
  if (!body_.empty()) body_ += ", ";
  body_ += JsonString(key) + ": " + json;
  return *this;
}

std::string JsonMatrix4(const Eigen::Matrix4d& m) {
  std::vector<std::string> rows;
  for (int i = 0; i < 4; ++i) {
    rows.push_back(JsonArray({JsonNumber(m(i, 0)), JsonNumber(m(i, 1)), JsonNumber(m(i, 2)), JsonNumber(m(i, 3))}));
  }
  return JsonArray(rows);
}

JsonObject DzStatisticsJson(const DzStatistics& s) {
  JsonObject json;
  json.Int("count", s.count)
      .Number("mean", s.mean)
      .Number("median", s.median)
      .Number("nmad", s.nmad)
      .Number("stddev", s.stddev)
      .Number("rmse", s.rmse)
      .Number("le90", s.le90);
  return json;
}

}  // namespace surfreg
