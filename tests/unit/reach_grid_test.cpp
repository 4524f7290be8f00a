// The reach grid (systems/collision/reach_grid.h): a box that overlaps a flagged particle's swept path grown by the
// reach always reaches a marked cell; boxes far from every path do not.
#include <doctest/doctest.h>

#include <limits>
#include <random>

#include "systems/collision/broad_phase.h"
#include "systems/collision/reach_grid.h"

using namespace clothsim;

TEST_CASE("reach grid: one resting particle marks the 27 cells round it, a box two cells away is not near") {
  State in;
  in.x = {Vec3(0.05, 0.05, 0.05), Vec3(3, 3, 3), Vec3(3, 3, 3), Vec3(3, 3, 3), Vec3(3, 3, 3)};
  const State out = in;
  ReachGrid g;
  build_reach_grid(in, out, {1, 0, 0, 0, 0}, 0.1, g);  // the others are not flagged
  // Grown by 0.1 m, the particle's point spans [-0.05, 0.15] an axis: cells -1, 0 and 1 of side 0.1 m.
  CHECK(g.cells.size() == 27);
  CHECK_FALSE(g.everywhere);
  CHECK(reaches(g, {Vec3(0.14, 0.14, 0.14), Vec3(0.16, 0.16, 0.16)}));  // meets the grown box
  CHECK(reaches(g, {Vec3(0.18, 0.18, 0.18), Vec3(0.19, 0.19, 0.19)}));  // outside it, inside its last cell
  CHECK_FALSE(reaches(g, {Vec3(0.21, 0.05, 0.05), Vec3(0.25, 0.06, 0.06)}));
  CHECK_FALSE(reaches(g, {Vec3(2.9, 2.9, 2.9), Vec3(3.1, 3.1, 3.1)}));  // round the unflagged particle
}

TEST_CASE("reach grid: every box that meets a grown path reaches a marked cell (random paths and boxes)") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<Real> pos(-0.5, 0.5), step(-0.02, 0.02), size(0, 0.08);
  State in, out;
  std::vector<std::uint8_t> flag;
  for (int i = 0; i < 400; ++i) {
    in.x.push_back(Vec3(pos(rng), pos(rng), pos(rng)));
    out.x.push_back(in.x.back() + Vec3(step(rng), step(rng), step(rng)));
    flag.push_back(i % 8 == 0);  // 50 flagged
  }
  const Real reach = 0.03;
  ReachGrid g;
  build_reach_grid(in, out, flag, reach, g);
  int meets = 0, near = 0;
  for (int q = 0; q < 20000; ++q) {
    const Vec3 lo(pos(rng), pos(rng), pos(rng));
    const Aabb box{lo, lo + Vec3(size(rng), size(rng), size(rng))};
    bool met = false;
    for (std::size_t i = 0; i < flag.size() && !met; ++i) {
      if (!flag[i]) continue;
      Aabb grown = swept_box(in.x[i], out.x[i]);
      grown.lo.array() -= reach;
      grown.hi.array() += reach;
      met = boxes_overlap(box, grown);
    }
    const bool reached = reaches(g, box);
    if (met) CHECK(reached);
    meets += met;
    near += reached;
  }
  // Conservative by at most the cells round each grown path: some boxes meet no path yet reach a cell, and most
  // boxes reach none.
  CHECK(meets > 500);
  CHECK(near >= meets);
  CHECK(near < 20000 / 2);
  MESSAGE(meets << " boxes meet a grown path, " << near << " reach a marked cell, of 20000");
}

TEST_CASE("reach grid: a path beyond the representable cells, no reach or many particles make every box near") {
  State in;
  in.x = {Vec3(std::numeric_limits<Real>::infinity(), 0, 0)};
  const State out = in;
  ReachGrid g;
  build_reach_grid(in, out, {1}, 0.1, g);
  CHECK(g.everywhere);
  CHECK(reaches(g, {Vec3(5, 5, 5), Vec3(6, 6, 6)}));
  in.x = {Vec3::Zero()};
  build_reach_grid(in, in, {1}, 0, g);
  CHECK(g.everywhere);
  // Two of five particles flagged: over a quarter, so no cells are listed; one of five is marked cell by cell.
  in.x.assign(5, Vec3::Zero());
  build_reach_grid(in, in, {1, 1, 0, 0, 0}, 0.1, g);
  CHECK(g.everywhere);
  build_reach_grid(in, in, {1, 0, 0, 0, 0}, 0.1, g);
  CHECK_FALSE(g.everywhere);
  CHECK(g.cells.size() == 27);
}
