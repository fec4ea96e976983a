#include "tools/transform_file.h"

#include <yaml-cpp/yaml.h>

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <vector>

#include "measure/input_error.h"
#include "io/surface_reader_internal.h"

namespace surfreg {
namespace {

// A number read from the file, with the line it is on (1-based).
struct Entry {
  double value = 0;
  int line = 0;
};

[[noreturn]] void Fail(const std::string& label, const std::string& path, int line,
                       const std::string& reason) {
  throw InputError(label + ": " + path + (line > 0 ? ":" + std::to_string(line) : "") + ": " +
                   reason);
}

// One token as a finite number, or an error naming its line.
Entry Parse(std::string_view token, int line, const std::string& label, const std::string& path) {
  Entry entry{0, line};
  if (io_internal::ParseNumber(token, &entry.value) != io_internal::NumberStatus::kOk) {
    Fail(label, path, line, io_internal::Quote(token) + " is not a number");
  }
  if (!std::isfinite(entry.value)) {
    Fail(label, path, line, io_internal::Quote(token) + " is not a finite number");
  }
  return entry;
}

std::vector<Entry> TextEntries(std::string_view text, const std::string& label,
                               const std::string& path) {
  std::vector<Entry> entries;
  int line = 0;
  while (!text.empty()) {
    const std::size_t end = std::min(text.find('\n'), text.size());
    const std::string_view content = io_internal::StripComment(text.substr(0, end));
    text.remove_prefix(std::min(end + 1, text.size()));
    ++line;
    std::size_t at = 0;
    while ((at = content.find_first_not_of(" \t\r,", at)) != std::string_view::npos) {
      const std::size_t stop = std::min(content.find_first_of(" \t\r,", at), content.size());
      entries.push_back(Parse(content.substr(at, stop - at), line, label, path));
      at = stop;
    }
  }
  return entries;
}

// The "matrix" member of a JSON object: 4 lists of 4 numbers, or 16 numbers.
std::vector<Entry> JsonEntries(const std::string& text, const std::string& label,
                               const std::string& path) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    Fail(label, path, e.mark.is_null() ? 0 : e.mark.line + 1, "not valid JSON: " + e.msg);
  }
  if (!root.IsMap() || !root["matrix"]) {
    Fail(label, path, 0, "a JSON transform needs a \"matrix\" member (as `surfreg align --output` writes)");
  }
  const YAML::Node matrix = root["matrix"];
  const int line = matrix.Mark().is_null() ? 0 : matrix.Mark().line + 1;
  const char* shape = "\"matrix\" must be 4 lists of 4 numbers (row-major)";
  if (!matrix.IsSequence()) Fail(label, path, line, shape);
  std::vector<Entry> entries;
  const auto add = [&](const YAML::Node& item) {
    if (!item.IsScalar()) Fail(label, path, line, shape);
    entries.push_back(Parse(item.Scalar(), item.Mark().is_null() ? line : item.Mark().line + 1,
                            label, path));
  };
  for (const YAML::Node& row : matrix) {
    if (row.IsSequence()) {
      if (row.size() != 4) Fail(label, path, line, shape);
      for (const YAML::Node& item : row) add(item);
    } else {
      add(row);
    }
  }
  return entries;
}

bool IsJson(const std::string& text) {
  std::string_view rest = text;
  while (!rest.empty()) {
    const std::size_t end = std::min(rest.find('\n'), rest.size());
    const std::string_view line = io_internal::StripComment(rest.substr(0, end));
    const std::size_t first = line.find_first_not_of(" \t\r");
    if (first != std::string_view::npos) return line[first] == '{';
    rest.remove_prefix(std::min(end + 1, rest.size()));
  }
  return false;
}

std::string Format(const char* format, double a, double b = 0, double c = 0, double d = 0) {
  char buffer[160];
  std::snprintf(buffer, sizeof(buffer), format, a, b, c, d);
  return buffer;
}

}  // namespace

std::string RigidMotionProblem(const Eigen::Matrix4d& m) {
  // Written by another tool, the last row may carry rounding: 1e-9 is none.
  if ((m.row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-9 ||
      !m.allFinite()) {
    return Format("not a rigid motion: the last row is %.17g %.17g %.17g %.17g, not 0 0 0 1",
                  m(3, 0), m(3, 1), m(3, 2), m(3, 3));
  }
  const Eigen::Matrix3d r = m.topLeftCorner<3, 3>();
  const double off = (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  if (!(off <= kRotationTolerance)) {
    // A scale, a shear, or numbers written with too few digits.
    return Format("not a rigid motion: the 3 x 3 part is not a rotation (R^T R differs from the "
                  "identity by up to %.3g, more than %.0e: a scale or shear?)",
                  off, kRotationTolerance);
  }
  if (r.determinant() < 0) {
    return "not a rigid motion: the 3 x 3 part is a reflection (determinant -1), not a rotation";
  }
  return "";
}

Eigen::Matrix4d ReadTransformFile(const std::string& path, const std::string& label) {
  std::string text;
  try {
    text = io_internal::ReadFile(path);
  } catch (const InputError& e) {
    throw InputError(label + ": " + e.what());
  }
  const std::vector<Entry> entries =
      IsJson(text) ? JsonEntries(text, label, path) : TextEntries(text, label, path);
  if (entries.size() != 16) {
    Fail(label, path, entries.size() > 16 ? entries[16].line : 0,
         std::to_string(entries.size()) +
             " numbers; a transform holds 16 (4 rows of 4, row-major, moving -> reference)");
  }
  Eigen::Matrix4d m;
  for (int k = 0; k < 16; ++k) m(k / 4, k % 4) = entries[k].value;
  const std::string problem = RigidMotionProblem(m);
  if (!problem.empty()) Fail(label, path, 0, problem);
  m.row(3) << 0, 0, 0, 1;
  return m;
}

std::string MatrixText(const Eigen::Matrix4d& m) {
  std::string text;
  for (int i = 0; i < 4; ++i) {
    text += Format("%.17g %.17g %.17g %.17g\n", m(i, 0), m(i, 1), m(i, 2), m(i, 3));
  }
  return text;
}

std::array<double, 16> RowMajor(const Eigen::Matrix4d& m) {
  std::array<double, 16> out{};
  for (int k = 0; k < 16; ++k) out[k] = m(k / 4, k % 4);
  return out;
}

std::string MatrixOneLine(const Eigen::Matrix4d& m) {
  std::string text;
  for (int k = 0; k < 16; ++k) text += (k ? " " : "") + Format("%.17g", m(k / 4, k % 4));
  return text;
}

}  // namespace surfreg
