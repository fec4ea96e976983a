#include "io/las_writer.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "measure/input_error.h"
#include "io/atomic_file.h"
#include "io/surface_reader_internal.h"

namespace surfreg {
namespace {

// Public header fields (LAS 1.4 R15, Table 3; the same offsets since 1.0).
constexpr std::size_t kVersionMinor = 25, kHeaderSize = 94, kPointDataOffset = 96, kFormat = 104,
                      kRecordLength = 105, kLegacyCount = 107, kScale = 131, kOffset = 155, kBounds = 179,
                      kCount14 = 247;
constexpr std::size_t kHeader12Size = 227;
constexpr int kFormat0Length = 20;
// At most 2^30 steps across an axis: well inside int32 with any offset.
constexpr double kMaxSteps = 1073741824.0;

void Put(std::string* out, std::size_t at, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) (*out)[at + i] = static_cast<char>((value >> (8 * i)) & 0xFF);
}
void PutDouble(std::string* out, std::size_t at, double value) {
  uint64_t bits;
  std::memcpy(&bits, &value, sizeof(bits));
  Put(out, at, bits, 8);
}
uint64_t Get(std::string_view d, std::size_t at, int bytes) {
  uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(d[at + i]);
  return v;
}
double GetDouble(std::string_view d, std::size_t at) {
  const uint64_t bits = Get(d, at, 8);
  double value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

// The power of ten that spans [lo, hi] in at most kMaxSteps steps, and no
// finer than `finest` (0: no limit).
double ScaleFor(double lo, double hi, double finest) {
  const double extent = std::max(hi - lo, 1e-9 * std::max({1.0, std::fabs(lo), std::fabs(hi)}));
  double scale = std::pow(10.0, std::ceil(std::log10(extent / kMaxSteps)));
  return std::max(scale, finest);
}

struct Bounds {
  std::array<double, 3> lo{}, hi{};
  Bounds() {
    lo.fill(std::numeric_limits<double>::infinity());
    hi.fill(-std::numeric_limits<double>::infinity());
  }
  void Add(const std::array<double, 3>& p) {
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  }
};

void PutBounds(const Bounds& b, std::string* out) {
  for (int k = 0; k < 3; ++k) {
    PutDouble(out, kBounds + 16 * k, b.hi[k]);
    PutDouble(out, kBounds + 16 * k + 8, b.lo[k]);
  }
}

int32_t Quantize(double value, double offset, double scale) {
  return static_cast<int32_t>(std::llround((value - offset) / scale));
}

}  // namespace

bool IsLasPath(const std::string& path) { return io_internal::Extension(path) == ".las"; }

std::string SurfaceToLas(const Surface& surface, const std::string& label) {
  if (surface.size() > 0xFFFFFFFFull) {
    throw InputError(label + ": " + std::to_string(surface.size()) +
                     " points are more than a LAS 1.2 file can count (4294967295)");
  }
  Bounds bounds;
  for (std::size_t i = 0; i < surface.size(); ++i) {
    bounds.Add({surface.xy[i].x + surface.origin[0], surface.xy[i].y + surface.origin[1],
                surface.z[i] + surface.origin[2]});
  }
  if (surface.size() == 0) bounds.lo.fill(0.0), bounds.hi.fill(0.0);
  std::array<double, 3> scale{};
  for (int k = 0; k < 3; ++k) scale[k] = ScaleFor(bounds.lo[k], bounds.hi[k], 0.0);

  std::string out(kHeader12Size + surface.size() * kFormat0Length, '\0');
  std::memcpy(&out[0], "LASF", 4);
  out[24] = 1;
  out[kVersionMinor] = 2;
  const char software[] = "surfreg";
  std::memcpy(&out[26], software, sizeof(software) - 1);  // system identifier
  std::memcpy(&out[58], software, sizeof(software) - 1);  // generating software
  Put(&out, kHeaderSize, kHeader12Size, 2);
  Put(&out, kPointDataOffset, kHeader12Size, 4);
  out[kFormat] = 0;
  Put(&out, kRecordLength, kFormat0Length, 2);
  Put(&out, kLegacyCount, surface.size(), 4);
  Put(&out, 111, surface.size(), 4);  // all are first returns
  for (int k = 0; k < 3; ++k) {
    PutDouble(&out, kScale + 8 * k, scale[k]);
    PutDouble(&out, kOffset + 8 * k, bounds.lo[k]);
  }
  PutBounds(bounds, &out);
  for (std::size_t i = 0; i < surface.size(); ++i) {
    const std::size_t at = kHeader12Size + i * kFormat0Length;
    const double p[3] = {surface.xy[i].x + surface.origin[0], surface.xy[i].y + surface.origin[1],
                         surface.z[i] + surface.origin[2]};
    for (int k = 0; k < 3; ++k) {
      Put(&out, at + 4 * k, static_cast<uint32_t>(Quantize(p[k], bounds.lo[k], scale[k])), 4);
    }
    out[at + 14] = 0x09;  // return 1 of 1
  }
  return out;
}

std::string MovedLas(std::string_view las, const LasMotion& matrix, const std::string& name) {
  auto fail = [&name](const std::string& what) { throw InputError(name + ": " + what); };
  if (las.size() < kHeader12Size || las.substr(0, 4) != "LASF") fail("not a LAS file");
  const int minor = static_cast<unsigned char>(las[kVersionMinor]);
  const uint64_t data_at = Get(las, kPointDataOffset, 4);
  const uint64_t length = Get(las, kRecordLength, 2);
  uint64_t count = Get(las, kLegacyCount, 4);
  if (minor >= 4 && las.size() >= kCount14 + 8 && Get(las, kHeaderSize, 2) >= kCount14 + 8) {
    count = std::max(count, Get(las, kCount14, 8));
  }
  if (length < 12) fail("point record length " + std::to_string(length) + " (byte 105) is shorter than x, y, z");
  if (data_at > las.size() || count > (las.size() - data_at) / length) {
    fail(std::to_string(count) + " point records of " + std::to_string(length) +
         " bytes from byte " + std::to_string(data_at) + " do not fit the file's " +
         std::to_string(las.size()) + " bytes");
  }
  std::array<double, 3> scale{}, offset{};
  for (int k = 0; k < 3; ++k) {
    scale[k] = GetDouble(las, kScale + 8 * k);
    offset[k] = GetDouble(las, kOffset + 8 * k);
    if (!(scale[k] > 0) || !std::isfinite(scale[k]) || !std::isfinite(offset[k])) {
      fail("the scale or offset of axis " + std::to_string(k) + " (bytes 131-178) is not a finite number");
    }
  }
  // Moved about the old offsets: no large coordinate meets the rotation.
  auto rotate = [&matrix](const std::array<double, 3>& p) {
    std::array<double, 3> q{};
    for (int i = 0; i < 3; ++i) q[i] = matrix[4 * i] * p[0] + matrix[4 * i + 1] * p[1] + matrix[4 * i + 2] * p[2];
    return q;
  };
  std::array<double, 3> moved_o = rotate(offset);
  for (int i = 0; i < 3; ++i) moved_o[i] += matrix[4 * i + 3];
  std::vector<std::array<double, 3>> moved(count);
  Bounds bounds;
  for (uint64_t i = 0; i < count; ++i) {
    const std::size_t at = data_at + i * length;
    std::array<double, 3> local{};
    for (int k = 0; k < 3; ++k) {
      local[k] = static_cast<int32_t>(static_cast<uint32_t>(Get(las, at + 4 * k, 4))) * scale[k];
    }
    moved[i] = rotate(local);
    for (int k = 0; k < 3; ++k) moved[i][k] += moved_o[k];
    bounds.Add(moved[i]);
  }
  if (count == 0) bounds.lo = moved_o, bounds.hi = moved_o;
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(bounds.lo[k]) || !std::isfinite(bounds.hi[k])) fail("moved coordinates are not finite");
  }
  std::string out(las);
  for (int k = 0; k < 3; ++k) {
    scale[k] = ScaleFor(bounds.lo[k], bounds.hi[k], scale[k]);  // the file's own unless too fine
    PutDouble(&out, kScale + 8 * k, scale[k]);
    PutDouble(&out, kOffset + 8 * k, bounds.lo[k]);
  }
  PutBounds(bounds, &out);
  for (uint64_t i = 0; i < count; ++i) {
    const std::size_t at = data_at + i * length;
    for (int k = 0; k < 3; ++k) {
      Put(&out, at + 4 * k, static_cast<uint32_t>(Quantize(moved[i][k], bounds.lo[k], scale[k])), 4);
    }
  }
  return out;
}

void WriteMovedLas(const std::string& input, const LasMotion& matrix, const std::string& output,
                   const std::string& label) {
  const std::string bytes = io_internal::ReadFile(input);
  WriteFileAtomically(output, MovedLas(bytes, matrix, input), label);
}

}  // namespace surfreg
