// srics_dynamic_tls_threads PROBE_LIBRARY THREADS
// Loads PROBE_LIBRARY, starts THREADS threads that each touch its thread-local and stay alive,
// and exits 0 while they are: LeakSanitizer's check at exit then walks every thread's
// dynamic TLS (leak_check_test.cc).
#include <dlfcn.h>
#include <unistd.h>

#include <barrier>
#include <cstdio>
#include <cstdlib>
#include <thread>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s PROBE_LIBRARY THREADS\n", argv[0]);
    return 2;
  }
  void* library = dlopen(argv[1], RTLD_NOW);
  if (!library) {
    std::fprintf(stderr, "dlopen %s: %s\n", argv[1], dlerror());
    return 2;
  }
  using Touch = char* (*)();
  const auto touch = reinterpret_cast<Touch>(dlsym(library, "TouchProbe"));
  if (!touch) {
    std::fprintf(stderr, "no TouchProbe in %s\n", argv[1]);
    return 2;
  }
  const int count = std::atoi(argv[2]);
  std::barrier all_touched(count + 1);
  std::vector<std::thread> threads;
  for (int i = 0; i < count; ++i)
    threads.emplace_back([&] {
      touch();
      all_touched.arrive_and_wait();
      pause();  // alive until the process exits
    });
  all_touched.arrive_and_wait();
  std::printf("%d threads touched the probe\n", count);
  std::fflush(stdout);  // before the leak check, which may abort
  // exit, not return: the leak check runs at exit, and main's joinable threads must not be
  // destroyed (std::terminate)
  std::exit(0);
}
