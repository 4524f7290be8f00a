#include "io/cloth_maps.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/error.h"

namespace clothsim::io {

std::vector<Real> vertex_grey(const GreyImage& image, const MeshData& mesh) {
  // Distinct (vertex, uv) pairs: a vertex inside a UV island counts its one UV once, however many corners.
  std::vector<std::pair<Index, Index>> pairs;
  pairs.reserve(mesh.tri_index.size());
  for (std::size_t k = 0; k < mesh.tri_index.size(); ++k) pairs.emplace_back(mesh.tri_index[k], mesh.tri_uv[k]);
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());

  std::vector<Real> grey(mesh.vertex_count(), 0.0);
  for (std::size_t b = 0; b < pairs.size();) {
    std::size_t e = b;
    Real sum = 0;
    bool same = true;
    const Real first = sample_grey(image, mesh.uvs[pairs[b].second]);
    for (; e < pairs.size() && pairs[e].first == pairs[b].first; ++e) {
      const Real g = sample_grey(image, mesh.uvs[pairs[e].second]);
      sum += g;
      same = same && g == first;
    }
    // Equal samples give that sample exactly, so a seam on a constant map matches the scalar bit for bit.
    grey[pairs[b].first] = same ? first : sum / Real(e - b);
    b = e;
  }
  return grey;
}

VertexParams sample_cloth_maps(const SceneDesc& scene, const ClothDesc& cloth, const MeshData& mesh) {
  VertexParams out;
  auto sample = [&](const ParamMapDesc& map, const char* element) {
    std::vector<Real> values;
    if (!map.mapped()) return values;
    const std::string attribute = "cloth '" + cloth.name + "' <" + element + " map=\"" + map.path + "\">: ";
    if (mesh.uvs.empty() || mesh.tri_uv.size() != mesh.tri_index.size())
      throw Error(scene.path, map.line,
                  attribute + "the mesh " + (mesh.source.empty() ? std::string("") : "'" + mesh.source + "' ") +
                      "has no texture coordinates; expected 'vt' on every face corner for a map");
    GreyImage image;
    try {
      image = read_grey_image(map.path);
    } catch (const Error& e) {
      throw Error(scene.path, map.line, attribute + e.what());
    }
    values = vertex_grey(image, mesh);
    // std::lerp is exact at both ends: a white map gives max bit for bit.
    for (Real& v : values) v = std::lerp(map.min, map.max, v);
    return values;
  };
  out.density = sample(cloth.density_map, "density");
  out.mass = sample(cloth.mass_map, "mass");
  out.stiffness = sample(cloth.stiffness_map, "stiffness");
  out.damping = sample(cloth.damping_map, "damping");
  out.thickness = sample(cloth.thickness_map, "thickness");
  // Pins and attachments select the vertices above half grey.
  auto above_half = [&](const ParamMapDesc& map, const char* element) {
    const std::vector<Real> grey = sample(map, element);
    std::vector<char> on(grey.size());
    for (std::size_t i = 0; i < grey.size(); ++i) on[i] = grey[i] > 0.5;
    return on;
  };
  out.pinned = above_half(cloth.pins_map, "pins");
  for (const AttachDesc& a : cloth.attach) out.attached.push_back(above_half(a.map, "attach"));
  return out;
}

}  // namespace clothsim::io
