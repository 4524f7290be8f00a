#include "core/blas_kernel.h"

#include <dlfcn.h>

#include <algorithm>
#include <array>
#include <cctype>

namespace clothsim {

std::string blas_kernel_name() {
  using CoreName = char* (*)();
  const auto core_name = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  const char* name = core_name ? core_name() : nullptr;
  return name ? std::string(name) : std::string();
}

bool blas_calls_may_overlap() {
  using GetParallel = int (*)();
  static const bool overlap = [] {
    const auto get_parallel = reinterpret_cast<GetParallel>(dlsym(RTLD_DEFAULT, "openblas_get_parallel"));
    return !get_parallel || get_parallel() != 0;  // 0: OpenBLAS's sequential build
  }();
  return overlap;
}

void blas_on_calling_thread() {
  using SetThreads = void (*)(int);
  static const auto set_threads = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set_threads) set_threads(1);
}

CpuVectorUnits cpu_vector_units() {
  CpuVectorUnits u;
#if defined(__x86_64__) || defined(__i386__)
  __builtin_cpu_init();
  u.avx2 = __builtin_cpu_supports("avx2");
  u.avx512 = __builtin_cpu_supports("avx512f");
#endif
  return u;
}

std::string better_openblas_coretype(std::string_view kernel, CpuVectorUnits cpu) {
  if (kernel.empty() || !cpu.avx2) return {};
  std::string lower(kernel);
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  // OpenBLAS 0.3's x86-64 kernels that use AVX2 or AVX-512; every other one is older.
  constexpr std::array<std::string_view, 5> wide = {"haswell", "zen", "skylakex", "cooperlake", "sapphirerapids"};
  if (std::find(wide.begin(), wide.end(), lower) != wide.end()) return {};
  return cpu.avx512 ? "SkylakeX" : "Haswell";
}

}  // namespace clothsim
