// Which cell kernel runs (the choice and the CPU), and the
// dispatch to the vector ones. Compiled for the baseline target: nothing
// here may use AVX, and the kernels' files are entered only after the CPU
// check. SURFREG_X86_CELL_KERNELS is defined (registration/CMakeLists.txt)
// when those files are compiled for their instruction sets.
#include "registration/volume_cost/volume_kernel_simd.h"

#include <atomic>
#include <string>
#include <utility>

#include <glog/logging.h>

namespace surfreg {
namespace volume_internal {

namespace {

// Whether this CPU (and OS) runs a kernel.
bool CpuRuns(CellKernel kernel) {
#if defined(SURFREG_X86_CELL_KERNELS) && defined(__x86_64__)
  __builtin_cpu_init();
  switch (kernel) {
    case CellKernel::kScalar: return true;
    case CellKernel::kAvx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case CellKernel::kAvx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx2") &&
             __builtin_cpu_supports("fma");
  }
  return false;
#else
  return kernel == CellKernel::kScalar;
#endif
}

CellKernel Best() {
  CellKernel best = CellKernel::kScalar;
  for (CellKernel k : {CellKernel::kAvx2, CellKernel::kAvx512}) {
    if (CpuRuns(k)) best = k;
  }
  return best;
}

}  // namespace

CellKernel ResolveCellKernel(CellKernelChoice choice) {
  static const CellKernel best = Best();
  CellKernel wanted = best;
  switch (choice) {
    case CellKernelChoice::kBest: return best;
    case CellKernelChoice::kScalar: wanted = CellKernel::kScalar; break;
    case CellKernelChoice::kAvx2: wanted = CellKernel::kAvx2; break;
    case CellKernelChoice::kAvx512: wanted = CellKernel::kAvx512; break;
  }
  if (CpuRuns(wanted)) return wanted;
  static std::atomic<bool> warned{false};
  if (!warned.exchange(true)) {
    LOG(WARNING) << "cell kernel " << CellKernelName(wanted) << ": this CPU (or build) cannot run it; using "
                 << CellKernelName(best);
  }
  return best;
}

const char* CellKernelName(CellKernel kernel) {
  switch (kernel) {
    case CellKernel::kScalar: return "scalar";
    case CellKernel::kAvx2: return "avx2";
    case CellKernel::kAvx512: return "avx512";
  }
  return "?";
}

void IntegrateCellsSimd(CellKernel kernel, const CellKernelInput& in, int32_t lo, int32_t hi,
                        bool gradient, CellKernelOutput* out) {
#if defined(SURFREG_X86_CELL_KERNELS) && defined(__x86_64__)
  if (CpuRuns(kernel)) {  // as ResolveCellKernel made sure; cheap
    if (kernel == CellKernel::kAvx512) {
      return IntegrateCellsAvx512(in, lo, hi, gradient, out);
    }
    if (kernel == CellKernel::kAvx2) return IntegrateCellsAvx2(in, lo, hi, gradient, out);
  }
#endif
  LOG(FATAL) << "IntegrateCellsSimd: no " << CellKernelName(kernel) << " vector kernel here";
}

}  // namespace volume_internal

bool ParseCellKernel(const std::string& name, CellKernelChoice* choice) {
  static const std::pair<const char*, CellKernelChoice> kNames[] = {{"best", CellKernelChoice::kBest},
                                                                    {"scalar", CellKernelChoice::kScalar},
                                                                    {"avx2", CellKernelChoice::kAvx2},
                                                                    {"avx512", CellKernelChoice::kAvx512}};
  for (const auto& [text, value] : kNames) {
    if (name == text) {
      *choice = value;
      return true;
    }
  }
  return false;
}

}  // namespace surfreg
