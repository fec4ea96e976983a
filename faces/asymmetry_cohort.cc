#include "faces/asymmetry_cohort.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "measure/input_error.h"

namespace surfreg {
namespace {

std::string Number(double value) {
  char text[40];
  std::snprintf(text, sizeof(text), "%.9g", value);
  return text;
}

std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

// Splits one CSV line (RFC 4180 quotes) into fields.
std::vector<std::string> SplitCsv(std::string_view line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        fields.back() += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else if (c != '\r') {
      fields.back() += c;
    }
  }
  return fields;
}

}  // namespace

std::vector<IndexValue> IndexValues(const AsymmetryIndices& indices) {
  std::vector<IndexValue> values;
  const auto add = [&](const RegionIndex& r) {
    values.push_back({r.name + "_rms", r.rms});
    values.push_back({r.name + "_mean_abs", r.mean_abs});
    values.push_back({r.name + "_mean", r.mean});
    values.push_back({r.name + "_max_abs", r.max_abs});
    values.push_back({r.name + "_area", r.area});
  };
  add(indices.whole);
  for (const RegionIndex& r : indices.regions) add(r);
  return values;
}

std::string IndexTableHeader(const AsymmetryIndices& indices) {
  std::string header = "file,points,angle_deg,noise_sigma";
  for (const IndexValue& v : IndexValues(indices)) header += "," + v.name;
  return header;
}

std::string IndexTableRow(const std::string& file, int64_t points, double angle_deg,
                          const AsymmetryIndices& indices) {
  std::string row = CsvField(file) + "," + std::to_string(points) + "," + Number(angle_deg) + "," +
                    Number(indices.noise_sigma);
  for (const IndexValue& v : IndexValues(indices)) row += "," + Number(v.value);
  return row;
}

AsymmetryNorms ParseAsymmetryNorms(const std::string& text, const std::string& source) {
  AsymmetryNorms norms;
  norms.source = source;
  std::vector<std::string> header;
  std::vector<int> numeric;  // field index of each numeric column
  std::vector<std::vector<double>> columns;
  std::size_t start = 0;
  int line_number = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string_view line(text.data() + start, end - start);
    start = end + 1;
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string_view::npos) continue;
    const std::vector<std::string> fields = SplitCsv(line);
    const std::string where = source + ":" + std::to_string(line_number) + ": ";
    if (header.empty()) {
      header = fields;
      for (std::size_t k = 0; k < header.size(); ++k) {
        if (header[k] == "file") continue;
        numeric.push_back(static_cast<int>(k));
        norms.names.push_back(header[k]);
      }
      columns.resize(numeric.size());
      continue;
    }
    if (fields.size() != header.size()) {
      throw InputError(where + "expected " + std::to_string(header.size()) +
                       " fields (as the header), got " + std::to_string(fields.size()));
    }
    for (std::size_t c = 0; c < numeric.size(); ++c) {
      const std::string& field = fields[numeric[c]];
      char* stop = nullptr;
      errno = 0;
      const double value = std::strtod(field.c_str(), &stop);
      if (field.empty() || stop == nullptr || *stop != '\0' || errno == ERANGE ||
          !std::isfinite(value)) {
        throw InputError(where + "column '" + norms.names[c] + "': expected a number, got '" +
                         field + "'");
      }
      columns[c].push_back(value);
    }
    ++norms.faces;
  }
  if (header.empty())
    throw InputError(source + ": empty (expected a header line and a row per face)");
  if (norms.faces < 2) {
    throw InputError(source + ": norms need at least 2 faces, the table holds " +
                     std::to_string(norms.faces));
  }
  for (const std::vector<double>& column : columns) {
    double mean = 0;
    for (double v : column) mean += v;
    mean /= static_cast<double>(column.size());
    double var = 0;
    for (double v : column) var += (v - mean) * (v - mean);
    norms.mean.push_back(mean);
    norms.sd.push_back(std::sqrt(var / static_cast<double>(column.size() - 1)));
  }
  return norms;
}

std::vector<ZScore> ZScores(const AsymmetryNorms& norms, const std::vector<IndexValue>& values) {
  std::vector<ZScore> scores;
  bool shared = false;
  for (const IndexValue& v : values) {
    for (std::size_t c = 0; c < norms.names.size(); ++c) {
      if (norms.names[c] != v.name) continue;
      shared = true;
      if (norms.sd[c] > 0)
        scores.push_back({v.name, v.value, (v.value - norms.mean[c]) / norms.sd[c]});
      break;
    }
  }
  if (!shared) {
    throw InputError(norms.source +
                     ": the norms hold none of this face's indices (expected columns such as " +
                     (values.empty() ? std::string("face_rms") : values.front().name) + ")");
  }
  return scores;
}

std::vector<IndexValue> IndexDifferences(const std::vector<IndexValue>& a,
                                         const std::vector<IndexValue>& b) {
  if (a.size() != b.size()) {
    throw InputError("repeatability: the two scans hold different regions (" +
                     std::to_string(a.size()) + " and " + std::to_string(b.size()) + " indices)");
  }
  std::vector<IndexValue> differences;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (a[k].name != b[k].name) {
      throw InputError("repeatability: the two scans hold different regions ('" + a[k].name +
                       "' and '" + b[k].name + "')");
    }
    differences.push_back({a[k].name, b[k].value - a[k].value});
  }
  return differences;
}

}  // namespace surfreg
