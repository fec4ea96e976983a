#pragma once
// The keys of MeasureOptions and of the data domain (docs/measure.md), each
// defined once: its documentation row, the field it sets, how it reads back.
// The Python module's measure() takes them as keywords; align's option
// table (registration/align_keys.h) lifts the domain keys into
// AlignOptions::domain. Values are parsed by measure/option_keys.h.
#include <string>
#include <vector>

#include "measure/domain.h"
#include "measure/measures.h"
#include "measure/option_keys.h"

namespace surfreg {

using DomainRuleEntry = config_value::Entry<DomainRule>;
using MeasureOptionEntry = config_value::Entry<MeasureOptions>;

// domain, domain_max_edge_spacings, domain_min_thinness.
const std::vector<DomainRuleEntry>& DomainRuleKeys();

// volume, weights (uniform | per_point), lod (a level of detection: change
// detection on), min_overlap_fraction, threads and the domain keys.
const std::vector<MeasureOptionEntry>& MeasureOptionKeys();

// Sets key `name` of `table` from `value` (value.where starts the messages);
// InputError for an unknown key, naming the nearest one.
template <typename Options>
void SetOption(const std::vector<config_value::Entry<Options>>& table, const std::string& name,
               config_value::Value value, Options* options) {
  std::vector<std::string> names;
  for (const auto& entry : table) {
    if (name == entry.key.name) {
      value.expected = entry.key.type;
      entry.set(value, options);
      return;
    }
    names.push_back(entry.key.name);
  }
  throw InputError(value.where + ": unknown key " + Quote(name) + UnknownKeyHint(name, names));
}

}  // namespace surfreg
