#include <doctest/doctest.h>

#include "core/blas_kernel.h"

using namespace clothsim;

TEST_CASE("the OPENBLAS_CORETYPE advice: only for a kernel older than AVX2 on a CPU that has it") {
  const CpuVectorUnits avx512{true, true}, avx2{true, false}, sse{false, false};
  // The case met on an AVX-512 Xeon that Debian's OpenBLAS 0.3.21 does not know (docs/performance.md).
  CHECK(better_openblas_coretype("Prescott", avx512) == "SkylakeX");
  CHECK(better_openblas_coretype("Prescott", avx2) == "Haswell");
  CHECK(better_openblas_coretype("Sandybridge", avx2) == "Haswell");  // AVX without AVX2's FMA kernels
  CHECK(better_openblas_coretype("Prescott", sse).empty());           // nothing wider to use
  CHECK(better_openblas_coretype("Haswell", avx512).empty());
  CHECK(better_openblas_coretype("Zen", avx2).empty());
  CHECK(better_openblas_coretype("SKYLAKEX", avx512).empty());  // names compared without case
  CHECK(better_openblas_coretype("", avx512).empty());          // not OpenBLAS: nothing to say
  MESSAGE("this machine: OpenBLAS kernels '" << blas_kernel_name() << "', advice '"
                                             << better_openblas_coretype(blas_kernel_name(), cpu_vector_units())
                                             << "'");
}
