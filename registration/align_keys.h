#pragma once
// The keys of AlignOptions (docs/align.md, the key table): each key's
// documentation row, the field it sets and how it reads back, defined once
// here for every way a user sets an option: the CLI's config files and
// flags (which add the inputs and outputs, tools/align_config.cc) and the
// Python module's keywords. Values are parsed and checked with
// measure/option_keys.h, so every source gets the same messages.
#include <string>
#include <vector>

#include "measure/option_keys.h"
#include "registration/align_options.h"

namespace surfreg {

using AlignOptionEntry = config_value::Entry<AlignOptions>;

// Every option key, in the order of the documentation.
const std::vector<AlignOptionEntry>& AlignOptionKeys();

// The entry of `name`, or nullptr.
const AlignOptionEntry* FindAlignOption(const std::string& name);

// Sets option `name` from `value` (value.where starts the messages: "keyword
// 'cost'"); InputError for an unknown key (naming the nearest) or a bad value.
void SetAlignOption(const std::string& name, config_value::Value value, AlignOptions* options);

// `options`' value of `name` as YAML text ("axial", "100", "[0, 0, 0]").
std::string AlignOptionValue(const AlignOptions& options, const std::string& name);

}  // namespace surfreg
