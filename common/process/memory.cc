#include "common/process/memory.h"

#include <cstdlib>  // defines __GLIBC__ on glibc

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace srics::process {

void ReturnBigBlocksToTheSystem() {
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  // a fixed M_MMAP_THRESHOLD also fixes the trim threshold (128 KiB by default): the heap's top
  // would go back to the kernel after every update's temporaries are freed, and come back page
  // fault by page fault in the next one
  mallopt(M_TRIM_THRESHOLD, 16 << 20);
#endif
}

}  // namespace srics::process
