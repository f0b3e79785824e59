// libFuzzer harness: a checkpoint file read from bytes (nn::ReadCheckpoint through a temporary
// file, as the processes read theirs), then its "parameters" section loaded into a small layer
// (nn::LoadSection). Each input is read twice: as it is, and with its last 8 bytes replaced by
// the FNV-1a checksum of the rest, so that the sections behind a matching checksum are reached
// too. A refused file throws CheckpointError; a crash, a sanitizer report or a hang is a finding.
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/nn/modules.h"
#include "common/nn/serialize.h"
#include "tests/fuzz/fuzz_input.h"

namespace {

using namespace srics::nn;

struct Layer {
  Rng rng{7};
  Linear<float> linear{"policy", 3, 2, true, rng};
  ParameterList<float> params;
  Layer() { linear.Parameters(params); }
};

// in memory when there is /dev/shm (35 times the runs of a file on disk); removed at exit
// (a plain array: a static std::string would be destroyed before the atexit handler runs)
char temp_path[128];

std::string TempPath() {
  if (temp_path[0] == '\0') {
    std::snprintf(temp_path, sizeof temp_path, "%s/srics-fuzz-checkpoint-%d.ckpt",
                  std::filesystem::is_directory("/dev/shm") ? "/dev/shm" : "/tmp", static_cast<int>(getpid()));
    std::atexit([] { std::remove(temp_path); });
  }
  return temp_path;
}

void ReadFrom(const std::string& bytes, Layer& layer) {
  {
    std::ofstream out(TempPath(), std::ios::binary | std::ios::trunc);
    out << bytes;
  }
  try {
    const auto sections = ReadCheckpoint(TempPath());
    LoadSection(FindSection(sections, "parameters", TempPath()), layer.params, TempPath());
  } catch (const CheckpointError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = srics::fuzz::SeedDir()) {
    Layer layer;
    srics::fuzz::WriteSeed(dir, "parameters",
                           CheckpointBytes({{"parameters", SignatureString(layer.params), Flatten(layer.params), {}}}));
    ByteWriter w;
    w.Put<uint64_t>(42);
    w.PutVector(std::vector<float>{1.0f, 2.0f});
    w.PutString("state");
    srics::fuzz::WriteSeed(dir, "sections",
                           CheckpointBytes({{"parameters", SignatureString(layer.params), Flatten(layer.params), {}},
                                            {"learner", "", {}, w.Take()}}));
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Layer layer;
  std::string bytes(reinterpret_cast<const char*>(data), size);
  ReadFrom(bytes, layer);
  if (bytes.size() >= 8) {
    const uint64_t sum = Fnv1a(bytes.data(), bytes.size() - 8);
    std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
    ReadFrom(bytes, layer);
  }
  return 0;
}
