#pragma once
// Which BLAS kernels the Cholesky factorisation runs on. Debian's OpenBLAS picks its kernels from the CPU's model
// number, and a CPU newer than it knows gets its generic Prescott (SSE3) kernels: on an AVX-512 Xeon that made the
// sewn dress's implicit phase half as slow again (docs/performance.md, "The BLAS kernels"). OpenBLAS reads its
// choice once, when it is loaded, from OPENBLAS_CORETYPE, so the front end sets it and restarts (tools/main.cpp).
#include <string>
#include <string_view>

namespace clothsim {

// OpenBLAS's name for the kernels it runs (openblas_get_corename, looked up at run time), "" when the BLAS loaded
// is not OpenBLAS.
std::string blas_kernel_name();

// Whether BLAS calls may run at once on different threads. False for an OpenBLAS built single-threaded (Debian's
// libopenblas0-serial): it shares its buffers between calls without locks, and two factorisations at once
// corrupt each other's results. True for a threaded OpenBLAS and for other BLAS libraries.
bool blas_calls_may_overlap();

// Asks a threaded OpenBLAS to run each call on the thread that makes it (openblas_set_num_threads(1)): clothsim's
// threads already share the work, and a call split over OpenBLAS's own threads would both compete with them and
// round differently from the same call made serially. Nothing for other BLAS libraries.
void blas_on_calling_thread();

struct CpuVectorUnits {
  bool avx2 = false;
  bool avx512 = false;  // AVX-512 F
};
CpuVectorUnits cpu_vector_units();

// The OPENBLAS_CORETYPE worth setting: SkylakeX on an AVX-512 CPU, Haswell on an AVX2 one, when OpenBLAS runs a
// kernel older than AVX2; "" otherwise (kernels that use AVX2 or wider, no OpenBLAS, or a CPU without AVX2).
std::string better_openblas_coretype(std::string_view kernel, CpuVectorUnits cpu);

}  // namespace clothsim
