// Which cell kernel runs (SURFREG_CELL_KERNEL and the CPU), and the
// dispatch to the vector ones. Compiled for the baseline target: nothing
// here may use AVX, and the kernels' files are entered only after the CPU
// check. SURFREG_X86_CELL_KERNELS is defined (registration/CMakeLists.txt)
// when those files are compiled for their instruction sets.
#include "registration/volume_kernel_simd.h"

#include <cstdlib>
#include <cstring>

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

CellKernel Select() {
  CellKernel best = CellKernel::kScalar;
  for (CellKernel k : {CellKernel::kAvx2, CellKernel::kAvx512}) {
    if (CpuRuns(k)) best = k;
  }
  const char* value = std::getenv("SURFREG_CELL_KERNEL");
  if (value == nullptr) return best;
  for (CellKernel k : {CellKernel::kScalar, CellKernel::kAvx2, CellKernel::kAvx512}) {
    if (std::strcmp(value, CellKernelName(k)) != 0) continue;
    if (CpuRuns(k)) return k;
    LOG(WARNING) << "SURFREG_CELL_KERNEL=" << value << ": this CPU (or build) cannot run it; using "
                 << CellKernelName(best);
    return best;
  }
  LOG(WARNING) << "SURFREG_CELL_KERNEL=" << value << ": unknown (scalar, avx2 or avx512); using "
               << CellKernelName(best);
  return best;
}

}  // namespace

CellKernel SelectedCellKernel() {
  static const CellKernel kernel = Select();
  return kernel;
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
                        bool gradient, Moment* moment, CellKernelOutput* out) {
#if defined(SURFREG_X86_CELL_KERNELS) && defined(__x86_64__)
  if (CpuRuns(kernel)) {  // as SelectedCellKernel made sure; cheap
    if (kernel == CellKernel::kAvx512) {
      return IntegrateCellsAvx512(in, lo, hi, gradient, moment, out);
    }
    if (kernel == CellKernel::kAvx2) return IntegrateCellsAvx2(in, lo, hi, gradient, moment, out);
  }
#endif
  LOG(FATAL) << "IntegrateCellsSimd: no " << CellKernelName(kernel) << " vector kernel here";
}

}  // namespace volume_internal
}  // namespace surfreg
