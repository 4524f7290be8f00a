// clothsim info MESH.obj [--json]: counts and topology checks of a mesh, and how long they took.
#include <chrono>
#include <cstdio>

#include "core/topology.h"
#include "io/json_writer.h"
#include "io/obj_reader.h"
#include "tools/cli_args.h"
#include "tools/commands.h"

namespace clothsim::cli {

int cmd_info(int argc, char** argv) {
  const Args args = parse_args(argc, argv, {}, {"--json"});
  if (args.help) {
    std::puts("usage: clothsim info MESH.obj [--json]\n"
              "Vertex, triangle, unique-edge, edge-spring and bend-spring counts, connected pieces, boundary and\n"
              "non-manifold edges, degenerate triangles, and the seconds to load and to build the topology.");
    return exit_ok;
  }
  if (args.positional.size() != 1) throw UsageError("expected one mesh file");
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  const MeshData mesh = io::read_obj(args.positional[0], io::MeshCheck::lenient);
  const auto t1 = clock::now();
  const Topology topo = build_topology(mesh);
  const auto t2 = clock::now();
  const double load = std::chrono::duration<double>(t1 - t0).count();
  const double topology = std::chrono::duration<double>(t2 - t1).count();

  if (args.has("--json")) {
    io::JsonWriter j;
    j.begin_object()
        .field("vertices", mesh.vertex_count())
        .field("triangles", mesh.triangle_count())
        .field("edges", topo.edge_count())
        .field("edge_springs", topo.edge_count())
        .field("bend_springs", topo.bend_count())
        .field("pieces", topo.pieces)
        .field("boundary_edges", topo.boundary_edges)
        .field("nonmanifold_edges", topo.nonmanifold_edges)
        .field("degenerate_triangles", topo.degenerate_triangles)
        .field("unused_vertices", topo.unused_vertices)
        .field("polygons_triangulated", mesh.polygons_triangulated)
        .field("stitches", mesh.stitch_count())
        .field("seams", mesh.seam_count)
        .field("has_uvs", !mesh.uvs.empty())
        .field("load_seconds", load)
        .field("topology_seconds", topology)
        .end_object();
    std::puts(j.str().c_str());
  } else {
    std::printf("%s\n", args.positional[0].c_str());
    std::printf("  vertices              %d\n", mesh.vertex_count());
    std::printf("  triangles             %d%s\n", mesh.triangle_count(),
                mesh.polygons_triangulated ? " (polygons split into fans)" : "");
    std::printf("  unique edges          %d\n", topo.edge_count());
    std::printf("  edge springs          %d\n", topo.edge_count());
    std::printf("  bend springs          %d\n", topo.bend_count());
    std::printf("  pieces                %d\n", topo.pieces);
    std::printf("  boundary edges        %d\n", topo.boundary_edges);
    std::printf("  non-manifold edges    %d (no bend spring)\n", topo.nonmanifold_edges);
    std::printf("  degenerate triangles  %d\n", topo.degenerate_triangles);
    std::printf("  unused vertices       %d\n", topo.unused_vertices);
    std::printf("  stitches              %d (in %d seams)\n", mesh.stitch_count(), mesh.seam_count);
    std::printf("  UVs                   %s\n", mesh.uvs.empty() ? "no" : "yes");
    std::printf("  load                  %.3f s\n", load);
    std::printf("  topology              %.3f s\n", topology);
  }
  return exit_ok;
}

}  // namespace clothsim::cli
