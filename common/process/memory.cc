#include "common/process/memory.h"

#include <cstdlib>  // defines __GLIBC__ on glibc

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace srics::process {

void ReturnBigBlocksToTheSystem() {
#ifdef __GLIBC__
  // a fixed M_MMAP_THRESHOLD also turns off the dynamic adjustment of the trim threshold
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
#endif
}

}  // namespace srics::process
