#include "tools/align_config_values.h"

#include <algorithm>

#include "registration/align.h"
#include "io/surface_reader_internal.h"

namespace surfreg {
namespace config_value {

std::vector<int> Classes(const Value& v) {
  if (v.kind == Value::kNull) return {};
  std::vector<int> classes;
  for (const std::string& item : Items(v)) {
    Value one = v;
    one.kind = Value::kScalar;
    one.text = item;
    classes.push_back(Integer(one, 0, 255));
  }
  return classes;
}

std::vector<std::string> Columns(const Value& v) {
  if (v.kind == Value::kNull) return {};
  const std::vector<std::string> items = Items(v);
  if (items.empty()) return {};
  if (items.size() != 3 && items.size() != 4) Reject(v);
  for (const std::string& item : items) {
    // A name is one header token: no blanks, separators or comment; a
    // number must be a position.
    unsigned long long position = 0;
    double number = 0;
    const bool is_position = io_internal::ParseCount(item, &position);
    if (item.empty() || item.find_first_of(" \t,;#[]") != std::string::npos ||
        (is_position && position == 0) ||
        (!is_position && io_internal::ParseNumber(item, &number) == io_internal::NumberStatus::kOk)) {
      Reject(v);
    }
  }
  return items;
}

std::string ListText(const std::vector<std::string>& items) {
  if (items.empty()) return "";
  std::string out;
  for (const std::string& item : items) out += (out.empty() ? "" : ", ") + item;
  return "[" + out + "]";
}

std::string ListText(const std::vector<int>& items) {
  std::vector<std::string> text;
  for (int item : items) text.push_back(std::to_string(item));
  return ListText(text);
}

}  // namespace config_value
}  // namespace surfreg
