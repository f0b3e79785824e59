// A small thread-local in a library loaded with dlopen: each thread that touches it gets a
// dynamic TLS block from malloc (see leak_check_test.cc).
thread_local char probe_bytes[8];

extern "C" char* TouchProbe() {
  probe_bytes[0] = 1;
  return probe_bytes;
}
