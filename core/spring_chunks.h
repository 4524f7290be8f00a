#pragma once
// The blocked spring layout's schedule, built once with the model. Springs are cut into chunks of consecutive
// indices; each chunk's particles span [lo, hi]. Chunks go greedily, in index order, into the first pass where
// they overlap no other chunk's span, so within a pass every particle is written by at most one chunk. A chunk
// is summed sequentially, and passes run in order: each particle's forces add up in one fixed order, whatever
// the thread count. Needs spring order to follow particle order (grids, and meshes whose vertex order is local);
// otherwise spans overlap, passes multiply, and the model keeps the two_phase layout.
#include "core/model.h"

namespace clothsim {

inline constexpr Index spring_chunk_size = 8192;  // springs per chunk (bench/: enough chunks per pass to share)
inline constexpr Index spring_max_passes = 8;     // beyond this the spring order has no locality to use

// Fills model.spring_chunk_offset/pass_offset/pass_chunk and returns true, or leaves them empty and returns
// false when more than max_passes passes would be needed.
bool build_spring_chunks(Model& model, Index chunk_size = spring_chunk_size, Index max_passes = spring_max_passes);

}  // namespace clothsim
