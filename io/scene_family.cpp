#include "io/scene_family.h"

#include <cmath>
#include <cstdio>

#include <cstdint>

namespace clothsim::io {
namespace {

// Uniform in [0, 1) from (seed, a, b): splitmix64 finaliser (Steele, Lea & Flood 2014), 53 bits.
double unit(std::uint64_t seed, std::uint64_t a, std::uint64_t b) {
  std::uint64_t z = seed * 0x9e3779b97f4a7c15ULL + a * 0xbf58476d1ce4e5b9ULL + b * 0x94d049bb133111ebULL;
  for (int k = 0; k < 2; ++k) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
  }
  return double(z >> 11) * 0x1.0p-53;
}

}  // namespace

FamilyScene family_scene(int seed, const std::string& timestep) {
  auto pick = [&](int slot) { return unit(977, std::uint64_t(seed), std::uint64_t(slot)); };  // in [0, 1)
  const int nx = 3 + int(4 * pick(0)), ny = 3 + int(4 * pick(1));
  const Real size = 0.3 + 0.7 * pick(2);
  const Real density = 0.05 * std::pow(10.0, pick(3));               // 0.05 .. 0.5 kg/m^2
  const Real stiffness = 200 * std::pow(10.0, 1.5 * pick(4));        // 200 .. 6300 N/m
  const bool proportional = pick(5) < 0.6;
  const Real bend = proportional ? 1.0 : 0.1;
  const Real damping = pick(6) < 0.2 ? 0.0 : 0.001 * std::pow(10.0, 3 * pick(7));  // 0, or 0.001 .. 1 N s/m
  const Real air = pick(8) < 0.4 ? 0.0 : 5 * pick(9);                // 1/s
  const int integ = int(3 * pick(10));                               // euler, symplectic, rk4
  const int pins = int(3 * pick(11));                                // none, one corner, two corners
  const bool collider = pick(12) < 0.5;
  // Explicit Euler is unstable at any step without damping: it is given some where the draw has none.
  const Real spring_damping = integ == 0 && damping == 0 ? 0.01 : damping;
  char buf[1400];
  std::snprintf(buf, sizeof buf, R"(<scene>
  <simulation timestep="%s" fps="100" startFrame="1" endFrame="3" integrator="%s"/>
  <forces><airDamping value="%.6g"/></forces>
  %s
  <cloth name="c" grid="%d %d" size="%.6g %.6g" rotate="%s" saveDir="out" saveName="c">
    <density value="%.6g"/><stiffness value="%.6g" bend="%.6g"/><damping value="%.6g"/><thickness value="0.005"/>
    %s
  </cloth>
</scene>
)", timestep.c_str(), integrator_name(Integrator(integ)), air,
                collider ? R"(<sphere name="ball" center="0 -0.15 0.2" radius="0.12" friction="0.3"/>)" : "",
                nx, ny, size, size, pins ? "90 0 0" : "0 0 0", density, stiffness, bend, spring_damping,
                pins == 0 ? "" : pins == 1 ? "<pins vertices=\"0\"/>" : ("<pins vertices=\"0 " + std::to_string(nx - 1) + "\"/>").c_str());
  return {buf, proportional};
}

void perturb_start(const Model& m, State& s, Real amount) {
  for (Index i = 0; i < m.particle_count; ++i)
    if (m.particle_inv_mass[i] > 0)
      for (int k = 0; k < 3; ++k) s.x[i][k] += amount * (unit(31, std::uint64_t(i), std::uint64_t(k)) - 0.5);
}

}  // namespace clothsim::io
