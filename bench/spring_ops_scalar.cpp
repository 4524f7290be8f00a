// Compiled with -fno-tree-vectorize (bench/CMakeLists.txt): the scalar arithmetic roof.
#include "bench/spring_ops.h"

namespace clothsim::bench {

void eval_spring_ops_scalar(SpringSoA& s, double ke, double kd) { eval_spring_ops(s, ke, kd); }

}  // namespace clothsim::bench
