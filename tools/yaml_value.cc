// yaml-cpp glue shared by the config readers (tools/yaml_value.h).
#include "tools/yaml_value.h"

namespace surfreg::config_value {

Value FromYaml(const YAML::Node& node) {
  Value value;
  if (node.IsNull()) {
    value.kind = Value::kNull;
  } else if (node.IsScalar()) {
    value.text = node.Scalar();
  } else if (node.IsMap()) {
    value.kind = Value::kMapping;
  } else {
    value.kind = Value::kList;
    for (const YAML::Node& item : node) {
      if (item.IsScalar()) {
        value.items.push_back(item.Scalar());
      } else {
        value.nested = true;
      }
    }
  }
  return value;
}

std::string YamlAt(const std::string& file, const YAML::Mark& mark) {
  return file + (mark.is_null() ? "" : ":" + std::to_string(mark.line + 1)) + ": ";
}

}  // namespace surfreg::config_value
