#include "tools/face_orientation.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include "measure/input_error.h"
#include "io/surface_reader_internal.h"

namespace surfreg {

using io_internal::Quote;

void FaceOrientationFromString(const std::string& text, const std::string& where,
                               FaceFrameOptions* options) {
  if (text == "auto") {
    options->orientation = FaceOrientation::kPrincipalAxes;
    return;
  }
  if (text == "as_is") {
    options->orientation = FaceOrientation::kAsIs;
    return;
  }
  std::string body = text;
  if (body.size() >= 2 && body.front() == '[' && body.back() == ']') {
    body = body.substr(1, body.size() - 2);
  }
  std::array<double, 3> r{};
  int found = 0;
  std::size_t start = 0;
  bool ok = true;
  while (ok && start <= body.size()) {
    const std::size_t comma = std::min(body.find(',', start), body.size());
    std::string item = body.substr(start, comma - start);
    item.erase(0, item.find_first_not_of(" \t"));
    item.erase(item.find_last_not_of(" \t") + 1);
    double v = 0.0;
    ok = found < 3 && io_internal::ParseNumber(item, &v) == io_internal::NumberStatus::kOk &&
         std::isfinite(v);
    if (ok) r[found++] = v;
    start = comma + 1;
  }
  if (!ok || found != 3) {
    throw InputError(where +
                     ": expected auto, as_is or a rotation vector RX,RY,RZ in degrees, got " +
                     Quote(text));
  }
  options->orientation = FaceOrientation::kGiven;
  options->rotation_deg = r;
}

std::string FaceOrientationToString(const FaceFrameOptions& options) {
  if (options.orientation == FaceOrientation::kPrincipalAxes) return "auto";
  if (options.orientation == FaceOrientation::kAsIs) return "as_is";
  std::string out;
  for (int k = 0; k < 3; ++k) {
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.17g", options.rotation_deg[k]);
    out += (k ? "," : "") + std::string(buffer);
  }
  return out;
}

}  // namespace surfreg
