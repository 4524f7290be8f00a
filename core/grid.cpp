#include "core/grid.h"

#include <algorithm>

namespace clothsim {

MeshData make_grid_mesh(int nx, int ny, Real width, Real height) {
  MeshData mesh;
  mesh.positions.reserve(std::size_t(nx) * ny);
  mesh.uvs.reserve(std::size_t(nx) * ny);
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      const Real u = Real(i) / (nx - 1), v = Real(j) / (ny - 1);
      mesh.positions.push_back(Vec3(-0.5 * width + width * u, 0, -0.5 * height + height * v));
      mesh.uvs.push_back(Vec2(u, v));
    }
  }
  // Corners ordered so the normals point along +Y. Reserved: growing by doubling would hold a large array twice.
  mesh.tri_index.reserve(6 * std::size_t(nx - 1) * (ny - 1));
  for (int j = 0; j + 1 < ny; ++j) {
    for (int i = 0; i + 1 < nx; ++i) {
      const Index a = j * nx + i, b = a + 1, c = a + nx, d = c + 1;
      for (Index k : {a, c, b, b, c, d}) mesh.tri_index.push_back(k);
    }
  }
  mesh.tri_uv = mesh.tri_index;
  return mesh;
}

SpringList make_grid_springs(int nx, int ny) {
  SpringList s;
  const std::size_t X = nx, Y = ny;  // structural, shear, flex
  const std::size_t count = (X - 1) * Y + X * (Y - 1) + 2 * (X - 1) * (Y - 1) + std::size_t(std::max(nx - 2, 0)) * Y +
                            X * std::size_t(std::max(ny - 2, 0));
  s.a.reserve(count);
  s.b.reserve(count);
  s.kind.reserve(count);
  auto id = [nx](int i, int j) { return Index(j * nx + i); };
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      if (i + 1 < nx) s.add(id(i, j), id(i + 1, j), SpringKind::structural);
      if (j + 1 < ny) s.add(id(i, j), id(i, j + 1), SpringKind::structural);
      if (i + 1 < nx && j + 1 < ny) {
        s.add(id(i, j), id(i + 1, j + 1), SpringKind::shear);
        s.add(id(i + 1, j), id(i, j + 1), SpringKind::shear);
      }
      if (i + 2 < nx) s.add(id(i, j), id(i + 2, j), SpringKind::flex);
      if (j + 2 < ny) s.add(id(i, j), id(i, j + 2), SpringKind::flex);
    }
  return s;
}

}  // namespace clothsim
