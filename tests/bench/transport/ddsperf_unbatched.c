/* Preloaded into ddsperf by the transport bench (LD_PRELOAD) for its unbatched reference:
   ddsperf switches Cyclone's write batching on unconditionally and has no option to keep it
   off, so this replaces the switch with one that does nothing. */
#include <stdbool.h>

void dds_write_set_batch(bool enable) { (void)enable; }
