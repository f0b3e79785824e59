// libFuzzer harness: graph.json parsed and validated (graph_file::GraphFromJson, what
// LoadGraph runs on a file's text). A refused text throws std::runtime_error or
// std::invalid_argument; a crash, a sanitizer report or a hang is a finding.
#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/graph_file/graph_file.h"
#include "tests/fuzz/fuzz_input.h"

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  if (const char* dir = srics::fuzz::SeedDir()) {
    using srics::graph_file::AggregateGraph;
    std::vector<double> scores = {0, 0.5, 0.4, 0, 0, 0.3, 0, 0.01, 0};
    auto g = AggregateGraph(3, scores, 0.06, 0);
    g.version = 4;
    g.entity_kinds = {0, 1, 2};
    g.action_correlation = {0.9, 0.1, 0.05};
    srics::fuzz::WriteSeed(dir, "three", srics::graph_file::GraphToJson(g));
    auto star = AggregateGraph(2, {0, 0.9, 0, 0}, 0.06, 0);
    star.version = 1;
    star.readout = "cut";
    srics::fuzz::WriteSeed(dir, "two", srics::graph_file::GraphToJson(star));
    std::exit(0);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    srics::graph_file::GraphFromJson(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}
