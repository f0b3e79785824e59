#pragma once
// The one exception type of the config library. Its message always names the file, the key
// path and what was expected, e.g. "run.yaml:12: env.num_pucks: expected an integer in
// [1, 6], got 9".

#include <stdexcept>
#include <string>

namespace srics::config {

class ConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace srics::config
