#include "measure/dz_statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <vector>

namespace surfreg {
namespace {

constexpr int64_t kChunkItems = int64_t{1} << 15;
constexpr int kBins = 1024;

// The value of rank k (0-based) among data[0, n), all finite, lo and hi
// their minimum and maximum. Exact, and the same for any thread count:
// each round counts the values into kBins bins by chunks (the bin a
// monotone function of the value, so a lower bin never holds a larger
// value), keeps only the bin holding rank k, and goes on with its values;
// a few tens of thousands left are selected directly.
double KthSmallest(const double* data, int64_t n, int64_t k, double lo, double hi,
                   const Execution& execution) {
  std::vector<double> kept;
  for (;;) {
    if (lo == hi) return lo;
    // Halves: no overflow of hi − lo for values near the largest double.
    const double scale = kBins / (0.5 * hi - 0.5 * lo);
    if (n <= kChunkItems || !std::isfinite(scale)) {
      std::vector<double> rest(data, data + n);
      std::nth_element(rest.begin(), rest.begin() + k, rest.end());
      return rest[static_cast<std::size_t>(k)];
    }
    const auto bin_of = [lo, scale](double v) {
      return std::min<int64_t>(kBins - 1, static_cast<int64_t>((0.5 * v - 0.5 * lo) * scale));
    };
    const int chunks = ChunksFor(n, kChunkItems);
    std::vector<uint32_t> counts(static_cast<std::size_t>(chunks) * kBins, 0);
    ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
      uint32_t* count = &counts[static_cast<std::size_t>(c) * kBins];
      for (int64_t i = begin; i < end; ++i) ++count[bin_of(data[i])];
    });
    int64_t below = 0;  // values in the bins before `bin`
    int bin = 0;
    for (;; ++bin) {
      int64_t in_bin = 0;
      for (int c = 0; c < chunks; ++c) in_bin += counts[static_cast<std::size_t>(c) * kBins + bin];
      if (below + in_bin > k) break;
      below += in_bin;
    }
    // The bin's values, chunk after chunk, and their range.
    std::vector<int64_t> offset(static_cast<std::size_t>(chunks) + 1, 0);
    for (int c = 0; c < chunks; ++c)
      offset[c + 1] = offset[c] + counts[static_cast<std::size_t>(c) * kBins + bin];
    std::vector<double> next(static_cast<std::size_t>(offset[chunks]));
    std::vector<double> low(chunks, hi), high(chunks, lo);
    ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
      double* out = next.data() + offset[c];
      double least = hi, most = lo;  // locals: the chunks' slots share cache lines
      for (int64_t i = begin; i < end; ++i) {
        if (bin_of(data[i]) != bin) continue;
        *out++ = data[i];
        least = std::min(least, data[i]), most = std::max(most, data[i]);
      }
      low[c] = least, high[c] = most;
    });
    lo = *std::min_element(low.begin(), low.end());
    hi = *std::max_element(high.begin(), high.end());
    k -= below;
    kept.swap(next);
    data = kept.data();
    n = static_cast<int64_t>(kept.size());
  }
}

// The q-quantile (0..1) of the values, linear between order statistics (as
// of the sorted values); lo and hi their minimum and maximum.
double Quantile(const double* values, int64_t n, double q, double lo, double hi,
                const Execution& execution) {
  const double position = q * static_cast<double>(n - 1);
  const int64_t below = static_cast<int64_t>(std::floor(position));
  const int64_t above = std::min(below + 1, n - 1);
  const double t = position - static_cast<double>(below);
  const double low = KthSmallest(values, n, below, lo, hi, execution);
  if (t == 0.0 || above == below) return low;
  // The next rank's value is `low` again if more than `above` values are at
  // most `low`, else the least value above it: one pass, not a selection.
  const int chunks = ChunksFor(n, kChunkItems);
  std::vector<int64_t> at_most(chunks, 0);
  std::vector<double> least_above(chunks, std::numeric_limits<double>::infinity());
  ForEachChunk(execution, n, chunks, [&](int c, int64_t begin, int64_t end) {
    int64_t count = 0;
    double least = std::numeric_limits<double>::infinity();
    for (int64_t i = begin; i < end; ++i) {
      if (values[i] <= low) {
        ++count;
      } else {
        least = std::min(least, values[i]);
      }
    }
    at_most[c] = count, least_above[c] = least;
  });
  int64_t total = 0;
  for (int64_t count : at_most) total += count;
  const double high =
      total > above ? low : *std::min_element(least_above.begin(), least_above.end());
  return low + t * (high - low);
}

