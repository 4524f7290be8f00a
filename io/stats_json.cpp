#include "io/stats_json.h"

#include "io/atomic_file.h"
#include "io/json_writer.h"

namespace clothsim::io {

std::string format_stats(const Model& m, const SimOptions& o, const RunStats& s) {
  JsonWriter j;
  j.begin_object();
  j.field("scene", std::string_view(s.scene)).field("status", std::string_view(s.status));
  j.field("particles", m.particle_count).field("triangles", m.tri_count);
  j.key("springs").begin_object();
  for (int k = 0; k < spring_kind_count; ++k) j.field(spring_kind_names[k], m.spring_kind_total[k]);
  j.field("total", m.spring_count).end_object();
  Index pieces = 0;
  for (const ClothInfo& c : m.cloths) pieces += c.pieces;
  j.field("pieces", pieces).field("cloths", int(m.cloths.size())).field("pinned", int(m.pinned.size()));
  j.field("integrator", std::string_view(integrator_name(o.integrator)));
  j.field("dt", o.dt).field("steps_per_frame", o.steps_per_frame).field("steps", s.steps);
  j.field("timestep", std::string_view(o.auto_step ? "auto" : "fixed"));
  j.field("force_evaluations", s.force_evaluations).field("threads", s.threads);
  if (o.integrator == Integrator::implicit) {
    j.field("preconditioner", std::string_view(preconditioner_name(o.solver.preconditioner)));
    if (!s.blas_kernel.empty())
      j.field("blas_kernel", std::string_view(s.blas_kernel))
          .field("blas_kernel_chosen_by", std::string_view(s.blas_kernel_chosen_by));
    if (s.cholesky_pieces > 0) j.field("cholesky_pieces", s.cholesky_pieces);
    j.field("cg_iterations", s.cg_iterations).field("implicit_failed_steps", s.implicit_failed_steps);
  }
  if (m.strain_limited) j.field("strain_limit_iterations", s.strain_limit_iterations);
  // The other integrators' steps fail only where the strain limit stops unmet (docs/scene-format.md).
  if (m.strain_limited && o.integrator != Integrator::implicit) j.field("failed_steps", s.implicit_failed_steps);
  j.field("frames_written", s.frames_written).field("wall_seconds", s.wall_seconds);
  j.key("phases").begin_object()
      .field("load", s.load_seconds)
      .field("topology", s.topology_seconds)
      .field("forces", s.forces_seconds)
      .field("integrate", s.integrate_seconds)
      .field("write", s.write_seconds);
  if (m.collision.enabled) j.field("collide", s.collide_seconds);
  j.end_object();
  j.key("phases_cpu").begin_object()
      .field("load", s.load_cpu_seconds)
      .field("topology", s.topology_cpu_seconds)
      .end_object();
  j.field("peak_rss_bytes", s.peak_rss_bytes);
  j.key("frames").begin_array();
  for (const FrameStats& f : s.frames) {
    j.begin_object().field("frame", f.frame).field("max_strain", f.max_strain).field("kinetic_energy", f.kinetic_energy);
    if (m.strain_limited) j.field("strain_excess", f.strain_excess);
    j.field("steps", f.steps.taken).field("steps_rejected", f.steps.rejected);
    j.field("step_min", f.steps.smallest).field("step_max", f.steps.largest);
    if (o.integrator == Integrator::implicit) {
      j.key("cg_iterations").begin_array();
      for (int it : f.cg_iterations) j.value(it);
      j.end_array().key("cg_residual").begin_array();
      for (Real r : f.cg_residual) j.value(r);
      j.end_array().field("failed_steps", f.implicit_failed);
      if (o.solver.preconditioner == Preconditioner::cholesky) j.field("factorizations", f.factorizations);
    }
    if (m.collision.enabled) {
      j.field("contacts", f.contacts).field("penetrations", f.penetrations);
      if (m.strain_limited) j.field("guarded", f.guarded);
      if (m.collision.impact_zones()) {
        j.key("impact_zones").begin_object()
            .field("steps", f.zones.steps).field("passes", f.zones.passes).field("zones", f.zones.zones)
            .field("vertices", f.zones.zone_nodes).field("largest", f.zones.largest)
            .field("unresolved", f.zones.unresolved)
            .end_object();
      }
      j.key("collider_distance").begin_object();
      for (std::size_t c = 0; c < f.collider_distance.size(); ++c)
        j.field(m.collision.colliders[c].name, f.collider_distance[c]);
      j.end_object();
    }
    j.end_object();
  }
  j.end_array().end_object();
  return j.str() + "\n";
}

void write_stats(const std::string& path, const Model& model, const SimOptions& options, const RunStats& stats) {
  write_file_atomic(path, format_stats(model, options, stats));
}

}  // namespace clothsim::io
