#include "measure/spatial_sort.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "measure/bucket_scatter.h"

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
// digit first: three passes of 11 bits (counts fit the L1 cache), each a
// chunked stable scatter, so the order is the same for any thread count.
void RadixSortByUpperHalf(std::vector<uint64_t>& items, const Execution& execution) {
  constexpr int kBits = 11, kBuckets = 1 << kBits, kPasses = 3;
  const int64_t n = static_cast<int64_t>(items.size());
  BucketSlots slots(ChunksFor(n, int64_t{1} << 16), kBuckets);
  std::vector<uint64_t> buffer(items.size());
  for (int pass = 0; pass < kPasses; ++pass) {
    const int shift = 32 + kBits * pass;
    const auto digit = [&](int64_t i) { return static_cast<int>((items[i] >> shift) & (kBuckets - 1)); };
    CountIntoBuckets(execution, n, slots, digit);
    ScatterIntoBuckets(execution, n, slots, digit, [&](int64_t i, int64_t at) { buffer[at] = items[i]; });
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

std::vector<int32_t> SpatialOrder(const std::vector<Point2>& points, bool brio, uint64_t seed,
                                  const Execution& execution) {
  const std::size_t n = points.size();
  const int64_t count = static_cast<int64_t>(n);
  const int chunks = ChunksFor(count, int64_t{1} << 16);
  struct Box {
    double min_x = INFINITY, min_y = INFINITY, max_x = -INFINITY, max_y = -INFINITY;
  };
  std::vector<Box> boxes(chunks);
  ForEachChunk(execution, count, chunks, [&](int c, int64_t first, int64_t last) {
    Box& box = boxes[c];
    for (int64_t i = first; i < last; ++i) {
      const Point2& p = points[i];
      box.min_x = std::min(box.min_x, p.x), box.max_x = std::max(box.max_x, p.x);
      box.min_y = std::min(box.min_y, p.y), box.max_y = std::max(box.max_y, p.y);
    }
  });
  Box all;
  for (const Box& box : boxes) {
    all.min_x = std::min(all.min_x, box.min_x), all.max_x = std::max(all.max_x, box.max_x);
    all.min_y = std::min(all.min_y, box.min_y), all.max_y = std::max(all.max_y, box.max_y);
  }
  const double min_x = all.min_x, min_y = all.min_y;
  const double cells = static_cast<double>((1u << kCurveOrder) - 1);
  const double extent = std::max(all.max_x - min_x, all.max_y - min_y);
  const double scale = extent > 0.0 ? cells / extent : 0.0;

  // Rounds: last round ~n/2 points, the one before ~n/4, ..., first ~64.
  int rounds = 0;
  if (brio) {
    while (rounds + 1 < (1 << kRoundBits) && (n >> (rounds + 1)) >= 64) ++rounds;
  }
  std::vector<uint64_t> items(n);
  ForEachChunk(execution, count, chunks, [&](int, int64_t first, int64_t last) {
    for (int64_t i = first; i < last; ++i) {
      const auto qx = static_cast<uint32_t>((points[i].x - min_x) * scale);
      const auto qy = static_cast<uint32_t>((points[i].y - min_y) * scale);
      uint32_t key = HilbertIndex(qx, qy, kCurveOrder);
      if (rounds > 0) {
        // SplitMix64 is a counter: point i's draw is the (i + 1)-th.
        uint64_t state = seed + static_cast<uint64_t>(i) * 0x9E3779B97F4A7C15ULL;
        const uint64_t r = SplitMix64(state) | (1ULL << rounds);
        const auto round = static_cast<uint32_t>(rounds - __builtin_ctzll(r));
        key |= round << (2 * kCurveOrder);
      }
      items[i] = (static_cast<uint64_t>(key) << 32) | static_cast<uint32_t>(i);
    }
  });
  RadixSortByUpperHalf(items, execution);
  std::vector<int32_t> order(n);
  ForEachChunk(execution, count, chunks, [&](int, int64_t first, int64_t last) {
    for (int64_t i = first; i < last; ++i) order[i] = static_cast<int32_t>(items[i] & 0xFFFFFFFFu);
  });
  return order;
}

}  // namespace surfreg
