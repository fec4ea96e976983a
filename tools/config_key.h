#pragma once
// One key of a command's config (`align`, `jaw`): a row of its reference.

namespace surfreg {

struct ConfigKey {
  const char* name;
  const char* type;  // what a value looks like ("an integer >= 1"), for messages and docs
  const char* help;  // one line
};

}  // namespace surfreg
