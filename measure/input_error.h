#pragma once
// The one error type for bad input a user can fix (unreadable file, a line
// that does not parse, too few points, ...). The CLI catches it and exits 2;
// internal invariants use CHECK instead.
#include <stdexcept>
#include <string>

namespace surfreg {

class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace surfreg
