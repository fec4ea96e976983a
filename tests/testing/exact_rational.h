#pragma once
// Exact arithmetic on doubles for test oracles, independent of
// measure/predicates: every finite double is a dyadic rational m * 2^e with
// an integer m, so sums, differences and products of doubles are dyadic
// rationals too and can be held exactly as a big integer times a power of
// two. Slow (heap-allocated limbs, schoolbook multiplication) and simple on
// purpose: the point is to be obviously right, not fast.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "measure/surface.h"

namespace surfreg::testing {

// Sign-magnitude arbitrary-precision integer, base 2^32 limbs, little endian.
class BigInt {
 public:
  BigInt() = default;
  static BigInt FromInt64(int64_t v) {
    BigInt r;
    r.neg_ = v < 0;
    // Magnitude without overflowing on INT64_MIN.
    uint64_t m = v < 0 ? uint64_t{0} - static_cast<uint64_t>(v) : static_cast<uint64_t>(v);
    while (m != 0) {
      r.mag_.push_back(static_cast<uint32_t>(m & 0xFFFFFFFFu));
      m >>= 32;
    }
    r.Trim();
    return r;
  }

  int Sign() const { return mag_.empty() ? 0 : (neg_ ? -1 : 1); }
  bool IsZero() const { return mag_.empty(); }

  BigInt operator-() const {
    BigInt r = *this;
    if (!r.mag_.empty()) r.neg_ = !r.neg_;
    return r;
  }

  BigInt operator+(const BigInt& o) const {
    if (neg_ == o.neg_) {
      BigInt r;
      r.mag_ = AddMag(mag_, o.mag_);
      r.neg_ = neg_;
      r.Trim();
      return r;
    }
    // Different signs: subtract the smaller magnitude from the larger.
    const int c = CompareMag(mag_, o.mag_);
    if (c == 0) return BigInt();
    BigInt r;
    if (c > 0) {
      r.mag_ = SubMag(mag_, o.mag_);
      r.neg_ = neg_;
    } else {
      r.mag_ = SubMag(o.mag_, mag_);
      r.neg_ = o.neg_;
    }
    r.Trim();
    return r;
  }
  BigInt operator-(const BigInt& o) const { return *this + (-o); }

  BigInt operator*(const BigInt& o) const {
    if (mag_.empty() || o.mag_.empty()) return BigInt();
    BigInt r;
    r.mag_.assign(mag_.size() + o.mag_.size(), 0u);
    for (std::size_t i = 0; i < mag_.size(); ++i) {
      uint64_t carry = 0;
      for (std::size_t j = 0; j < o.mag_.size(); ++j) {
        const uint64_t cur = static_cast<uint64_t>(mag_[i]) * o.mag_[j] + r.mag_[i + j] + carry;
        r.mag_[i + j] = static_cast<uint32_t>(cur & 0xFFFFFFFFu);
        carry = cur >> 32;
      }
      std::size_t k = i + o.mag_.size();
      while (carry != 0) {
        const uint64_t cur = static_cast<uint64_t>(r.mag_[k]) + carry;
        r.mag_[k] = static_cast<uint32_t>(cur & 0xFFFFFFFFu);
        carry = cur >> 32;
        ++k;
      }
    }
    r.neg_ = neg_ != o.neg_;
    r.Trim();
    return r;
  }

  // *this * 2^bits, bits >= 0.
  BigInt ShiftLeft(int bits) const {
    if (bits < 0) throw std::invalid_argument("BigInt::ShiftLeft: negative shift");
    if (mag_.empty() || bits == 0) return *this;
    const int limbs = bits / 32, rest = bits % 32;
    BigInt r;
    r.neg_ = neg_;
    r.mag_.assign(mag_.size() + static_cast<std::size_t>(limbs) + 1, 0u);
    for (std::size_t i = 0; i < mag_.size(); ++i) {
      const uint64_t v = static_cast<uint64_t>(mag_[i]) << rest;
      r.mag_[i + limbs] |= static_cast<uint32_t>(v & 0xFFFFFFFFu);
      r.mag_[i + limbs + 1] |= static_cast<uint32_t>(v >> 32);
    }
    r.Trim();
    return r;
  }

