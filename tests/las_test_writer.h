#pragma once
// A small LAS writer for the tests and the fuzz seeds: the header fields at
// their documented offsets, byte by byte little endian, so that the reader
// is checked against the format, not against itself. The bytes a record has
// beyond x, y, z and the classification are filled with a pattern, so a
// reader reading the wrong field gets wrong values.
#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace surfreg::las_test {

struct LasPoint {
  int32_t x = 0, y = 0, z = 0;  // scaled integers
  uint8_t classification = 0;   // formats 0-5: 0-31 (the writer adds flag bits above)
};

struct LasFile {
  int minor = 2;          // LAS 1.minor
  int format = 1;         // point data record format
  int record_length = 0;  // 0: the format's own; more: extra bytes per record
  std::array<double, 3> scale = {0.01, 0.01, 0.001};
  std::array<double, 3> offset = {500000, 4000000, 100};
  std::vector<LasPoint> points;
  std::string wkt;          // an OGC WKT VLR (record 2112) when not empty
  int projected_epsg = 0;   // a GeoKeyDirectory VLR (34735) with ProjectedCSTypeGeoKey
  int geographic_epsg = 0;  // ... and/or GeographicTypeGeoKey
  bool legacy_count = true;  // LAS 1.4: also fill the 32-bit count (formats 0-5 only)
  // Formats 0-5: the synthetic/key-point/withheld bits set on every other
  // point's classification byte (the reader must mask them off).
  bool flag_bits = true;
};

constexpr int kMinRecordLength[11] = {20, 28, 26, 34, 57, 63, 30, 36, 38, 59, 67};

inline void Put(std::string* out, std::size_t at, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) (*out)[at + i] = static_cast<char>((value >> (8 * i)) & 0xFF);
}

inline void PutDouble(std::string* out, std::size_t at, double value) {
  uint64_t bits;
  std::memcpy(&bits, &value, sizeof(bits));
  Put(out, at, bits, 8);
}

inline std::string Vlr(uint16_t record, const std::string& data) {
  std::string vlr(54, '\0');
  const char user[] = "LASF_Projection";
  std::memcpy(&vlr[2], user, sizeof(user) - 1);
  Put(&vlr, 18, record, 2);
  Put(&vlr, 20, data.size(), 2);
  return vlr + data;
}

inline std::string GeoKeys(int projected, int geographic) {
  // GTModelTypeGeoKey: 1 projected, 2 geographic.
  std::vector<std::array<uint16_t, 4>> keys = {{1024, 0, 1, uint16_t(projected ? 1 : 2)}};
  if (geographic) keys.push_back({2048, 0, 1, static_cast<uint16_t>(geographic)});
  if (projected) keys.push_back({3072, 0, 1, static_cast<uint16_t>(projected)});
  std::string data(8 + 8 * keys.size(), '\0');
  Put(&data, 0, 1, 2);
  Put(&data, 2, 1, 2);
  Put(&data, 6, keys.size(), 2);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    for (int i = 0; i < 4; ++i) Put(&data, 8 + 8 * k + 2 * i, keys[k][i], 2);
  }
  return data;
}

inline std::string WriteLas(const LasFile& f) {
  const std::size_t header_size = f.minor >= 4 ? 375 : f.minor == 3 ? 235 : 227;
  std::string vlrs;
  int vlr_count = 0;
  if (!f.wkt.empty()) {
    vlrs += Vlr(2112, f.wkt + '\0');
    ++vlr_count;
  }
  if (f.projected_epsg || f.geographic_epsg) {
    vlrs += Vlr(34735, GeoKeys(f.projected_epsg, f.geographic_epsg));
    ++vlr_count;
  }
  const int length = f.record_length > 0 ? f.record_length : kMinRecordLength[f.format];
  std::string out(header_size, '\0');
  std::memcpy(&out[0], "LASF", 4);
  out[24] = 1;
  out[25] = static_cast<char>(f.minor);
  const char software[] = "surfreg las_test_writer";
  std::memcpy(&out[58], software, sizeof(software) - 1);
  Put(&out, 94, header_size, 2);
  Put(&out, 96, header_size + vlrs.size(), 4);
  Put(&out, 100, vlr_count, 4);
  out[104] = static_cast<char>(f.format);
  Put(&out, 105, length, 2);
  const bool legacy = f.format < 6 && (f.minor < 4 || f.legacy_count);
  Put(&out, 107, legacy ? f.points.size() : 0, 4);
  for (int k = 0; k < 3; ++k) {
    PutDouble(&out, 131 + 8 * k, f.scale[k]);
    PutDouble(&out, 155 + 8 * k, f.offset[k]);
  }
  if (f.minor >= 4) Put(&out, 247, f.points.size(), 8);
  out += vlrs;
  for (std::size_t i = 0; i < f.points.size(); ++i) {
    std::string record(length, '\0');
    for (int b = 12; b < length; ++b) record[b] = static_cast<char>(0xA5 ^ (b * 7 + i));
    const LasPoint& p = f.points[i];
    Put(&record, 0, static_cast<uint32_t>(p.x), 4);
    Put(&record, 4, static_cast<uint32_t>(p.y), 4);
    Put(&record, 8, static_cast<uint32_t>(p.z), 4);
    if (f.format < 6) {
      record[15] = static_cast<char>(p.classification | (f.flag_bits && i % 2 ? 0xE0 : 0));
    } else {
      record[16] = static_cast<char>(p.classification);
    }
    out += record;
  }
  return out;
}

// n points on a slightly curved sheet, classes cycling through `classes`.
inline std::vector<LasPoint> Sheet(int n, const std::vector<uint8_t>& classes = {2}) {
  std::vector<LasPoint> points;
  for (int i = 0; i < n; ++i) {
    LasPoint p;
    p.x = (i % 7) * 137 - 400 + i;
    p.y = (i / 7) * 151 - 300;
    p.z = 1000 + (p.x * p.x) / 97 - p.y * 3 + i % 3;
    p.classification = classes[static_cast<std::size_t>(i) % classes.size()];
    points.push_back(p);
  }
  return points;
}

}  // namespace surfreg::las_test
