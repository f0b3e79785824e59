#pragma once
// How long-running processes use the C heap: one policy for every process, set once.

#include <cstddef>

namespace srics::process {

// Blocks of this size or more are mapped on their own (SetUpHeap).
inline constexpr size_t kHeapMmapThreshold = size_t{8} << 20;

// glibc's heap as every role process, the launcher and the DDS participant want it (idempotent;
// a no-op off glibc):
//  - a block of 8 MiB or more that the heap's free top cannot hold gets its own mmap, unmapped
//    when freed: a checkpoint's serialized state (twice its file size, briefly) goes back to
//    the system at once instead of staying resident for a whole checkpoint period (the soak saw
//    a learner's RSS step up by ~11 MiB);
//  - smaller blocks come from the heap, which keeps up to 64 MiB free at its top and grows by
//    16 MiB: 5 MiB policy weights received by Cyclone's thread, and an update's buffers and
//    temporaries at batch 2048 (up to ~3 MiB), are reused instead of being mapped, faulted in
//    page by page and unmapped each time (8% of the receive thread; ~30% of a batch-2048 run).
// Before 2026-12-06 the roles set a 1 MiB threshold and the participant, constructed later,
// 32 MiB: which one held depended on the order of construction.
void SetUpHeap();

}  // namespace srics::process