  int Compare(const BigInt& o) const { return (*this - o).Sign(); }
  bool operator==(const BigInt& o) const { return Compare(o) == 0; }
  bool operator!=(const BigInt& o) const { return Compare(o) != 0; }

  // Hexadecimal, for failure messages.
  std::string ToHex() const {
    if (mag_.empty()) return "0x0";
    static const char* kDigits = "0123456789abcdef";
    std::string s;
    for (std::size_t i = 0; i < mag_.size(); ++i) {
      uint32_t v = mag_[i];
      for (int k = 0; k < 8; ++k) {
        s.push_back(kDigits[v & 0xF]);
        v >>= 4;
      }
    }
    while (s.size() > 1 && s.back() == '0') s.pop_back();
    s += "x0";
    if (neg_) s += "-";
    std::reverse(s.begin(), s.end());
    return s;
  }

  std::size_t num_limbs() const { return mag_.size(); }

 private:
  void Trim() {
    while (!mag_.empty() && mag_.back() == 0u) mag_.pop_back();
    if (mag_.empty()) neg_ = false;
  }
  static int CompareMag(const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
    if (a.size() != b.size()) return a.size() < b.size() ? -1 : 1;
    for (std::size_t i = a.size(); i-- > 0;) {
      if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
    }
    return 0;
  }
  static std::vector<uint32_t> AddMag(const std::vector<uint32_t>& a,
                                      const std::vector<uint32_t>& b) {
    const std::vector<uint32_t>& big = a.size() >= b.size() ? a : b;
    const std::vector<uint32_t>& small = a.size() >= b.size() ? b : a;
    std::vector<uint32_t> r(big.size() + 1, 0u);
    uint64_t carry = 0;
    for (std::size_t i = 0; i < big.size(); ++i) {
      const uint64_t cur = static_cast<uint64_t>(big[i]) + (i < small.size() ? small[i] : 0u) + carry;
      r[i] = static_cast<uint32_t>(cur & 0xFFFFFFFFu);
      carry = cur >> 32;
    }
    r[big.size()] = static_cast<uint32_t>(carry);
    return r;
  }
  // |a| - |b| with |a| >= |b|.
  static std::vector<uint32_t> SubMag(const std::vector<uint32_t>& a,
                                      const std::vector<uint32_t>& b) {
    std::vector<uint32_t> r(a.size(), 0u);
    int64_t borrow = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      int64_t cur = static_cast<int64_t>(a[i]) - (i < b.size() ? static_cast<int64_t>(b[i]) : 0) -
                    borrow;
      borrow = 0;
      if (cur < 0) {
        cur += int64_t{1} << 32;
        borrow = 1;
      }
      r[i] = static_cast<uint32_t>(cur);
    }
    return r;
  }

  bool neg_ = false;
  std::vector<uint32_t> mag_;
};

// An exact dyadic rational m * 2^e.
struct Dyadic {
  BigInt m;
  int e = 0;

  static Dyadic FromDouble(double v) {
    if (!std::isfinite(v)) throw std::invalid_argument("Dyadic::FromDouble: not finite");
    Dyadic d;
    if (v == 0.0) return d;
    int exp = 0;
    const double f = std::frexp(v, &exp);  // v = f * 2^exp, 0.5 <= |f| < 1
    // f has at most 53 significant bits below its leading 2^-1 bit (fewer
    // for subnormals), so f * 2^62 is an integer, and |f * 2^62| < 2^62.
    const double scaled = std::ldexp(f, 62);
    d.m = BigInt::FromInt64(static_cast<int64_t>(scaled));
    if (static_cast<double>(static_cast<int64_t>(scaled)) != scaled) {
      throw std::logic_error("Dyadic::FromDouble: mantissa not integral");
    }
    d.e = exp - 62;
    return d;
  }
  static Dyadic FromInt(int64_t v) {
    Dyadic d;
    d.m = BigInt::FromInt64(v);
    return d;
  }

