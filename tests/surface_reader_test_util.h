#pragma once
// Helpers shared by the surface reader tests: run a reader on a string,
// capture its InputError, and get points back in input coordinates.
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <sstream>
#include <string>

#include "measure/input_error.h"
#include "io/surface_reader.h"

namespace surfreg::reader_test {

using Reader = Surface (*)(std::istream&, const std::string&, const ReadOptions&);

inline Surface Read(Reader reader, const std::string& text, const std::string& name,
                    const ReadOptions& options = {}) {
  std::istringstream in(text, std::ios::in | std::ios::binary);
  return reader(in, name, options);
}

// The InputError message of reading `text` ("" if it reads fine; any other
// exception type fails the test).
inline std::string ErrorOf(Reader reader, const std::string& text, const std::string& name) {
  try {
    Read(reader, text, name);
  } catch (const InputError& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "not an InputError: " << e.what();
    return e.what();
  }
  return "";
}

inline ::testing::AssertionResult Contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
}

// Point i in input coordinates (local + origin).
inline std::array<double, 3> InputPoint(const Surface& s, std::size_t i) {
  return {s.xy[i].x + s.origin[0], s.xy[i].y + s.origin[1], s.z[i] + s.origin[2]};
}

inline void ExpectPoint(const Surface& s, std::size_t i, double x, double y, double z) {
  const std::array<double, 3> p = InputPoint(s, i);
  EXPECT_EQ(p[0], x) << "point " << i;
  EXPECT_EQ(p[1], y) << "point " << i;
  EXPECT_EQ(p[2], z) << "point " << i;
}

// Little-endian bytes of binary PLY bodies, independent of the host order.
class ByteWriter {
 public:
  template <typename T>
  ByteWriter& Put(T value) {
    static_assert(sizeof(T) <= 8, "scalar types only");
    uint64_t bits = 0;
    if constexpr (sizeof(T) == 1) {
      uint8_t u;
      std::memcpy(&u, &value, 1);
      bits = u;
    } else if constexpr (sizeof(T) == 2) {
      uint16_t u;
      std::memcpy(&u, &value, 2);
      bits = u;
    } else if constexpr (sizeof(T) == 4) {
      uint32_t u;
      std::memcpy(&u, &value, 4);
      bits = u;
    } else {
      std::memcpy(&bits, &value, 8);
    }
    for (std::size_t i = 0; i < sizeof(T); ++i)
      bytes_ += static_cast<char>((bits >> (8 * i)) & 0xff);
    return *this;
  }
  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
};

}  // namespace surfreg::reader_test
