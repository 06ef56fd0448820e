// What the CPU running the core can do, for the loops compiled for more than the
// build's baseline (a target attribute, never -march): checked at run time, once.
#pragma once

namespace pcl_vts::detail {

/// Whether this CPU runs AVX2 instructions; false where the compiler cannot ask
/// (not GCC or clang on x86).
inline bool cpuHasAvx2()
{
#if defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
  static const bool avx2 = __builtin_cpu_supports("avx2") != 0;
  return avx2;
#else
  return false;
#endif
}

} // namespace pcl_vts::detail
