#pragma once
// One mechanism for the config keys of every command that takes a YAML
// config and --KEY=VALUE flags (`align`, `jaw`; `sweep` sets `align`'s): a
// table of keys, each with its setter and getter, and the reading of YAML
// mappings, config files and flags over it, with the same messages for
// every command ("t.yaml:3: unknown key 'cots' (did you mean 'cost'?)").
// Internal to tools/.
#include <yaml-cpp/yaml.h>

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "measure/input_error.h"
#include "measure/option_keys.h"
#include "tools/config_value.h"
#include "io/surface_reader_internal.h"
#include "tools/yaml_value.h"

namespace surfreg {

namespace config_table {

// The keys of one command. Config has `origin` (key -> where it was last
// set) and `config_file`.
template <typename Config>
class Table {
 public:
  explicit Table(std::vector<config_value::Entry<Config>> entries) : entries_(std::move(entries)) {
    for (const auto& entry : entries_) keys_.push_back(entry.key), names_.push_back(entry.key.name);
  }

  const std::vector<ConfigKey>& keys() const { return keys_; }
  const std::vector<std::string>& names() const { return names_; }

  const config_value::Entry<Config>* Find(const std::string& name) const {
    for (const auto& entry : entries_) {
      if (name == entry.key.name) return &entry;
    }
    return nullptr;
  }

  // The known key closest to `name` (align_config.h NearestKey), or "".
  std::string Nearest(const std::string& name) const { return NearestKey(name, names_); }

  // "unknown key 'x' (did you mean 'y'?)", or the list of known keys.
  std::string UnknownKeyMessage(const std::string& name) const {
    const std::string hint = UnknownKeyHint(name, names_);
    if (!hint.empty()) return "unknown key " + io_internal::Quote(name) + hint;
    std::string known;
    for (const std::string& key : names_) known += (known.empty() ? "" : ", ") + key;
    return "unknown key " + io_internal::Quote(name) + " (known keys: " + known + ")";
  }

  // The value of `key` as YAML text; InputError for an unknown key.
  std::string Get(const Config& config, const std::string& key) const {
    const auto* entry = Find(key);
    if (entry == nullptr) throw InputError(UnknownKeyMessage(key));
    return entry->get(config);
  }

  // Sets `entry` from `value`; `where` starts its messages and is recorded
  // as where the key was set.
  void Apply(const config_value::Entry<Config>& entry, config_value::Value value, const std::string& where,
             Config* config) const {
    value.where = where;
    value.expected = entry.key.type;
    entry.set(value, config);
    config->origin[entry.key.name] = where;
  }

  // One setting as text (a flag's value: booleans "true"/"false", lists
  // "a,b" or "[a, b]"), set from `where` ("flag '--cost'").
  void Set(const std::string& key, const std::string& text, const std::string& where, Config* config) const {
    const auto* entry = Find(key);
    if (entry == nullptr) throw InputError(where + ": " + UnknownKeyMessage(key));
    config_value::Value value;
    value.text = text;
    Apply(*entry, value, where, config);
  }

  void ApplyFlag(const std::string& key, const std::string& text, Config* config) const {
    Set(key, text, "flag '--" + key + "'", config);
  }

  // The YAML mapping `yaml_text` (`file` names it in messages), in file
  // order: text that is not a mapping, unknown and repeated keys, and values
  // of the wrong type are refused.
  void ApplyYaml(const std::string& yaml_text, const std::string& file, Config* config) const {
    YAML::Node root;
    try {
      root = YAML::Load(yaml_text);
    } catch (const YAML::Exception& e) {
      throw InputError(config_value::YamlAt(file, e.mark) + "not valid YAML: " + e.msg);
    }
    if (!root.IsMap()) {
      throw InputError(file + ": expected a YAML mapping of 'key: value' lines, found " + KindName(root));
    }
    try {
      // Every unknown key in one message, before any value is read.
      std::string unknown;
      for (const auto& pair : root) {
        if (pair.first.IsScalar() && Find(pair.first.Scalar()) == nullptr) {
          unknown += (unknown.empty() ? "" : "; ") + config_value::YamlAt(file, pair.first.Mark()) +
                     UnknownKeyMessage(pair.first.Scalar());
        }
      }
      if (!unknown.empty()) throw InputError(unknown);
      std::map<std::string, int> seen;  // key -> line
      for (const auto& pair : root) {
        const std::string at = config_value::YamlAt(file, pair.first.Mark());
        if (!pair.first.IsScalar()) throw InputError(at + "expected a key name, found a list or mapping");
        const std::string name = pair.first.Scalar();
        const auto* entry = Find(name);
        const auto [previous, inserted] = seen.emplace(name, pair.first.Mark().line + 1);
        if (!inserted) {
          throw InputError(at + "key '" + name + "' given twice (also at line " +
                           std::to_string(previous->second) + ")");
        }
        Apply(*entry, config_value::FromYaml(pair.second), at + "key '" + name + "'", config);
      }
    } catch (const YAML::Exception& e) {  // not expected once parsed; kept one line all the same
      throw InputError(config_value::YamlAt(file, e.mark) + e.msg);
    }
  }

  // The config file at `path` (a file that cannot be read names the flag).
  void ApplyFile(const std::string& path, Config* config) const {
    std::string text;
    try {
      text = io_internal::ReadFile(path);
    } catch (const InputError& e) {
      throw InputError(std::string("flag '--config': ") + e.what());
    }
    config->config_file = path;
    ApplyYaml(text, path, config);
  }

 private:
  static const char* KindName(const YAML::Node& node) {
    if (node.IsSequence()) return "a list";
    if (node.IsScalar()) return "a single value";
    return "nothing (an empty file)";
  }

  std::vector<config_value::Entry<Config>> entries_;
  std::vector<ConfigKey> keys_;
  std::vector<std::string> names_;
};

}  // namespace config_table
}  // namespace surfreg
