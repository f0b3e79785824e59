#pragma once
// How long-running processes use the C heap.

namespace srics::process {

// Makes glibc serve every block of 1 MiB or more by its own mmap, unmapped when freed, for the
// rest of the process. By default glibc raises that threshold to the size of the largest block
// freed so far (up to 32 MiB), after which big temporary buffers (a checkpoint's serialized
// state: twice its file size) come from the heap, and freed heap blocks below live ones stay
// resident: a learner's RSS stepped up by ~11 MiB for a whole checkpoint period in the soak.
// The networks' hot paths reuse their buffers (nn::Tape, one tape per pass of an update), so
// they do not pay an mmap per use; the heap's top is kept up to 16 MiB, so an update's smaller
// temporaries do not go back to the kernel and fault in again each time.
// Called by every role process and the launcher at start; a no-op off glibc.
void ReturnBigBlocksToTheSystem();

}  // namespace srics::process
