#pragma once
// Which cell kernel the volume cost integrates the overlay's cells with
// (volume_kernel_simd.h): AlignOptions::cell_kernel, the CLI's key
// `cell_kernel`.
#include <string>

namespace surfreg {

// The volume cost's inner loop, the integrals over the overlay's cells: the
// best kernel this CPU runs (AVX-512 F/DQ/VL, then AVX2 + FMA, then
// scalar), or one named, for comparison (one the CPU or build cannot run
// falls back to the best, with a warning). Every kernel gives the same
// cost to rounding.
enum class CellKernelChoice { kBest, kScalar, kAvx2, kAvx512 };
// "scalar", "avx2", "avx512" or "best"; false (choice untouched) for
// another name (the CLI's key `cell_kernel`).
bool ParseCellKernel(const std::string& name, CellKernelChoice* choice);

}  // namespace surfreg