  int Sign() const { return m.Sign(); }

  Dyadic operator-() const { return {-m, e}; }
  Dyadic operator+(const Dyadic& o) const {
    if (m.IsZero()) return o;
    if (o.m.IsZero()) return *this;
    const int lo = std::min(e, o.e);
    return {m.ShiftLeft(e - lo) + o.m.ShiftLeft(o.e - lo), lo};
  }
  Dyadic operator-(const Dyadic& o) const { return *this + (-o); }
  Dyadic operator*(const Dyadic& o) const { return {m * o.m, e + o.e}; }
  int Compare(const Dyadic& o) const { return (*this - o).Sign(); }
  bool operator==(const Dyadic& o) const { return Compare(o) == 0; }
  bool operator!=(const Dyadic& o) const { return Compare(o) != 0; }
};

// Determinant of a small square matrix by Laplace expansion along the first
// row (n! terms; meant for n <= 4).
inline Dyadic ExactDeterminant(const std::vector<std::vector<Dyadic>>& a) {
  const std::size_t n = a.size();
  if (n == 1) return a[0][0];
  if (n == 2) return a[0][0] * a[1][1] - a[0][1] * a[1][0];
  Dyadic sum;
  for (std::size_t j = 0; j < n; ++j) {
    if (a[0][j].m.IsZero()) continue;
    std::vector<std::vector<Dyadic>> minor(n - 1);
    for (std::size_t r = 1; r < n; ++r) {
      for (std::size_t c = 0; c < n; ++c) {
        if (c != j) minor[r - 1].push_back(a[r][c]);
      }
    }
    const Dyadic term = a[0][j] * ExactDeterminant(minor);
    sum = (j % 2 == 0) ? sum + term : sum - term;
  }
  return sum;
}

// The orientation determinant det[[ax, ay, 1], [bx, by, 1], [cx, cy, 1]],
// exactly: > 0 for counter-clockwise a, b, c.
inline Dyadic ExactOrientDet(const Point2& a, const Point2& b, const Point2& c) {
  const Dyadic one = Dyadic::FromInt(1);
  std::vector<std::vector<Dyadic>> m;
  for (const Point2* p : {&a, &b, &c}) {
    m.push_back({Dyadic::FromDouble(p->x), Dyadic::FromDouble(p->y), one});
  }
  return ExactDeterminant(m);
}
inline int ExactOrientSign(const Point2& a, const Point2& b, const Point2& c) {
  return ExactOrientDet(a, b, c).Sign();
}

// Rows [x, y, x² + y², 1] of the lifted in-circle matrix.
inline std::vector<std::vector<Dyadic>> LiftedRows(const Point2& a, const Point2& b,
                                                   const Point2& c, const Point2& d) {
  const Dyadic one = Dyadic::FromInt(1);
  std::vector<std::vector<Dyadic>> m;
  for (const Point2* p : {&a, &b, &c, &d}) {
    const Dyadic x = Dyadic::FromDouble(p->x), y = Dyadic::FromDouble(p->y);
    m.push_back({x, y, x * x + y * y, one});
  }
  return m;
}

// The 4x4 lifted determinant: > 0 iff d is inside the circle through the
// counter-clockwise a, b, c (the standard paraboloid-lifting identity).
inline Dyadic ExactInCircleDet(const Point2& a, const Point2& b, const Point2& c,
                               const Point2& d) {
  return ExactDeterminant(LiftedRows(a, b, c, d));
}
inline int ExactInCircleSign(const Point2& a, const Point2& b, const Point2& c,
                             const Point2& d) {
  return ExactInCircleDet(a, b, c, d).Sign();
}

