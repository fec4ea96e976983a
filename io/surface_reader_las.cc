// LAS point clouds (ASPRS LAS 1.0-1.4, point data record formats 0-10).
//
// Every field is decoded byte by byte as little endian at its documented
// offset (no struct is laid over the bytes), and every offset and count from
// the file is checked against the file's size before it is used, so a
// malformed header gives one message naming the field and its byte offset,
// never a read past the end or an allocation larger than the file implies.
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>

#include "io/surface_reader_internal.h"

namespace surfreg::io_internal {
namespace {

// Offsets and sizes of the public header block (LAS 1.4 R15, Table 3).
constexpr std::size_t kHeaderSize12 = 227;  // LAS 1.0-1.2; 1.3 adds 8 bytes, 1.4 148
constexpr std::size_t kHeaderSize14 = 375;
constexpr std::size_t kVersionMajor = 24, kVersionMinor = 25;
constexpr std::size_t kHeaderSizeField = 94, kPointOffsetField = 96, kVlrCountField = 100;
constexpr std::size_t kFormatField = 104, kRecordLengthField = 105, kLegacyCountField = 107;
constexpr std::size_t kScaleField = 131, kOffsetField = 155;  // x, y, z doubles each
constexpr std::size_t kEvlrStartField = 235, kEvlrCountField = 243, kCountField = 247;
constexpr std::size_t kVlrHeaderSize = 54, kEvlrHeaderSize = 60;
// The smallest record of each point data record format (Tables 7-17).
constexpr std::array<uint16_t, 11> kMinRecordLength = {20, 28, 26, 34, 57, 63,
                                                       30, 36, 38, 59, 67};
constexpr uint16_t kWktRecord = 2112, kGeoKeyRecord = 34735;
constexpr uint16_t kProjectedCsKey = 3072, kGeographicTypeKey = 2048;
constexpr uint16_t kUserDefined = 32767;  // GeoTIFF: "not an EPSG code"

const char* const kAxis[] = {"x", "y", "z"};

uint64_t Le(std::string_view d, std::size_t at, int bytes) {
  uint64_t value = 0;
  for (int i = 0; i < bytes; ++i) {
    value |= static_cast<uint64_t>(static_cast<unsigned char>(d[at + i])) << (8 * i);
  }
  return value;
}
uint16_t U16(std::string_view d, std::size_t at) { return static_cast<uint16_t>(Le(d, at, 2)); }
uint32_t U32(std::string_view d, std::size_t at) { return static_cast<uint32_t>(Le(d, at, 4)); }
uint64_t U64(std::string_view d, std::size_t at) { return Le(d, at, 8); }
int32_t I32(std::string_view d, std::size_t at) {
  const uint32_t bits = U32(d, at);
  int32_t value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}
double F64(std::string_view d, std::size_t at) {
  const uint64_t bits = U64(d, at);
  double value;
  std::memcpy(&value, &bits, sizeof(value));
  return value;
}

std::string At(uint64_t offset) { return "byte " + std::to_string(offset); }

struct LasHeader {
  int major = 0, minor = 0;
  std::size_t header_size = 0;
  uint64_t point_offset = 0;
  uint32_t vlr_count = 0;
  int format = 0;
  uint16_t record_length = 0;
  uint64_t count = 0;
  std::array<double, 3> scale = {1, 1, 1}, offset = {0, 0, 0};
  uint64_t evlr_start = 0;
  uint32_t evlr_count = 0;
};

LasHeader ParseHeader(std::string_view d, const std::string& name) {
  if (d.size() < 4 || std::memcmp(d.data(), "LASF", 4) != 0) {
    Fail(name, 0, "not a LAS file (it does not start with 'LASF')");
  }
  if (d.size() < kHeaderSize12) {
    Fail(name, 0,
         "truncated LAS header: the file has " + std::to_string(d.size()) +
             " bytes, the header alone needs " + std::to_string(kHeaderSize12));
  }
  LasHeader h;
  h.major = static_cast<unsigned char>(d[kVersionMajor]);
  h.minor = static_cast<unsigned char>(d[kVersionMinor]);
  if (h.major != 1 || h.minor > 4) {
    Fail(name, 0,
         "LAS version " + std::to_string(h.major) + "." + std::to_string(h.minor) + " (" +
             At(kVersionMajor) + ") is not supported (1.0 to 1.4)");
  }
  h.header_size = U16(d, kHeaderSizeField);
  const std::size_t needed = h.minor >= 4 ? kHeaderSize14 : h.minor == 3 ? 235 : kHeaderSize12;
  if (h.header_size < needed) {
    Fail(name, 0,
         "header size " + std::to_string(h.header_size) + " (" + At(kHeaderSizeField) +
             ") is less than the " + std::to_string(needed) + " bytes of a LAS 1." +
             std::to_string(h.minor) + " header");
  }
  if (h.header_size > d.size()) {
    Fail(name, 0,
         "truncated LAS header: the header size (" + At(kHeaderSizeField) + ") is " +
             std::to_string(h.header_size) + " bytes, the file has " + std::to_string(d.size()));
  }
  h.point_offset = U32(d, kPointOffsetField);
  h.vlr_count = U32(d, kVlrCountField);
  const int format_byte = static_cast<unsigned char>(d[kFormatField]);
  // LASzip marks compressed points by setting bit 7 (and sometimes 6) of the format.
  if (format_byte & 0xC0) {
    Fail(name, 0,
         "the point data record format byte (" + At(kFormatField) + ") is " +
             std::to_string(format_byte) +
             ": the points are LAZ-compressed; decompress the file first, e.g. `laszip -i x.laz "
             "-o x.las` or `pdal translate x.laz x.las`");
  }
  h.format = format_byte;
  if (h.format >= static_cast<int>(kMinRecordLength.size())) {
    Fail(name, 0,
         "unknown point data record format " + std::to_string(h.format) + " (" +
             At(kFormatField) + "; LAS has formats 0 to 10)");
  }
  h.record_length = U16(d, kRecordLengthField);
  if (h.record_length < kMinRecordLength[h.format]) {
    Fail(name, 0,
         "point data record length " + std::to_string(h.record_length) + " (" +
             At(kRecordLengthField) + ") is less than the " +
             std::to_string(kMinRecordLength[h.format]) + " bytes point format " +
             std::to_string(h.format) + " needs");
  }
  h.count = U32(d, kLegacyCountField);
  if (h.minor >= 4) {
    // LAS 1.4: the 64-bit count is the count; the legacy one is 0 for
    // formats 6-10 and for more than 2^32-1 points. Some writers leave the
    // 64-bit field 0 and fill the legacy one only.
    const uint64_t count64 = U64(d, kCountField);
    if (count64 != 0) h.count = count64;
    h.evlr_start = U64(d, kEvlrStartField);
    h.evlr_count = U32(d, kEvlrCountField);
  }
  for (int k = 0; k < 3; ++k) {
    const std::size_t scale_at = kScaleField + 8 * k, offset_at = kOffsetField + 8 * k;
    h.scale[k] = F64(d, scale_at);
    h.offset[k] = F64(d, offset_at);
    const std::string scale = std::string(kAxis[k]) + " scale factor (" + At(scale_at) + ")";
    const std::string offset = std::string(kAxis[k]) + " offset (" + At(offset_at) + ")";
    if (!std::isfinite(h.scale[k])) Fail(name, 0, scale + " is not a finite number");
    if (h.scale[k] == 0) Fail(name, 0, scale + " is 0");
    if (!std::isfinite(h.offset[k])) Fail(name, 0, offset + " is not a finite number");
  }
  if (h.point_offset < h.header_size || h.point_offset > d.size()) {
    Fail(name, 0,
         "offset to point data " + std::to_string(h.point_offset) + " (" +
             At(kPointOffsetField) + ") is " +
             (h.point_offset < h.header_size ? "inside the " + std::to_string(h.header_size) +
                                                   "-byte header"
                                             : "past the end of the file (" +
                                                   std::to_string(d.size()) + " bytes)"));
  }
  // Divided, not multiplied: a huge count must not overflow into a small size.
  const uint64_t room = (d.size() - h.point_offset) / h.record_length;
  if (h.count > room) {
    Fail(name, 0,
         "the header declares " + std::to_string(h.count) + " points of " +
             std::to_string(h.record_length) + " bytes from " + At(h.point_offset) +
             ", but the file has " + std::to_string(d.size()) + " bytes: room for " +
             std::to_string(room) + " (truncated file, or a wrong count)");
  }
  return h;
}

// The CRS of one (extended) variable length record under "LASF_Projection";
// `wkt` and `epsg` are set when the record holds one.
void ReadProjectionRecord(std::string_view d, std::size_t header_at, std::size_t data_at,
                          uint64_t length, std::string* wkt, std::string* epsg) {
  const std::string_view user = d.substr(header_at + 2, 16);
  const std::string_view projection = "LASF_Projection";
  if (user.substr(0, projection.size()) != projection ||
      (user.size() > projection.size() && user[projection.size()] != '\0')) {
    return;
  }
  const uint16_t record = U16(d, header_at + 18);
  if (record == kWktRecord && wkt->empty()) {
    std::string_view text = d.substr(data_at, length);
    const std::size_t nul = text.find('\0');
    if (nul != std::string_view::npos) text = text.substr(0, nul);
    *wkt = std::string(text);
  } else if (record == kGeoKeyRecord && length >= 8) {
    // GeoKeyDirectory: a 4-short header whose 4th is the key count, then
    // 4 shorts per key: id, location (0: the value is inline), count, value.
    const uint64_t keys = U16(d, data_at + 6);
    std::string projected, geographic;
    for (uint64_t k = 0; k < keys && 8 + 8 * (k + 1) <= length; ++k) {
      const std::size_t at = data_at + 8 + 8 * k;
      const uint16_t id = U16(d, at), location = U16(d, at + 2), value = U16(d, at + 6);
      if (location != 0 || value == 0 || value >= kUserDefined) continue;
      if (id == kProjectedCsKey) projected = "EPSG:" + std::to_string(value);
      if (id == kGeographicTypeKey) geographic = "EPSG:" + std::to_string(value);
    }
    if (epsg->empty()) *epsg = projected.empty() ? geographic : projected;
  }
}

// The CRS of the file from its VLRs (and LAS 1.4 EVLRs): the OGC WKT
// record if there is one, else the EPSG code of the GeoTIFF keys; "" if none.
std::string ReadCrs(std::string_view d, const LasHeader& h, const std::string& name) {
  std::string wkt, epsg;
  std::size_t at = h.header_size;
  for (uint32_t i = 0; i < h.vlr_count; ++i) {
    if (h.point_offset - at < kVlrHeaderSize ||
        h.point_offset - at - kVlrHeaderSize < U16(d, at + 20)) {
      Fail(name, 0,
           "variable length record " + std::to_string(i + 1) + " of " +
               std::to_string(h.vlr_count) + " (" + At(at) +
               ") runs past the start of the point data (" + At(h.point_offset) + ")");
    }
    const uint16_t length = U16(d, at + 20);
    ReadProjectionRecord(d, at, at + kVlrHeaderSize, length, &wkt, &epsg);
    at += kVlrHeaderSize + length;
  }
  if (h.evlr_count > 0) {
    uint64_t e = h.evlr_start;
    for (uint32_t i = 0; i < h.evlr_count; ++i) {
      if (e > d.size() || d.size() - e < kEvlrHeaderSize ||
          d.size() - e - kEvlrHeaderSize < U64(d, static_cast<std::size_t>(e) + 20)) {
        Fail(name, 0,
             "extended variable length record " + std::to_string(i + 1) + " of " +
                 std::to_string(h.evlr_count) + " (" + At(e) + ", " + At(kEvlrStartField) +
                 ") runs past the end of the file (" + std::to_string(d.size()) + " bytes)");
      }
      const auto start = static_cast<std::size_t>(e);
      const uint64_t length = U64(d, start + 20);
      ReadProjectionRecord(d, start, start + kEvlrHeaderSize, length, &wkt, &epsg);
      e += kEvlrHeaderSize + length;
    }
  }
  return wkt.empty() ? epsg : wkt;
}

}  // namespace

Surface ParseLas(std::string_view d, const std::string& name, const ReadOptions& options,
                 std::string* crs) {
  const LasHeader h = ParseHeader(d, name);
  const std::string file_crs = ReadCrs(d, h, name);
  // Formats 0-5 keep the class in the low 5 bits of byte 15 (the others are
  // the synthetic, key-point and withheld flags); 6-10 give it byte 16 whole.
  const bool wide = h.format >= 6;
  const std::size_t class_at = wide ? 16 : 15;
  const unsigned class_mask = wide ? 0xFF : 0x1F;
  std::array<bool, 256> keep{};
  keep.fill(options.classes.empty());
  for (int c : options.classes) {
    if (c < 0 || c > 255) Fail(name, 0, "classification " + std::to_string(c) + " is not 0 to 255");
    keep[static_cast<std::size_t>(c)] = true;
  }
  const auto kept = [&](std::size_t record) {
    return keep[static_cast<unsigned char>(d[record + class_at]) & class_mask];
  };
  uint64_t n = h.count;
  if (!options.classes.empty()) {
    n = 0;
    for (uint64_t i = 0; i < h.count; ++i) n += kept(h.point_offset + i * h.record_length);
    if (n == 0) {
      std::string list;
      for (int c : options.classes) list += (list.empty() ? "" : ", ") + std::to_string(c);
      Fail(name, 0,
           "none of its " + std::to_string(h.count) + " points has classification " + list +
               " (key 'classes')");
    }
  }
  CheckPointCount(n, name, options);
  PointList list;
  list.points.reserve(static_cast<std::size_t>(n));
  for (uint64_t i = 0; i < h.count; ++i) {
    const auto record = static_cast<std::size_t>(h.point_offset + i * h.record_length);
    if (!kept(record)) continue;
    std::array<double, 3> p;
    for (int k = 0; k < 3; ++k) {
      p[k] = I32(d, record + 4 * k) * h.scale[k] + h.offset[k];
      if (!std::isfinite(p[k])) {
        Fail(name, 0,
             "point " + std::to_string(i + 1) + " (" + At(record) + "): " + kAxis[k] +
                 " is not finite after its scale and offset");
      }
    }
    list.points.push_back(p);
  }
  if (crs != nullptr) *crs = file_crs;
  return Finish(std::move(list), name, options);
}

}  // namespace surfreg::io_internal
