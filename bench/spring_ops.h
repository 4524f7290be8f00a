#pragma once
// The spring's arithmetic alone, on cache-resident structure-of-arrays data: the arithmetic roof of
// docs/performance.md. Its items are springs, so a spring kernel's springs/s over this is its achieved fraction.
#include <cmath>
#include <vector>

namespace clothsim::bench {

struct SpringSoA {
  static constexpr int n = 4096;  // 10 arrays x 32 KB: L2-resident
  std::vector<double> dx, dy, dz, dvx, dvy, dvz, rest, fx, fy, fz;
  SpringSoA() : dx(n), dy(n), dz(n), dvx(n), dvy(n), dvz(n), rest(n), fx(n), fy(n), fz(n) {
    for (int i = 0; i < n; ++i) {
      dx[i] = 0.01 + 1e-6 * i; dy[i] = -0.002; dz[i] = 0.003;
      dvx[i] = 0.1; dvy[i] = -0.2; dvz[i] = 0.05; rest[i] = 0.0095;
    }
  }
};

// f = [ke (len - rest) + kd (dv.d)/len] d/len: one sqrt, one division, the rest (multiply-)adds.
inline void eval_spring_ops(SpringSoA& s, double ke, double kd) {
#pragma omp simd
  for (int i = 0; i < SpringSoA::n; ++i) {
    const double len = std::sqrt(s.dx[i] * s.dx[i] + s.dy[i] * s.dy[i] + s.dz[i] * s.dz[i]);
    const double inv = 1.0 / len;
    const double along = s.dvx[i] * s.dx[i] + s.dvy[i] * s.dy[i] + s.dvz[i] * s.dz[i];
    const double mag = (ke * (len - s.rest[i]) + kd * along * inv) * inv;
    s.fx[i] = mag * s.dx[i];
    s.fy[i] = mag * s.dy[i];
    s.fz[i] = mag * s.dz[i];
  }
}

// The same loop from a translation unit compiled without the vectoriser: one lane.
void eval_spring_ops_scalar(SpringSoA& s, double ke, double kd);

}  // namespace clothsim::bench
