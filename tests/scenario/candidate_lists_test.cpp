// The broad phase's candidate lists (systems/collision/candidate_cache.h): a walk through them finds exactly the
// pairs a brute-force pass over every prim finds, while the cloth stays within the margin, after parts of it have
// run away beyond it, and when the lists may not be used at all.
#include <doctest/doctest.h>

#include <random>

#include "systems/collision/collide.h"
#include "systems/collision/proximity_pairs.h"
#include "tests/support/collision_scene.h"

using namespace clothsim;

namespace {

// Two self-colliding 16 x 16 sheets of 0.5 m, 1 cm thick, in the same place, over a ball of 10 cm radius whose
// triangles and vertices they cross.
sim::LoadedScene sheets_on_ball() {
  const auto dir = test::scratch_dir("candidate_lists");
  test::write_text(dir / "ball.obj", test::sphere_obj(Vec3(0, -0.08, 0), 0.1));
  test::write_text(dir / "scene.xml", R"(<scene><simulation broadPhase="bvh"/>
      <cloth name="a" grid="16 16" size="0.5 0.5" selfCollision="true"><thickness value="0.01"/></cloth>
      <cloth name="b" grid="16 16" size="0.5 0.5" selfCollision="true"><thickness value="0.01"/></cloth>
      <static name="ball" obj="ball.obj"/></scene>)");
  return test::load_collision_scene(dir / "scene.xml");
}

// Each vertex of `from` moved by up to `reach` an axis.
std::vector<Vec3> jitter(const std::vector<Vec3>& from, Real reach, std::mt19937& rng) {
  std::uniform_real_distribution<Real> d(-reach, reach);
  std::vector<Vec3> x = from;
  for (Vec3& p : x) p += Vec3(d(rng), d(rng), d(rng));
  return x;
}

}  // namespace

TEST_CASE("candidate lists: the walks through them find the brute-force pairs, runaways included") {
  auto sc = sheets_on_ball();
  const Model& m = sc.built.model;
  REQUIRE(m.collision.broad_phase == BroadPhase::bvh);
  REQUIRE(m.collision.prim.size() > std::size_t(m.collision.cloth_prim_count));  // the ball's triangles
  std::mt19937 rng(7);
  State in = sc.built.state, out = in;
  std::uniform_real_distribution<Real> height(-0.03, 0.03);
  for (Vec3& p : in.x) p.y() += height(rng);
  out.x = jitter(in.x, 0.004, rng);
  Workspace ws = make_workspace(m, sc.built.options);
  CollisionScratch& s = ws.collision;
  build_broad_phase(m, in, out, s);
  make_candidate_lists(m, in, out, s);
  const Real margin = s.candidates.margin;
  CHECK(margin == doctest::Approx(0.0025));  // a quarter of the sheets' 1 cm thickness
  REQUIRE(usable_candidates(in, s, WalkKind::vertex) != nullptr);

  // Listed and brute-force pairs of the positions `at`, the cloth's boxes rebuilt there first.
  const auto both = [&](const std::vector<Vec3>& at) {
    State now = out;
    now.x = at;
    build_cloth_broad_phase(m, in, now, s);
    const auto listed = list_proximities(m, in, now, s, BroadMode::bvh);
    return std::make_pair(listed, list_proximities(m, in, now, s, BroadMode::brute));
  };
  std::size_t kinds[4] = {};
  {
    const auto [listed, brute] = both(out.x);
    CHECK(listed == brute);
    for (const auto& k : brute) ++kinds[k[0]];
  }
  // All four kinds of pair are there: vertex-triangle, cloth edges, collider vertex, collider edge.
  for (std::size_t n : kinds) CHECK(n > 10);
  {
    // Every vertex within 0.9 margins of where the lists were made: none runs away.
    const auto [listed, brute] = both(jitter(out.x, 0.9 * margin, rng));
    CHECK(s.candidates.runaway.empty());
    CHECK(listed.size() > 400);
    CHECK(listed == brute);
  }
  {
    // One vertex in 25 moved 3 margins: their triangles run away and are tested apart; the elements they
    // belong to walk the trees.
    std::vector<Vec3> at = jitter(out.x, 0.9 * margin, rng);
    std::uniform_real_distribution<Real> far(-3 * margin, 3 * margin);
    for (std::size_t i = 0; i < at.size(); i += 25) at[i] = out.x[i] + Vec3(far(rng), far(rng), far(rng));
    const auto [listed, brute] = both(at);
    CHECK(s.candidates.runaway.size() > 50);
    CHECK(s.candidates.runaway.size() <= runaway_limit);
    CHECK(listed == brute);
  }
  {
    // Every vertex 3 margins away: more runaways than the limit, and the lists are not used.
    std::vector<Vec3> at = jitter(out.x, 3 * margin, rng);
    const auto [listed, brute] = both(at);
    CHECK(usable_candidates(in, s, WalkKind::vertex) == nullptr);
    CHECK(listed == brute);
  }
  // Another start-of-step state, or a broad phase built afresh, turns them off.
  State other = in;
  CHECK(usable_candidates(other, s, WalkKind::edge) == nullptr);
  build_broad_phase(m, in, out, s);
  CHECK(usable_candidates(in, s, WalkKind::edge) == nullptr);
}
