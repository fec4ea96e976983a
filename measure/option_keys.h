#pragma once
// The values of option keys, one mechanism for every settings table of the
// project (registration/align_keys.h: AlignOptions' keys; the CLI's config
// tables add the inputs and outputs): a key's documentation row, how a value
// from a YAML node, a flag's text or a Python keyword sets its field, and
// how it reads back as YAML text, with the same messages from every source
// ("t.yaml:3: key 'cost' expects one of axial, volume, got 'fast'").
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "measure/input_error.h"

namespace surfreg {

// One key of a settings table: a row of its reference.
struct ConfigKey {
  const char* name;
  const char* type;  // what a value looks like ("an integer >= 1"), for messages and docs
  const char* help;  // one line
};

// `token` in single quotes for a message: shortened, non-printables escaped,
// so that a binary file never produces a multi-line or huge message.
std::string Quote(std::string_view token);

enum class NumberStatus { kOk, kNotANumber, kOutOfRange };

// Parses the whole of `token` as a double (an optional leading '+' is
// allowed). "nan" and "inf" parse (kOk): callers check finiteness so they can
// say which value is bad.
NumberStatus ParseNumber(std::string_view token, double* value);

// The key among `keys` closest to `name` (edit distance, or one containing
// the other; '-' read as '_'), or "" when none is close.
std::string NearestKey(const std::string& name, const std::vector<std::string>& keys);

// What follows "unknown key 'x'": " (replaced by cost: axial_sparser)" for a
// key the product no longer has, else " (did you mean 'y'?)" with the
// nearest of `keys` (`prefix` before it: "--" for flags), else "".
std::string UnknownKeyHint(const std::string& name, const std::vector<std::string>& keys,
                           const std::string& prefix = "");

namespace config_value {

// One value to set, from a YAML node or a flag's text.
struct Value {
  enum Kind { kNull, kScalar, kList, kMapping };
  std::string where;     // start of messages: "t.yaml:3: key 'cost'"
  std::string expected;  // the key's type text
  Kind kind = kScalar;
  std::string text;                // kScalar
  std::vector<std::string> items;  // kList (every item a scalar)
  bool nested = false;             // kList with a non-scalar item
};

inline std::string Shown(const Value& v) {
  switch (v.kind) {
    case Value::kNull:
      return "nothing";
    case Value::kMapping:
      return "a mapping";
    case Value::kList: {
      if (v.nested) return "a nested list";
      std::string out = "[";
      for (std::size_t i = 0; i < v.items.size(); ++i) out += (i ? ", " : "") + v.items[i];
      return Quote(out + "]");
    }
    case Value::kScalar:
      break;
  }
  return Quote(v.text);
}

[[noreturn]] inline void Reject(const Value& v) {
  throw InputError(v.where + " expects " + v.expected + ", got " + Shown(v));
}

inline std::string Scalar(const Value& v) {
  if (v.kind != Value::kScalar) Reject(v);
  return v.text;
}

// List items from a YAML sequence, or from "a,b,c" / "[a, b, c]" text.
inline std::vector<std::string> Items(const Value& v) {
  if (v.kind == Value::kList && !v.nested) return v.items;
  std::string text = Scalar(v);
  if (text.size() >= 2 && text.front() == '[' && text.back() == ']') {
    text = text.substr(1, text.size() - 2);
  }
  std::vector<std::string> items;
  if (text.find_first_not_of(" \t") == std::string::npos) return items;  // "" or "[]"
  std::size_t start = 0;
  for (;;) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    std::string item = text.substr(start, comma - start);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    items.push_back(item);
    if (comma == text.size()) return items;
    start = comma + 1;
  }
}

inline double NumberOf(const Value& v, const std::string& text) {
  double value = 0;
  if (ParseNumber(text, &value) != NumberStatus::kOk ||
      !std::isfinite(value)) {
    Reject(v);
  }
  return value;
}

// A number in the interval lo..hi, `bounds` saying which ends are open:
// "[]", "[)", "(]" or "()".
inline double Number(const Value& v, double lo, double hi, const char* bounds = "[]") {
  const double value = NumberOf(v, Scalar(v));
  const bool above = bounds[0] == '(' ? value > lo : value >= lo;
  const bool below = bounds[1] == ')' ? value < hi : value <= hi;
  if (!above || !below) Reject(v);
  return value;
}

inline int Integer(const Value& v, int lo, int hi = std::numeric_limits<int>::max()) {
  const std::string text = Scalar(v);
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc() || end != text.data() + text.size() || value < lo ||
      value > hi) {
    Reject(v);
  }
  return value;
}

inline bool Boolean(const Value& v) {
  std::string text = Scalar(v);
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (text == "true" || text == "yes" || text == "on" || text == "1") return true;
  if (text == "false" || text == "no" || text == "off" || text == "0") return false;
  Reject(v);
}

// A file name; nothing (YAML null, or "" from a flag) means none, unless required.
inline std::string Path(const Value& v, bool required) {
  const std::string text = v.kind == Value::kNull ? "" : Scalar(v);
  if (text.empty() && required) Reject(v);
  return text;
}

inline std::array<double, 3> Vector3(const Value& v) {
  const std::vector<std::string> items = Items(v);
  if (items.size() != 3) Reject(v);
  std::array<double, 3> out;
  for (int k = 0; k < 3; ++k) out[k] = NumberOf(v, items[k]);
  return out;
}

template <typename Enum>
using Names = std::vector<std::pair<const char*, Enum>>;

template <typename Enum>
inline Enum Choice(const Value& v, const Names<Enum>& names) {
  const std::string text = Scalar(v);
  for (const auto& [name, value] : names) {
    if (text == name) return value;
  }
  Reject(v);
}

template <typename Enum>
inline std::string NameOf(Enum value, const Names<Enum>& names) {
  for (const auto& [name, candidate] : names) {
    if (candidate == value) return name;
  }
  return "?";
}

inline std::string Text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof(buffer), "%.15g", value + 0.0);  // hides deg↔rad rounding
  return buffer;
}

inline std::string Text(const std::array<double, 3>& v, double scale = 1.0) {
  return "[" + Text(v[0] * scale) + ", " + Text(v[1] * scale) + ", " + Text(v[2] * scale) + "]";
}

inline std::string Text(bool value) { return value ? "true" : "false"; }

// A thread count: an integer >= 1, or "all" (0: every core, measure/tasks.h).
constexpr const char* kThreadsType = "an integer >= 1, or all";
inline int ThreadCount(const Value& v, int hi = std::numeric_limits<int>::max()) {
  return v.kind == Value::kScalar && v.text == "all" ? 0 : Integer(v, 1, hi);
}
inline std::string ThreadText(int threads) { return threads == 0 ? "all" : std::to_string(threads); }

// One key of a command's config: its documentation row, how a value sets
// it, how it reads back as YAML text ("" for a file key naming no file).
template <typename Config>
struct Entry {
  ConfigKey key;
  std::function<void(const Value&, Config*)> set;
  std::function<std::string(const Config&)> get;
};

// Optimal string alignment distance (edits and adjacent transpositions).
inline std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      d[i][j] = std::min(
          {d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1)});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
      }
    }
  }
  return d[a.size()][b.size()];
}

}  // namespace config_value
}  // namespace surfreg
