#include "io/scene_xml.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <pugixml.hpp>
#include <set>
#include <sstream>

#include "core/error.h"
#include "core/limits.h"
#include "core/step_count.h"
#include "io/atomic_file.h"
#include "io/text_file.h"
#include "io/xml_element.h"

namespace clothsim::io {
namespace {

std::string resolve(const std::string& base, const std::string& p) {
  if (p.empty()) return p;
  std::filesystem::path path(p);
  return path.is_absolute() ? p : (std::filesystem::path(base) / path).lexically_normal().string();
}

// One per-vertex parameter: value="…" (kept in `value`), or min="…" max="…" map="image" (into `map`).
// `positive`: the values must be > 0 (density, mass, thickness); otherwise >= 0 (stiffness, damping).
void read_param(const ElementReader& r, const std::string& base, Real& value, ParamMapDesc& map, bool positive,
                const char* unit) {
  const std::string expected = std::string(positive ? "a positive number (" : "a number >= 0 (") + unit + ")";
  const bool has_map = r.has("map") || r.has("min") || r.has("max");
  if (!has_map) {
    value = positive ? r.positive("value", value, unit) : r.non_negative("value", value, unit);
    return;
  }
  if (r.has("value")) r.fail("give either value=\"…\" or min=\"…\" max=\"…\" map=\"image\", not both");
  if (!r.has("map") || !r.has("min") || !r.has("max"))
    r.fail("a mapped parameter needs all of min=\"…\" max=\"…\" map=\"image\"");
  map.min = r.number("min", 0, expected.c_str());
  map.max = r.number("max", 0, expected.c_str());
  if (positive ? !(map.min > 0) : !(map.min >= 0)) r.bad("min", expected);
  if (positive ? !(map.max > 0) : !(map.max >= 0)) r.bad("max", expected);
  if (map.min > map.max) r.fail("min=\"" + r.text("min") + "\" is above max=\"" + r.text("max") + "\"; expected min <= max");
  if (r.text("map").empty()) r.bad("map", "an image file (PNG, JPEG, TGA or BMP)");
  map.path = resolve(base, r.text("map"));
  map.line = r.line();
}

// The step count a frame needs, 1/(fps * timestep), must stay within the documented limit (core/limits.h).
void check_steps_per_frame(const ElementReader& r, const SimulationDesc& sim) {
  if (steps_per_frame_count(sim.fps, sim.timestep) > limits::max_steps_per_frame)
    r.fail("timestep=\"" + r.text("timestep", std::to_string(sim.timestep)) + "\" at fps=\"" +
           r.text("fps", std::to_string(sim.fps)) + "\" needs more than " +
           std::to_string(limits::max_steps_per_frame) + " steps a frame; expected 1/(fps * timestep) at most that");
}

void read_simulation(const std::string& file, const std::string& text, pugi::xml_node n, SimulationDesc& sim) {
  ElementReader r(file, text, n,
                  {"timestep", "fps", "startFrame", "endFrame", "integrator", "gravity", "collisionIterations",
                   "cgTolerance", "cgMaxIterations", "newtonIterations", "preconditioner", "contactFilter",
                   "broadPhase", "checkpointEvery", "clothCollision", "impactZoneIterations",
                   "stepSafety", "minTimestep"});
  sim.timestep_auto = r.text("timestep") == "auto";
  if (!sim.timestep_auto) sim.timestep = r.positive("timestep", sim.timestep, "s");
  sim.step_safety = r.positive("stepSafety", sim.step_safety, "fraction of the stable step");
  if (sim.step_safety > 1) r.bad("stepSafety", "a number in (0, 1] (fraction of the estimated stable step)");
  if (r.has("minTimestep")) sim.min_timestep = r.positive("minTimestep", sim.min_timestep, "s");
  sim.fps = r.positive("fps", sim.fps, "frames per second");
  check_steps_per_frame(r, sim);
  sim.start_frame = r.integer("startFrame", sim.start_frame);
  sim.end_frame = r.integer("endFrame", sim.end_frame);
  if (sim.start_frame < 0) r.bad("startFrame", "a frame number >= 0");
  if (sim.start_frame > sim.end_frame)
    r.fail("startFrame " + std::to_string(sim.start_frame) + " is after endFrame " + std::to_string(sim.end_frame) +
           "; expected startFrame <= endFrame");
  if (sim.end_frame > 9999) r.bad("endFrame", "a frame number <= 9999 (frames are named with 4 digits)");
  if (!enum_from_name(integrator_names, r.text("integrator", "symplectic"), sim.integrator))
    r.bad("integrator", "one of euler, symplectic, rk4, implicit");
  sim.gravity = r.vec3("gravity", sim.gravity);
  sim.collision_iterations = r.integer("collisionIterations", sim.collision_iterations);
  if (sim.collision_iterations < 0) r.bad("collisionIterations", "an integer >= 0");
  sim.impact_zone_iterations = r.integer("impactZoneIterations", sim.impact_zone_iterations);
  if (sim.impact_zone_iterations < 0) r.bad("impactZoneIterations", "an integer >= 0");
  sim.cg_tolerance = r.positive("cgTolerance", sim.cg_tolerance, "relative CG residual");
  if (sim.cg_tolerance >= 1) r.bad("cgTolerance", "a number in (0, 1) (relative CG residual)");
  sim.cg_max_iterations = r.integer("cgMaxIterations", sim.cg_max_iterations);
  if (sim.cg_max_iterations < 1) r.bad("cgMaxIterations", "an integer >= 1");
  sim.newton_iterations = r.integer("newtonIterations", sim.newton_iterations);
  if (sim.newton_iterations < 1) r.bad("newtonIterations", "an integer >= 1");
  if (r.has("preconditioner") && !enum_from_name(preconditioner_names, r.text("preconditioner"), sim.preconditioner))
    r.bad("preconditioner", "jacobi, multigrid or cholesky");
  sim.contact_filter = r.boolean("contactFilter", sim.contact_filter);
  if (!enum_from_name(broad_phase_names, r.text("broadPhase", "bvh"), sim.broad_phase))
    r.bad("broadPhase", "hash or bvh");
  sim.checkpoint_every = r.integer("checkpointEvery", sim.checkpoint_every);
  if (sim.checkpoint_every < 0) r.bad("checkpointEvery", "a number of frames >= 0 (0: no checkpoints)");
  sim.cloth_collision = r.boolean("clothCollision", sim.cloth_collision);
}

void read_forces(const std::string& file, const std::string& text, pugi::xml_node n, ForcesDesc& f) {
  ElementReader(file, text, n, {});
  std::set<std::string> seen;
  for (pugi::xml_node c : n.children()) {
    if (c.type() != pugi::node_element) continue;
    const std::string name = c.name();
    if (!seen.insert(name).second) ElementReader::unknown_element(file, text, c, "appears twice in <forces>; expected it once");
    if (name == "external") {
      ElementReader r(file, text, c, {"acceleration"});
      f.external_acceleration = r.vec3("acceleration", f.external_acceleration);
    } else if (name == "wind") {
      ElementReader r(file, text, c, {"velocity", "strength"});
      f.wind_velocity = r.vec3("velocity", f.wind_velocity);
      f.wind_strength = r.non_negative("strength", 1.0, "kg/(m^2 s)");
    } else if (name == "random") {
      ElementReader r(file, text, c,
                      {"amplitude", "seed", "negX", "posX", "negY", "posY", "negZ", "posZ", "period", "cellSize"});
      f.random.amplitude = r.non_negative("amplitude", 0, "m/s^2");
      f.random.period = r.positive("period", f.random.period, "s");
      f.random.cell_size = r.positive("cellSize", f.random.cell_size, "m");
      const std::string seed = r.text("seed", "1");
      std::uint64_t s = 0;
      auto [p, ec] = std::from_chars(seed.data(), seed.data() + seed.size(), s);
      if (seed.empty() || ec != std::errc() || p != seed.data() + seed.size()) r.bad("seed", "a non-negative integer");
      f.random.seed = s;
      const char* axes[6] = {"negX", "posX", "negY", "posY", "negZ", "posZ"};
      for (int k = 0; k < 6; ++k) f.random.allow[k] = r.boolean(axes[k], true);
    } else if (name == "airDamping") {
      ElementReader r(file, text, c, {"value"});
      f.air_damping = r.non_negative("value", 0, "1/s");
    } else {
      ElementReader::unknown_element(file, text, c, "unknown element in <forces>; expected external, wind, random or airDamping");
    }
  }
}

// translate, rotate and scale: the same attributes on cloths and colliders.
void read_transform(const ElementReader& r, TransformDesc& t) {
  t.translate = r.vec3("translate", t.translate);
  t.rotate = r.vec3("rotate", t.rotate);
  if (r.has("scale")) {
    const auto s = r.numbers("scale", 0, "one non-zero number or three \"sx sy sz\"");
    if (s.size() != 1 && s.size() != 3) r.bad("scale", "one non-zero number or three \"sx sy sz\"");
    t.scale = s.size() == 1 ? Vec3(s[0], s[0], s[0]) : Vec3(s[0], s[1], s[2]);
    if (t.scale.cwiseAbs().minCoeff() == 0) r.bad("scale", "one non-zero number or three \"sx sy sz\"");
  }
}

// <static obj|sequence>, <sphere>, <plane>: one collider each.
void read_collider(const std::string& file, const std::string& text, const std::string& base, pugi::xml_node n,
                   ColliderDesc& c, int index) {
  const std::string kind = n.name();
  auto reader = [&]() -> ElementReader {
    if (kind == "static")
      return ElementReader(file, text, n, {"name", "friction", "translate", "rotate", "scale", "obj", "sequence"});
    if (kind == "sphere")
      return ElementReader(file, text, n, {"name", "friction", "translate", "rotate", "scale", "center", "radius"});
    return ElementReader(file, text, n, {"name", "friction", "translate", "rotate", "scale", "point", "normal"});
  };
  const ElementReader r = reader();
  c.line = r.line();
  c.name = r.name_text("name", kind + std::to_string(index));
  c.friction = r.non_negative("friction", c.friction, "Coulomb coefficient");
  read_transform(r, c.transform);
  if (kind == "static") {
    if (r.has("obj") == r.has("sequence"))
      r.fail("expected exactly one of obj=\"mesh.obj\" or sequence=\"body.####.obj\"");
    if (r.has("obj")) {
      c.shape = ColliderShape::mesh;
      c.obj = resolve(base, r.text("obj"));
    } else {
      c.shape = ColliderShape::sequence;
      c.sequence = resolve(base, r.text("sequence"));
      if (std::filesystem::path(c.sequence).filename().string().find('#') == std::string::npos)
        r.bad("sequence", "a file pattern with a run of '#' for the frame number, e.g. body.####.obj");
    }
  } else if (kind == "sphere") {
    c.shape = ColliderShape::sphere;
    c.center = r.vec3("center", c.center);
    c.radius = r.positive("radius", c.radius, "m");
  } else {
    c.shape = ColliderShape::plane;
    c.point = r.vec3("point", c.point);
    c.normal = r.vec3("normal", c.normal);
    if (!(c.normal.norm() > 0)) r.bad("normal", "a non-zero vector \"x y z\"");
  }
}

// The vertices="..." attribute: 0-based vertex indices, appended to out.
void read_vertex_indices(const ElementReader& s, std::vector<Index>& out) {
  std::istringstream in(s.text("vertices"));
  std::string tok;
  while (in >> tok) {
    Index v = -1;
    auto [q, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
    if (ec != std::errc() || q != tok.data() + tok.size() || v < 0)
      s.bad("vertices", "vertex indices (integers >= 0, counted from 0)");
    out.push_back(v);
  }
}

// map="image" of <pins> and <attach>: the vertices above half grey (min 0, max 1).
void read_selection_map(const ElementReader& s, const std::string& base, ParamMapDesc& map) {
  if (s.text("map").empty()) s.bad("map", "an image file (PNG, JPEG, TGA or BMP)");
  map.path = resolve(base, s.text("map"));
  map.min = 0;
  map.max = 1;
  map.line = s.line();
}

void read_cloth(const std::string& file, const std::string& text, const std::string& base, pugi::xml_node n,
                ClothDesc& c, int index) {
  ElementReader r(file, text, n,
                  {"name", "obj", "grid", "size", "saveDir", "saveName", "texture", "translate", "rotate", "scale",
                   "friction", "restitution", "selfCollision", "clothCollision", "maxStrain", "weld", "sewSpeed", "rest", "bending"});
  c.line = r.line();
  c.name = r.name_text("name", "cloth" + std::to_string(index));
  if (r.has("obj") == r.has("grid")) r.fail("expected exactly one of obj=\"mesh.obj\" or grid=\"NX NY\"");
  if (r.has("obj")) {
    c.obj = resolve(base, r.text("obj"));
    if (r.has("size")) r.fail("size applies to grid cloths only; use scale for an OBJ");
  } else {
    const auto g = r.numbers("grid", 2, "two integers \"NX NY\", each >= 2");
    if (g[0] != std::floor(g[0]) || g[1] != std::floor(g[1]) || g[0] < 2 || g[1] < 2 ||
        g[0] * g[1] > double(limits::max_mesh_vertices))
      r.bad("grid", "two integers \"NX NY\", each >= 2, with NX * NY <= " + std::to_string(limits::max_mesh_vertices));
    c.grid_nx = int(g[0]);
    c.grid_ny = int(g[1]);
    if (r.has("size")) {
      const auto s = r.numbers("size", 2, "two positive numbers \"W H\" (m)");
      if (!(s[0] > 0 && s[1] > 0)) r.bad("size", "two positive numbers \"W H\" (m)");
      c.grid_w = s[0];
      c.grid_h = s[1];
    }
  }
  if (r.has("saveDir") && r.text("saveDir").empty()) r.bad("saveDir", "a folder path");
  c.save_dir = resolve(base, r.name_text("saveDir", "out"));
  c.save_name = r.name_text("saveName", c.name);
  if (c.save_name.empty() || c.save_name.find('/') != std::string::npos)
    r.bad("saveName", "a file name without '/'");
  c.texture = resolve(base, r.name_text("texture"));
  read_transform(r, c.transform);
  c.friction = r.non_negative("friction", c.friction, "Coulomb coefficient");
  c.restitution = r.non_negative("restitution", c.restitution, "0..1");
  if (c.restitution > 1) r.bad("restitution", "a number in [0, 1]");
  c.self_collision = r.boolean("selfCollision", c.self_collision);
  c.cloth_collision = r.boolean("clothCollision", c.cloth_collision);
  if (!enum_from_name(bending_names, r.text("bending", "springs"), c.bending))
    r.bad("bending", "springs or dihedral");
  if (r.has("maxStrain")) c.max_strain = r.positive("maxStrain", 0, "largest strain (|d| - rest)/rest, e.g. 0.1");
  c.weld = r.non_negative("weld", c.weld, "m");
  c.sew_speed = r.positive("sewSpeed", c.sew_speed, "m/s");
  if (r.has("rest") && r.text("rest").empty()) r.bad("rest", "an OBJ with the cloth's vertices and triangles");
  c.rest = resolve(base, r.text("rest"));

  bool has_density = false;
  std::set<std::string> seen;
  for (pugi::xml_node p : n.children()) {
    if (p.type() != pugi::node_element) continue;
    const std::string name = p.name();
    if (name != "pins" && !seen.insert(name).second)
      ElementReader::unknown_element(file, text, p, "appears twice in <cloth>; expected it once");
    if (name == "density") {
      ElementReader s(file, text, p, {"value", "min", "max", "map"});
      if (c.mass_per_vertex) s.fail("expected one of <density> or <mass>, not both");
      has_density = true;
      read_param(s, base, c.density, c.density_map, true, "kg/m^2");
    } else if (name == "mass") {
      ElementReader s(file, text, p, {"value", "min", "max", "map"});
      if (has_density) s.fail("expected one of <density> or <mass>, not both");
      if (!s.has("value") && !s.has("map")) s.fail("expected value=\"kg per vertex\" or min, max and map");
      c.mass_per_vertex = true;
      read_param(s, base, c.mass, c.mass_map, true, "kg per vertex");
    } else if (name == "stiffness") {
      ElementReader s(file, text, p, {"value", "shear", "bend", "bendModulus", "min", "max", "map"});
      read_param(s, base, c.stiffness, c.stiffness_map, false, "N/m");
      c.shear_scale = s.non_negative("shear", c.shear_scale, "factor of value");
      c.bend_scale = s.non_negative("bend", c.bend_scale, "factor of value");
      // Each attribute names the model it sets: a modulus the springs would ignore is an error, not a no-op.
      if (s.has("bendModulus") && c.bending != Bending::dihedral)
        s.fail("bendModulus applies to <cloth bending=\"dihedral\">; springs take bend=\"factor of value\"");
      if (s.has("bend") && c.bending == Bending::dihedral)
        s.fail("bend scales bend springs; a cloth with bending=\"dihedral\" takes bendModulus=\"N m\"");
      c.bend_modulus = s.non_negative("bendModulus", c.bend_modulus, "N m");
    } else if (name == "damping") {
      read_param(ElementReader(file, text, p, {"value", "min", "max", "map"}), base, c.damping, c.damping_map, false,
                 "N s/m");
    } else if (name == "thickness") {
      read_param(ElementReader(file, text, p, {"value", "min", "max", "map"}), base, c.thickness, c.thickness_map,
                 true, "m");
    } else if (name == "pins") {
      ElementReader s(file, text, p, {"vertices", "map"});
      if (s.has("map")) read_selection_map(s, base, c.pins_map);
      read_vertex_indices(s, c.pins);
    } else if (name == "stitch") {
      ElementReader s(file, text, p, {"vertices"});
      const std::size_t before = c.stitch_pairs.size();
      read_vertex_indices(s, c.stitch_pairs);
      if ((c.stitch_pairs.size() - before) % 2 != 0 || c.stitch_pairs.size() == before)
        s.bad("vertices", "vertex pairs \"i j  k l ...\" (an even count of 0-based indices)");
    } else if (name == "attach") {
      ElementReader s(file, text, p, {"collider", "vertices", "map"});
      AttachDesc& a = c.attach.emplace_back();
      a.line = s.line();
      a.collider = s.text("collider");
      if (a.collider.empty()) s.bad("collider", "the name of a <static> mesh collider");
      if (s.has("vertices") == s.has("map")) s.fail("expected exactly one of vertices=\"i j ...\" or map=\"image\"");
      if (s.has("map")) read_selection_map(s, base, a.map);
      read_vertex_indices(s, a.vertices);
    } else {
      ElementReader::unknown_element(file, text, p,
          "unknown element in <cloth>; expected density, mass, stiffness, damping, thickness, pins, stitch or attach");
    }
  }
}

}  // namespace

SceneDesc read_scene(const std::string& path) { return parse_scene(path, read_text_file(path, "a scene XML file")); }

SceneDesc parse_scene(const std::string& path, const std::string& text) {
  pugi::xml_document doc;
  const pugi::xml_parse_result res = doc.load_buffer(text.data(), text.size(), pugi::parse_default);
  if (!res)
    throw Error(path, ElementReader::line_of(text, res.offset),
                std::string("malformed XML (") + res.description() + "); expected a <scene> document");
  pugi::xml_node root = doc.document_element();
  if (std::string(root.name()) != "scene")
    ElementReader::unknown_element(path, text, root, "unknown root element; expected <scene>");
  // pugixml reads elements after the root as further roots; XML allows one.
  for (pugi::xml_node n = root.next_sibling(); n; n = n.next_sibling())
    if (n.type() == pugi::node_element)
      ElementReader::unknown_element(path, text, n, "a second root element; expected one <scene> document");

  SceneDesc scene;
  scene.path = path;
  scene.base_dir = std::filesystem::path(path).parent_path().string();
  ElementReader(path, text, root, {});
  bool have_simulation = false, have_forces = false;
  for (pugi::xml_node n : root.children()) {
    if (n.type() != pugi::node_element) continue;
    const std::string name = n.name();
    if (name == "simulation") {
      if (have_simulation) ElementReader::unknown_element(path, text, n, "appears twice; expected one <simulation>");
      have_simulation = true;
      read_simulation(path, text, n, scene.simulation);
    } else if (name == "forces") {
      if (have_forces) ElementReader::unknown_element(path, text, n, "appears twice; expected one <forces>");
      have_forces = true;
      read_forces(path, text, n, scene.forces);
    } else if (name == "cloth") {
      scene.cloths.emplace_back();
      read_cloth(path, text, scene.base_dir, n, scene.cloths.back(), int(scene.cloths.size()) - 1);
    } else if (name == "static" || name == "sphere" || name == "plane") {
      scene.colliders.emplace_back();
      read_collider(path, text, scene.base_dir, n, scene.colliders.back(), int(scene.colliders.size()) - 1);
    } else {
      ElementReader::unknown_element(path, text, n,
                                     "unknown element in <scene>; expected simulation, forces, cloth, static, sphere "
                                     "or plane");
    }
  }
  if (scene.cloths.empty()) throw Error(path, "no <cloth> element; expected at least one cloth");
  std::set<std::string> outputs;
  for (const ClothDesc& c : scene.cloths)
    if (!outputs.insert(normalised_path(c.save_dir + "/" + c.save_name)).second)
      throw Error(path, c.line, "cloth '" + c.name + "' writes to the same files as another (saveDir + saveName); "
                                "expected distinct output names");
  return scene;
}

}  // namespace clothsim::io
