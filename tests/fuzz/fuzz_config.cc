// libFuzzer harness: a run configuration parsed and validated from YAML text
// (config::ParseConfig, what LoadConfig runs on a file's text). A refused text throws; a crash,
// a sanitizer report or a hang is a finding.
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <string>

#include "common/config/config.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = srics::fuzz::SeedDir()) {
    // shipped configurations merged (extends resolved: the text stands alone), and a small one
    for (const char* name : {"default.yaml", "rearrange-3.yaml", "relational-4.yaml"}) {
      const auto config = srics::config::LoadConfig(std::string(SRICS_SOURCE_DIR "/deploy/configs/") + name);
      srics::fuzz::WriteSeed(dir, name, config.effective_yaml);
    }
    srics::fuzz::WriteSeed(dir, "small.yaml",
                           "transport:\n  run_id: fuzz\n  domain_id: 3\nrun:\n  total_env_steps: 1000\n"
                           "env:\n  objects: [1, 2]\nlearner:\n  batch_size: 32\n");
    // documents that must be refused at once (issue 39): eight levels of nine aliases each, and
    // nesting 100 deep; the launcher's test starts `srics run` on the first
    std::string bomb = "a0: &a0 [x, x, x, x, x, x, x, x, x]\n";
    for (int level = 1; level <= 8; ++level) {
      bomb += "a" + std::to_string(level) + ": &a" + std::to_string(level) + " [";
      for (int i = 0; i < 9; ++i) bomb += (i ? ",*a" : "*a") + std::to_string(level - 1);
      bomb += "]\n";
    }
    srics::fuzz::WriteSeed(dir, "anchor-bomb.yaml", bomb + "run:\n  name: bomb\n");
    srics::fuzz::WriteSeed(dir, "deep.yaml", "run: " + std::string(100, '[') + std::string(100, ']') + "\n");
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    srics::config::ParseConfig(text, "fuzz.yaml");
  } catch (const std::exception&) {  // refused: ConfigError, or yaml-cpp's own for malformed YAML
  }
  return 0;
}
