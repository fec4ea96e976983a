#include "io/surface_writer.h"

#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "io/las_writer.h"
#include "io/surface_reader_internal.h"

namespace surfreg {
namespace {

// Comments must stay on their own line in either format.
std::string OneLine(std::string text) {
  for (char& c : text) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  return text;
}

// Shortest text that reads back as the same double; plain decimals (no
// exponent) for the usual magnitudes, so that 500000 is not written 5e+05.
void AppendNumber(double value, std::string* out) {
  char buffer[64];
  value += 0.0;  // -0 -> 0
  const double magnitude = std::fabs(value);
  const bool plain = magnitude == 0 || (magnitude >= 1e-4 && magnitude < 1e15);
  const auto result =
      plain ? std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::fixed)
            : std::to_chars(buffer, buffer + sizeof(buffer), value);
  out->append(buffer, result.ptr);
}

std::array<double, 3> InputPoint(const Surface& s, std::size_t i) {
  return {s.xy[i].x + s.origin[0], s.xy[i].y + s.origin[1], s.z[i] + s.origin[2]};
}

bool LittleEndianHost() {
  const uint16_t probe = 1;
  unsigned char first;
  std::memcpy(&first, &probe, 1);
  return first == 1;
}

void AppendLittleEndian(double value, bool swap, std::string* out) {
  unsigned char bytes[sizeof(double)];
  std::memcpy(bytes, &value, sizeof(double));
  if (swap) {
    for (std::size_t k = 0; k < sizeof(double) / 2; ++k) {
      std::swap(bytes[k], bytes[sizeof(double) - 1 - k]);
    }
  }
  out->append(reinterpret_cast<const char*>(bytes), sizeof(double));
}

}  // namespace

bool IsWritableSurfacePath(const std::string& path) {
  const std::string ext = io_internal::Extension(path);
  return ext == ".xyz" || ext == ".txt" || ext == ".ply" || ext == ".las";
}

std::string SurfaceToXyz(const Surface& surface, const std::vector<std::string>& comments) {
  const bool weighted = !surface.weight.empty();
  std::string out;
  out.reserve(surface.size() * (weighted ? 80 : 60));
  for (const std::string& comment : comments) out += "# " + OneLine(comment) + "\n";
  for (std::size_t i = 0; i < surface.size(); ++i) {
    const std::array<double, 3> p = InputPoint(surface, i);
    for (int k = 0; k < 3; ++k) {
      if (k > 0) out += ' ';
      AppendNumber(p[k], &out);
    }
    if (weighted) {
      out += ' ';
      AppendNumber(surface.weight[i], &out);
    }
    out += '\n';
  }
  return out;
}

std::string SurfaceToPly(const Surface& surface, const std::vector<std::string>& comments) {
  const bool weighted = !surface.weight.empty();
  std::string out = "ply\nformat binary_little_endian 1.0\n";
  for (const std::string& comment : comments) out += "comment " + OneLine(comment) + "\n";
  out += "element vertex " + std::to_string(surface.size()) + "\n";
  out += "property double x\nproperty double y\nproperty double z\n";
  if (weighted) out += "property double weight\n";
  out += "end_header\n";
  const bool swap = !LittleEndianHost();
  out.reserve(out.size() + surface.size() * sizeof(double) * (weighted ? 4 : 3));
  for (std::size_t i = 0; i < surface.size(); ++i) {
    for (const double value : InputPoint(surface, i)) AppendLittleEndian(value, swap, &out);
    if (weighted) AppendLittleEndian(surface.weight[i], swap, &out);
  }
  return out;
}

void WriteSurface(const std::string& path, const Surface& surface, const std::string& label,
                  const std::vector<std::string>& comments) {
  const std::string ext = io_internal::Extension(path);
  if (!IsWritableSurfacePath(path)) {
    throw InputError(label + ": cannot write a surface as '" + path +
                     "': unknown extension (expected .xyz, .txt, .ply or .las)");
  }
  const std::string data = ext == ".ply"   ? SurfaceToPly(surface, comments)
                           : ext == ".las" ? SurfaceToLas(surface, label)
                                           : SurfaceToXyz(surface, comments);
  WriteFileAtomically(path, data, label);
}

}  // namespace surfreg
