#pragma once
// The blocked spring layout's schedule, built once with the model. Springs are cut into chunks of consecutive
// indices; each chunk's particles span [lo, hi]. Chunks go greedily, in index order, into the first pass where
// they overlap no other chunk's span, so within a pass every particle is written by at most one chunk. A chunk
// is summed sequentially, and passes run in order: each particle's forces add up in one fixed order, whatever
// the thread count. Needs spring order to follow particle order (grids, and meshes whose vertex order is local);
// otherwise spans overlap, passes multiply, and the model keeps the gather layout.
//
// Each particle also gets the chunk that opens it (the first, in pass order, whose span holds it: it zeroes
// the particle's force) and the chunk that closes it (the last: after it, no spring reads or adds to the
// particle, so the integrator's per-particle update can run there, while the particle is still in cache).
// Particles in no span are opened and closed by a final step after the passes. Within its closing chunk a
// particle is closed after the first block of spring_block_size springs past which no spring of the chunk
// touches it (model.spring_block_close), so the update reads what the springs just wrote.
#include "core/model.h"

namespace clothsim {

// The automatic chunk size: spring_count / spring_chunks_wanted rounded down to a power of two, within
// [spring_chunk_min, spring_chunk_max]. Large chunks keep a grid to two passes and stream each particle about
// once per evaluation (a chunk's neighbours share only its edges); 64 chunks leave work for many cores. It
// depends on the model only, never on the thread count (docs/performance.md, "Spring-force layouts").
inline constexpr Index spring_block_size = 64;  // springs the kernel evaluates as one vector batch
inline constexpr Index spring_chunk_min = 4096, spring_chunk_max = 65536;
inline constexpr Index spring_chunks_wanted = 64;
inline constexpr Index spring_max_passes = 8;  // beyond this the spring order has no locality to use

// Fills model.spring_chunk_* and spring_pass_* and returns true, or leaves them empty and returns false when
// more than max_passes passes would be needed. chunk_size 0 picks the size as described above; any size is
// rounded up to a multiple of spring_block_size.
bool build_spring_chunks(Model& model, Index chunk_size = 0, Index max_passes = spring_max_passes);

}  // namespace clothsim
