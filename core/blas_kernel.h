#pragma once
// Which BLAS kernels the Cholesky factorisation runs on. Debian's OpenBLAS picks its kernels from the CPU's model
// number, and a CPU newer than it knows gets its generic Prescott (SSE3) kernels: on an AVX-512 Xeon that made the
// sewn dress's implicit phase half as slow again (docs/performance.md, "The BLAS kernels"). OpenBLAS reads its
// choice once, when it is loaded, from OPENBLAS_CORETYPE; clothsim can only say which value to set.
#include <string>
#include <string_view>

namespace clothsim {

// OpenBLAS's name for the kernels it runs (openblas_get_corename, looked up at run time), "" when the BLAS loaded
// is not OpenBLAS.
std::string blas_kernel_name();

struct CpuVectorUnits {
  bool avx2 = false;
  bool avx512 = false;  // AVX-512 F
};
CpuVectorUnits cpu_vector_units();

// The OPENBLAS_CORETYPE worth setting: SkylakeX on an AVX-512 CPU, Haswell on an AVX2 one, when OpenBLAS runs a
// kernel older than AVX2; "" otherwise (kernels that use AVX2 or wider, no OpenBLAS, or a CPU without AVX2).
std::string better_openblas_coretype(std::string_view kernel, CpuVectorUnits cpu);

}  // namespace clothsim
