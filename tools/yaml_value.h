#pragma once
// yaml-cpp glue shared by the config readers (align, jaw): a YAML node as a
// config_value::Value, and where a node is for messages. Only for .cc files
// of surfreg_tools (yaml-cpp is a private dependency).
#include <string>

#include <yaml-cpp/yaml.h>

#include "tools/config_value.h"

namespace surfreg::config_value {

// A scalar's text, a list of scalars (nested lists flagged), a mapping or null.
Value FromYaml(const YAML::Node& node);

// "t.yaml:3: ", or "t.yaml: " when yaml-cpp has no position.
std::string YamlAt(const std::string& file, const YAML::Mark& mark);

}  // namespace surfreg::config_value
