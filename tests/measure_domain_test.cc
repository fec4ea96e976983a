// Measure over the data domain (issue 20): Ω is the intersection of the two
// surfaces' data domains (measure/domain.h); with DomainKind::kHull it is the
// paper's Conv(A) ∩ Conv(B), bit for bit as before the domain existed.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "measure/domain.h"
#include "measure/measures.h"
#include "tests/testing/hull_golden_pairs.h"

namespace surfreg {
namespace {

// Recorded from Measure before the data domain (tests/testing/hull_golden_pairs.h,
// GoldenFingerprint order), printed with %a.
const std::vector<std::vector<double>> kHullGolden = {
    {0x1.e6d2968ecccaep+6, 0x1.78567138ac6d5p+0, 0x1.0d3d608e8fd42p-7, 0x1.4b5f8ff81d19dp+6,
     0x1.87c352b5225a9p+6, 0x1.7e490c47fa4f6p+6, 0x1.4b5f8ff81d199p+6, 0x1.78175ac984f76p+0,
     0x1.28c8b9b602adcp+6, 0x1.87cda82267bcep+6, 0x1.7c13b9b19438bp+4, 0x1.869e66ead222ap+6,
     0x1.7700deebe40a1p+4, 0x1.b641efd5453d1p+5, 0x1.5fddbbf8c12f8p+4, 0x1.b8p+9,
     0x1.46cp+12,          0x1.a7ep+11,          0x1.b12d0aa3bb9bbp+8, 0x1.68p+6},
    {0x1.e6d2968eccc9ep+6, 0x1.78567138ac6d5p+0, 0x1.0d3d608e8fd4ap-7, 0x1.4b5f8ff81d1a7p+6,
     0x1.87c352b5225a9p+6, 0x1.7e490c47fa4f6p+6, 0x1.4b5f8ff81d1a6p+6, 0x1.78175ac984f5ap+0,
     0x1.28c8b9b602ad8p+6, 0x1.87cda82267bb4p+6, 0x1.7c13b9b194386p+4, 0x1.869e66ead2219p+6,
     0x1.7700deebe40a2p+4, 0x1.b641efd5453fap+5, 0x1.5fddbbf8c12f8p+4, 0x1.b8p+9,
     0x1.46cp+12,          0x1.a7ep+11,          0x1.b12d0aa3bb9bbp+8, 0x1.68p+6},
    {0x1.e49f586a64412p+6,
     0x1.78567138ac6d5p+0,
     0x1.0e764bb2bbce1p-7,
     0x1.4a6228b200c0cp+6,
     0x1.87c352b5225a9p+6,
     0x1.7e490c47fa4f6p+6,
     0x1.4a6228b200c0cp+6,
     0x1.778362138f80fp+0,
     0x1.27e87fc38bb8fp+6,
     0x1.8643ec16f7fcbp+6,
     0x1.796db14db10eep+4,
     0x0p+0,
     0x0p+0,
     0x0p+0,
     0x0p+0,
     0x1.b8p+9,
     0x1.b44p+10,
     0x1.a7ep+11,
     0x1.b12d0aa3bb9bbp+8,
     0x1.68p+6},
    {0x1.30d4504c958ccp+7,
     0x1.717a6b13b723cp+0,
     0x1.adfc1e9a4dfe4p-8,
     0x1.4733b5e19c7e6p+6,
     0x1.811af03c20d6ep+6,
     0x1.7e490c47fa4f6p+6,
     0x1.a6054467cd1a2p+6,
     0x1.71d283701061dp+0,
     0x1.7b32b6d6bf0fcp+6,
     0x1.ee6dabb7f5147p+6,
     0x1.ccebd384d811dp+4,
     0x1.ee6dabb7f5141p+6,
     0x1.ccebd384d811ep+4,
     0x1.2b09a6fbd6409p+6,
     0x1.ebee75afdb703p+4,
     0x1.af8p+9,
     0x1.3c3p+12,
     0x1.9bap+11,
     0x0p+0,
     0x0p+0},
    {0x1.6e770b226f2bap+4,
     0x1.dd4701a1899abp-1,
     0x1.65aa717615e07p-5,
     0x1.4b5f8ff81d199p+6,
     0x1.87c352b5225a9p+6,
     0x1.7e490c47fa4f6p+6,
     0x1.9bffffffffffap+4,
     0x1.c769af63f5076p-1,
     -0x1.3762459091dfap+2,
     0x1.209e79be4ab44p+3,
     0x1.bc4f9c8693a3bp+3,
     0x0p+0,
     0x0p+0,
     0x0p+0,
     0x0p+0,
     0x1.b8p+9,
     0x1.46cp+12,
     0x1.a7ep+11,
     0x0p+0,
     0x0p+0},
    {0x1.023a3a73f2876p+11,
     0x1.ec961f85b532cp+1,
     0x1.fb95617f2dc2ep-12,
     0x1.0d56339c0ec07p+9,
     0x1.138p+9,
     0x1.138p+9,
     0x1.0d56339c0ebfp+9,
     0x1.eae1b3fb74f97p+1,
     0x1.020fa4d90377dp+11,
     0x1.0224efa67affbp+11,
     0x1.54acd7787dc81p-1,
     0x1.021f80309b699p+11,
     0x1.107c909a3d8bp-1,
     0x1.049afe41e363fp+9,
     0x1.8e79b09b96623p+2,
     0x1.07cp+10,
     0x1.437p+12,
     0x1.bcep+11,
     0x1.0a5026350505ep+11,
     0x1.88p+5},
};

TEST(MeasureDomainTest, HullDomainIsBitIdenticalToTheMeasuresBeforeTheDomain) {
  const std::vector<testing::GoldenCase> cases = testing::GoldenCases();
  ASSERT_EQ(cases.size(), kHullGolden.size());
  for (std::size_t k = 0; k < cases.size(); ++k) {
    MeasureOptions options = cases[k].options;
    options.domain.kind = DomainKind::kHull;
    const std::vector<double> now =
        testing::GoldenFingerprint(Measure(cases[k].a, cases[k].b, options));
    ASSERT_EQ(now.size(), kHullGolden[k].size());
    for (std::size_t i = 0; i < now.size(); ++i) {
      EXPECT_EQ(now[i], kHullGolden[k][i]) << "case " << k << ", value " << i;
    }
  }
}

}  // namespace
}  // namespace surfreg
