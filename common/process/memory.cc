#include "common/process/memory.h"

#include <cstdlib>  // defines __GLIBC__ on glibc
#include <mutex>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace srics::process {

void SetUpHeap() {
#ifdef __GLIBC__
  static std::once_flag once;
  std::call_once(once, [] {
    // a fixed mmap threshold also fixes the trim threshold (no dynamic adjustment): set both
    mallopt(M_MMAP_THRESHOLD, static_cast<int>(kHeapMmapThreshold));
    mallopt(M_TRIM_THRESHOLD, 64 << 20);
    mallopt(M_TOP_PAD, 16 << 20);
  });
#endif
}

}  // namespace srics::process