// Lexicographic (x, then y) order.
inline bool LexLessPoint(const Point2& p, const Point2& q) {
  return p.x < q.x || (p.x == q.x && p.y < q.y);
}

// The documented tie rule of InCirclePerturbed, evaluated from its definition:
// each point's lifted height x² + y² is raised by an infinitesimal δ, with
// δ(larger point) infinitely larger than δ(smaller point) in lexicographic
// order. The lifted determinant is linear in the height column, so
//   det(heights + δ) = det + Σ_r δ_r · det(height column := e_r),
// and its sign is that of det if non-zero, else of the first non-zero
// det(height column := e_r) taking rows r from the largest point down.
// Returns 0 only if every term vanishes (degenerate input).
inline int ExactInCirclePerturbedSign(const Point2& a, const Point2& b, const Point2& c,
                                      const Point2& d) {
  std::vector<std::vector<Dyadic>> m = LiftedRows(a, b, c, d);
  const int s = ExactDeterminant(m).Sign();
  if (s != 0) return s;
  const Point2* p[4] = {&a, &b, &c, &d};
  std::array<int, 4> rows = {0, 1, 2, 3};
  std::stable_sort(rows.begin(), rows.end(),
                   [&](int i, int j) { return LexLessPoint(*p[j], *p[i]); });  // largest first
  for (int r : rows) {
    std::vector<std::vector<Dyadic>> e = m;
    for (int k = 0; k < 4; ++k) e[k][2] = Dyadic::FromInt(k == r ? 1 : 0);
    const int t = ExactDeterminant(e).Sign();
    if (t != 0) return t;
  }
  return 0;
}

inline int SignOf(double v) { return v > 0.0 ? 1 : (v < 0.0 ? -1 : 0); }

// Filtered versions for bulk checks: a plain double evaluation whose sign is
// trusted only when it exceeds a deliberately loose error bound (1e-12 of
// the permanent, ~1000x Shewchuk's bounds, and only in a range free of
// underflow and overflow); otherwise the exact oracle decides.
inline int FilteredOrientSign(const Point2& a, const Point2& b, const Point2& c) {
  const double l = (a.x - c.x) * (b.y - c.y);
  const double r = (a.y - c.y) * (b.x - c.x);
  const double det = l - r;
  const double perm = std::fabs(l) + std::fabs(r);
  if (std::isfinite(perm) && perm > 1e-200 && perm < 1e200 && std::fabs(det) > 1e-12 * perm) {
    return SignOf(det);
  }
  return ExactOrientSign(a, b, c);
}

inline int FilteredInCircleSign(const Point2& a, const Point2& b, const Point2& c,
                                const Point2& d) {
  const double adx = a.x - d.x, ady = a.y - d.y;
  const double bdx = b.x - d.x, bdy = b.y - d.y;
  const double cdx = c.x - d.x, cdy = c.y - d.y;
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double bc = bdx * cdy - cdx * bdy;
  const double ca = cdx * ady - adx * cdy;
  const double ab = adx * bdy - bdx * ady;
  const double det = alift * bc + blift * ca + clift * ab;
  const double perm = alift * (std::fabs(bdx * cdy) + std::fabs(cdx * bdy)) +
                      blift * (std::fabs(cdx * ady) + std::fabs(adx * cdy)) +
                      clift * (std::fabs(adx * bdy) + std::fabs(bdx * ady));
  if (std::isfinite(perm) && perm > 1e-200 && perm < 1e200 && std::fabs(det) > 1e-12 * perm) {
    return SignOf(det);
  }
  return ExactInCircleSign(a, b, c, d);
}

inline int FilteredInCirclePerturbedSign(const Point2& a, const Point2& b, const Point2& c,
                                         const Point2& d) {
  const int s = FilteredInCircleSign(a, b, c, d);
  return s != 0 ? s : ExactInCirclePerturbedSign(a, b, c, d);
}

}  // namespace surfreg::testing
