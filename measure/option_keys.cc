#include "measure/option_keys.h"

#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <utility>

namespace surfreg {

std::string Quote(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char hex[8];
      std::snprintf(hex, sizeof(hex), "\\x%02x", c);
      out += hex;
    }
  }
  if (token.size() > kMaxShown) out += "...";
  return out + "'";
}

NumberStatus ParseNumber(std::string_view token, double* value) {
  const char* first = token.data();
  const char* last = first + token.size();
  // from_chars rejects '+' but some writers emit it; "+-1" must stay an error.
  if (first != last && *first == '+' && last - first > 1 && first[1] != '-' && first[1] != '+') {
    ++first;
  }
  const auto [ptr, ec] = std::from_chars(first, last, *value);
  if (ptr != last || first == last) return NumberStatus::kNotANumber;
  if (ec == std::errc::result_out_of_range) {
    // Over- or underflow: strtod tells them apart; an underflow to zero or a
    // subnormal is a fine value, an overflow is not.
    const std::string copy(first, last);
    errno = 0;
    *value = std::strtod(copy.c_str(), nullptr);
    return std::isinf(*value) ? NumberStatus::kOutOfRange : NumberStatus::kOk;
  }
  return ec == std::errc() ? NumberStatus::kOk : NumberStatus::kNotANumber;
}

std::string NearestKey(const std::string& name, const std::vector<std::string>& keys) {
  std::string wanted = name;
  for (char& c : wanted) {
    c = c == '-' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  }
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, wanted.size() / 3) + 1, best_edits = 0;
  for (const std::string& key : keys) {
    const std::size_t edits = config_value::EditDistance(wanted, key);
    // "iterations" for "max_iterations": a part of a key is close enough.
    const bool part = wanted.size() >= 3 && (key.find(wanted) != std::string::npos ||
                                             wanted.find(key) != std::string::npos);
    const std::size_t distance = part ? std::min<std::size_t>(edits, 1) : edits;
    // Among equally close keys the fewest edits win: 'mask_mode' for
    // 'mask_mod', not 'mask', which is only a part of it.
    if (distance < best_distance || (distance == best_distance && !best.empty() && edits < best_edits)) {
      best = key;
      best_distance = distance;
      best_edits = edits;
    }
  }
  return best;
}

std::string UnknownKeyHint(const std::string& name, const std::vector<std::string>& keys,
                           const std::string& prefix) {
  // Keys folded into another: a config written for an earlier release
  // says what to write instead.
  static const std::pair<const char*, const char*> kRetired[] = {
      {"axial_nodes", "cost: axial_sparser for 'sparser', cost: axial for 'both'"},
      {"sparser_nodes_ratio", "cost: auto, which switches at 2.5, or cost: volume, which never does"},
  };
  for (const auto& [retired, instead] : kRetired) {
    if (name == retired) return std::string(" (replaced by ") + instead + ")";
  }
  const std::string nearest = NearestKey(name, keys);
  return nearest.empty() ? std::string() : " (did you mean '" + prefix + nearest + "'?)";
}

}  // namespace surfreg
