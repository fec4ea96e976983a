#pragma once
// A stable counting scatter in chunks, for radix sorts and groupings: items
// go bucket after bucket and, within a bucket, in their input order, on any
// number of threads. Each chunk counts its items per bucket; the chunks'
// slots are laid out bucket-major, chunk-minor; each chunk then places its
// items from its own slots. Internal to the libraries.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "measure/tasks.h"

namespace surfreg {

struct BucketSlots {
  BucketSlots(int chunks_, int buckets_)
      : chunks(chunks_), buckets(buckets_),
        slot(static_cast<std::size_t>(chunks_) * static_cast<std::size_t>(buckets_)),
        start(static_cast<std::size_t>(buckets_) + 1) {}
  int chunks, buckets;
  std::vector<int64_t> slot;   // [c * buckets + b]: chunk c's count, then its next slot, in bucket b
  std::vector<int64_t> start;  // bucket b's first slot; start[buckets] is the number placed
};

// Counts each item i of [0, n) (cut into slots.chunks) into bucket
// bucket_of(i), which is in [0, buckets) or negative (the item is not
// placed), and lays out the slots. bucket_of may write what belongs to item
// i alone (it runs on any thread, once per item here).
template <typename BucketOf>
void CountIntoBuckets(const Execution& execution, int64_t n, BucketSlots& slots,
                      const BucketOf& bucket_of) {
  const int buckets = slots.buckets;
  ForEachChunk(execution, n, slots.chunks, [&](int c, int64_t begin, int64_t end) {
    int64_t* own = &slots.slot[static_cast<std::size_t>(c) * buckets];
    std::fill(own, own + buckets, int64_t{0});
    for (int64_t i = begin; i < end; ++i) {
      const int b = bucket_of(i);
      if (b >= 0) ++own[b];
    }
  });
  int64_t next = 0;
  for (int b = 0; b < buckets; ++b) {
    slots.start[b] = next;
    for (int c = 0; c < slots.chunks; ++c) {
      int64_t& slot = slots.slot[static_cast<std::size_t>(c) * buckets + b];
      const int64_t here = slot;
      slot = next;
      next += here;
    }
  }
  slots.start[buckets] = next;
}

// place(i, position) for each counted item, positions as laid out by
// CountIntoBuckets with the same n and (pure) bucket_of.
template <typename BucketOf, typename Place>
void ScatterIntoBuckets(const Execution& execution, int64_t n, BucketSlots& slots,
                        const BucketOf& bucket_of, const Place& place) {
  const int buckets = slots.buckets;
  ForEachChunk(execution, n, slots.chunks, [&](int c, int64_t begin, int64_t end) {
    int64_t* next = &slots.slot[static_cast<std::size_t>(c) * buckets];
    for (int64_t i = begin; i < end; ++i) {
      const int b = bucket_of(i);
      if (b >= 0) place(i, next[b]++);
    }
  });
}

}  // namespace surfreg
