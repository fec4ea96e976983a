#pragma once
// Value parsers of align keys whose values are lists (free, classes,
// columns) and their YAML text, out of align_config.cc to keep the key
// table's file small. Internal to tools/; messages as config_value.h.
#include <array>
#include <string>
#include <vector>

#include "tools/config_value.h"

namespace surfreg {
namespace config_value {

// classes: LAS classifications 0-255; an empty list (or nothing) keeps all.
std::vector<int> Classes(const Value& v);

// columns: 3 or 4 non-empty names or positions >= 1; nothing = the default.
std::vector<std::string> Columns(const Value& v);

// "[a, b]", or "" for an empty list.
std::string ListText(const std::vector<int>& items);
std::string ListText(const std::vector<std::string>& items);

}  // namespace config_value
}  // namespace surfreg
