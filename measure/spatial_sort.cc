#include "measure/spatial_sort.h"

#include <algorithm>
#include <cmath>

namespace surfreg {
namespace {

constexpr int kCurveOrder = 14;  // 16384 x 16384 cells; key fits in 28 bits
constexpr int kRoundBits = 4;    // up to 16 BRIO rounds in the top bits

uint64_t SplitMix64(uint64_t& state) {
  uint64_t z = (state += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// Sorts `items` by their upper 32 bits (the key), stable, least significant
// digit first: three passes of 11 bits (counts fit the L1 cache), all three
// histograms from one read.
void RadixSortByUpperHalf(std::vector<uint64_t>& items) {
  constexpr int kBits = 11, kBuckets = 1 << kBits, kPasses = 3;
  std::vector<std::size_t> count(kPasses * (kBuckets + 1), 0);
  for (uint64_t item : items) {
    for (int pass = 0; pass < kPasses; ++pass) {
      ++count[pass * (kBuckets + 1) + ((item >> (32 + kBits * pass)) & (kBuckets - 1)) + 1];
    }
  }
  std::vector<uint64_t> buffer(items.size());
  for (int pass = 0; pass < kPasses; ++pass) {
    std::size_t* c = &count[pass * (kBuckets + 1)];
    for (int b = 0; b < kBuckets; ++b) c[b + 1] += c[b];
    const int shift = 32 + kBits * pass;
    for (uint64_t item : items) buffer[c[(item >> shift) & (kBuckets - 1)]++] = item;
    items.swap(buffer);
  }
}

}  // namespace

namespace {

// The curve as a machine over levels, highest first: the state is the
// transformation (swap of x and y, complement of both) the levels above
// applied to the rest; a level's two bits, transformed, give its digit
// (3 rx) ^ ry and the next state. The table takes four levels in one step:
// entry (state, 4 bits of x, 4 bits of y) holds the 8 digit bits and the
// state after them.
constexpr int kSwap = 1, kComplement = 2;
constexpr int kTableLevels = 4;

struct HilbertTable {
  uint16_t entry[4 << (2 * kTableLevels)] = {};
};

constexpr HilbertTable MakeHilbertTable() {
  HilbertTable table;
  for (int start = 0; start < 4; ++start) {
    for (int xs = 0; xs < (1 << kTableLevels); ++xs) {
      for (int ys = 0; ys < (1 << kTableLevels); ++ys) {
        int state = start;
        int digits = 0;
        for (int level = kTableLevels - 1; level >= 0; --level) {
          int rx = (xs >> level) & 1, ry = (ys >> level) & 1;
          if (state & kComplement) rx ^= 1, ry ^= 1;
          if (state & kSwap) {
            const int t = rx;
            rx = ry;
            ry = t;
          }
          digits = (digits << 2) | ((3 * rx) ^ ry);
          if (ry == 0) state ^= kSwap | (rx == 1 ? kComplement : 0);
        }
        table.entry[(start << (2 * kTableLevels)) | (xs << kTableLevels) | ys] =
            static_cast<uint16_t>(digits | state << (2 * kTableLevels));
      }
    }
  }
  return table;
}

constexpr HilbertTable kHilbertTable = MakeHilbertTable();

}  // namespace

uint32_t HilbertIndex(uint32_t x, uint32_t y, int order) {
  // Padded to 16 levels: the levels below `order` only append digits.
  const int pad = 16 - order;
  x <<= pad;
  y <<= pad;
  uint32_t index = 0;
  uint32_t state = 0;
  for (int shift = 16 - kTableLevels; shift >= 0; shift -= kTableLevels) {
    const uint32_t xs = (x >> shift) & 0xF, ys = (y >> shift) & 0xF;
    const uint32_t e =
        kHilbertTable.entry[(state << (2 * kTableLevels)) | (xs << kTableLevels) | ys];
    index = (index << (2 * kTableLevels)) | (e & 0xFF);
    state = e >> (2 * kTableLevels);
  }
  return index >> (2 * pad);
}

std::vector<int32_t> SpatialOrder(const std::vector<Point2>& points, bool brio, uint64_t seed) {
  const std::size_t n = points.size();
  double min_x = INFINITY, min_y = INFINITY, max_x = -INFINITY, max_y = -INFINITY;
  for (const Point2& p : points) {
    min_x = std::min(min_x, p.x);
    max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y);
    max_y = std::max(max_y, p.y);
  }
  const double cells = static_cast<double>((1u << kCurveOrder) - 1);
  const double extent = std::max(max_x - min_x, max_y - min_y);
  const double scale = extent > 0.0 ? cells / extent : 0.0;

  // Rounds: last round ~n/2 points, the one before ~n/4, ..., first ~64.
  int rounds = 0;
  if (brio) {
    while (rounds + 1 < (1 << kRoundBits) && (n >> (rounds + 1)) >= 64) ++rounds;
  }
  uint64_t state = seed;
  std::vector<uint64_t> items(n);
  for (std::size_t i = 0; i < n; ++i) {
    const auto qx = static_cast<uint32_t>((points[i].x - min_x) * scale);
    const auto qy = static_cast<uint32_t>((points[i].y - min_y) * scale);
    uint32_t key = HilbertIndex(qx, qy, kCurveOrder);
    if (rounds > 0) {
      const uint64_t r = SplitMix64(state) | (1ULL << rounds);
      const auto round = static_cast<uint32_t>(rounds - __builtin_ctzll(r));
      key |= round << (2 * kCurveOrder);
    }
    items[i] = (static_cast<uint64_t>(key) << 32) | static_cast<uint32_t>(i);
  }
  RadixSortByUpperHalf(items);
  std::vector<int32_t> order(n);
  for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<int32_t>(items[i] & 0xFFFFFFFFu);
  return order;
}

}  // namespace surfreg