// Count, mean and sum of squared deviations of a chunk (Welford's update:
// no cancellation for large offsets), and the chunk's sum of squares and
// range; merged in chunk order (Chan et al.'s pairwise formula).
struct Moments {
  int64_t count = 0;
  double mean = 0, m2 = 0, squares = 0;
  double min = std::numeric_limits<double>::infinity(), max = -min;
  void Add(double v) {
    ++count;
    const double delta = v - mean;
    mean += delta / static_cast<double>(count);
    m2 += delta * (v - mean);
    squares += v * v;
    min = std::min(min, v), max = std::max(max, v);
  }
  void Merge(const Moments& o) {
    if (o.count == 0) return;
    const double total = static_cast<double>(count + o.count);
    const double delta = o.mean - mean;
    m2 += o.m2 + delta * delta * static_cast<double>(count) * static_cast<double>(o.count) / total;
    mean += delta * static_cast<double>(o.count) / total;
    count += o.count;
    squares += o.squares;
    min = std::min(min, o.min), max = std::max(max, o.max);
  }
};

}  // namespace

DzStatistics ComputeDzStatistics(const std::vector<double>& dz, const std::vector<bool>& keep,
                                 const Execution& execution) {
  // The finite kept values, in their order, by chunks.
  const int64_t size = static_cast<int64_t>(dz.size());
  const int chunks = ChunksFor(size, kChunkItems);
  const auto used = [&](int64_t i) {
    return (keep.empty() || keep[static_cast<std::size_t>(i)]) && std::isfinite(dz[i]);
  };
  std::vector<int64_t> offset(static_cast<std::size_t>(chunks) + 1, 0);
  std::vector<Moments> moments(chunks);
  ForEachChunk(execution, size, chunks, [&](int c, int64_t begin, int64_t end) {
    for (int64_t i = begin; i < end; ++i)
      if (used(i)) moments[c].Add(dz[i]);
  });
  for (int c = 0; c < chunks; ++c) offset[c + 1] = offset[c] + moments[c].count;
  // Buffers left uninitialized: each chunk's pages are first touched by the
  // chunk (a zero-fill would fault them all in on one thread).
  const int64_t used_count = offset[chunks];
  std::unique_ptr<double[]> values(new double[static_cast<std::size_t>(used_count)]);
  ForEachChunk(execution, size, chunks, [&](int c, int64_t begin, int64_t end) {
    double* out = values.get() + offset[c];
    for (int64_t i = begin; i < end; ++i)
      if (used(i)) *out++ = dz[i];
  });
  Moments all;
  for (const Moments& m : moments) all.Merge(m);

  DzStatistics s;
  s.count = all.count;
  if (used_count == 0) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    s.mean = s.median = s.nmad = s.stddev = s.rmse = s.le90 = s.min = s.max = nan;
    return s;
  }
  const double count = static_cast<double>(all.count);
  s.mean = all.mean;
  s.stddev = all.count > 1 ? std::sqrt(all.m2 / (count - 1.0)) : 0.0;
  s.rmse = std::sqrt(all.squares / count);
  s.min = all.min;
  s.max = all.max;
  s.median = Quantile(values.get(), used_count, 0.5, s.min, s.max, execution);
  // |dz|, then the deviations |dz − median|, into one buffer by chunks,
  // with their range.
  std::unique_ptr<double[]> derived(new double[static_cast<std::size_t>(used_count)]);
  const int value_chunks = ChunksFor(all.count, kChunkItems);
  const auto quantile_of = [&](const auto& f, double q) {
    std::vector<double> low(value_chunks), high(value_chunks);
    ForEachChunk(execution, all.count, value_chunks, [&](int c, int64_t begin, int64_t end) {
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (int64_t i = begin; i < end; ++i) {
        derived[i] = f(values[i]);
        lo = std::min(lo, derived[i]), hi = std::max(hi, derived[i]);
      }
      low[c] = lo, high[c] = hi;
    });
    return Quantile(derived.get(), used_count, q, *std::min_element(low.begin(), low.end()),
                    *std::max_element(high.begin(), high.end()), execution);
  };
  const double median = s.median;
  s.le90 = quantile_of([](double v) { return std::fabs(v); }, 0.9);
  s.nmad = 1.4826 * quantile_of([median](double v) { return std::fabs(v - median); }, 0.5);
  return s;
}

std::string DzStatisticsLine(const DzStatistics& s, const std::string& units) {
  char line[320];
  std::snprintf(line, sizeof line,
                "n %lld, mean %.4g, median %.4g, NMAD %.4g, std %.4g, RMSE %.4g, LE90 %.4g %s",
                static_cast<long long>(s.count), s.mean, s.median, s.nmad, s.stddev, s.rmse, s.le90,
                units.c_str());
  return line;
}

}  // namespace surfreg
