#pragma once
// Exact integrals of the vertical gap between two surfaces over one triangle.
//
// On a triangle of area S both surfaces are linear, so their gap
// d = F2 - F1 is linear too, given by its vertex values (a, b, c). Every
// integral here is a closed form (no quadrature): the zero line of d cuts the
// triangle into a small triangle at the lone vertex (the one whose sign the
// other two do not share) and a quadrilateral, and the integrand is linear
// (or, with a weight, a product of two linear functions) on each piece. The
// derivation is in volume.cc.
//
// Units: with d a height and S an area, volumes are in data units³ and
// `weight` is an area (units²); a weight μ multiplies the volumes by its own
// unit.
//
// Accuracy: `abs`, `above`, `below` and `weight` are evaluated as sums of
// products of non-negative terms (no subtraction of large terms anywhere),
// so each has a relative error of a few ulps, also in the sign-change cases
// with one vertex value tiny next to the others. `signed_volume` is
// evaluated from its own definition (a sum of signed terms), so its absolute
// error is a few ulps of S·(|a| + |b| + |c|)/3 (weighted: of
// S/12·(Σ|d_i|m_i + Σ|d_i|·Σm_i)); abs = above + below and
// above - below = signed_volume therefore hold to rounding, not bitwise.
// Permuting the vertices together with their values changes no result (the
// same doubles come out, up to the sign of a zero).
//
// Domain: finite inputs, S ≥ 0, weights m_i ≥ 0 (negative weights give the
// algebraically correct values but lose the accuracy statement above),
// |d_i| ≤ 2^1020 (≈ 1e307) so that no intermediate sum of magnitudes can
// overflow, and results (and S·|d_i|·m_i) representable. Any vertex
// value may be exactly 0 (also two or three of them). Values are not
// rescaled: results that fall below the normal range (e.g. S·d ≈ 1e-310)
// are subnormal with a correspondingly larger relative error, never NaN.
namespace surfreg {

struct GapIntegrals {
  double abs = 0;            // ∫ |d| μ
  double above = 0;          // ∫ max(d, 0) μ   (surface 2 above surface 1: "fill")
  double below = 0;          // ∫ max(-d, 0) μ  (surface 2 below surface 1: "cut")
  double signed_volume = 0;  // ∫ d μ
  double weight = 0;         // ∫ μ (the area when μ = 1)

  GapIntegrals& operator+=(const GapIntegrals& o) {
    abs += o.abs;
    above += o.above;
    below += o.below;
    signed_volume += o.signed_volume;
    weight += o.weight;
    return *this;
  }
};

// The integrals with μ = 1 over a triangle of area `area` on which d has
// vertex values a, b, c.
GapIntegrals IntegrateGap(double area, double a, double b, double c);

// The integrals with μ linear on the triangle, vertex values m[0..2] (at the
// vertices where d has values d[0..2]).
GapIntegrals IntegrateGapWeighted(double area, const double d[3], const double m[3]);

// The paper's closed form for ∫|d| alone: S(|a| + |b| + |c|)/3 when no two
// vertex values have strictly opposite signs; otherwise, with b the lone
// vertex and s the sign of the other two (of the non-zero one if one is 0),
//   s·S(a + b + c)/3 + 2S|b|³ / (3(|b| + |a|)(|b| + |c|)).
// The last term is evaluated as 2S/3·|b|·(|b|/(|b|+|a|))·(|b|/(|b|+|c|)),
// which is algebraically the same but cannot underflow or overflow in the
// intermediate |b|³. Agrees with IntegrateGap().abs to rounding.
double AbsVolumePaper(double area, double a, double b, double c);

}  // namespace surfreg
