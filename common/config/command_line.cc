#include "common/config/command_line.h"

#include "common/config/config_error.h"

#include <stdexcept>

namespace srics::config {

const std::string& ArgumentReader::Value() {
  if (at_ + 1 >= args_.size()) throw std::invalid_argument(arg() + " needs a value");
  return args_[++at_];
}

CommandLine ParseCommandLine(int argc, char** argv, const std::string& usage) {
  CommandLine cl;
  auto fail = [&](const std::string& why) { throw ConfigError(why + "\nusage: " + usage); };
  ArgumentReader args(argc, argv);
  auto value = [&]() -> const std::string& {
    try {
      return args.Value();
    } catch (const std::invalid_argument& e) {
      fail(e.what());
      throw;
    }
  };
  while (args.Next()) {
    const std::string& arg = args.arg();
    if (arg == "--set") {
      cl.overrides.push_back(value());
    } else if (arg == "--run-dir") {
      cl.run_dir = value();
    } else if (arg == "--log-level") {
      cl.log_level = value();
    } else if (arg == "--id") {
      const std::string& text = value();
      try {
        size_t used = 0;
        const int id = std::stoi(text, &used);
        if (used != text.size() || id < 0) throw std::invalid_argument(text);
        cl.id = id;
      } catch (const std::exception&) {
        fail("--id: expected a non-negative integer, got '" + text + "'");
      }
    } else if (arg.rfind("--", 0) == 0) {
      fail("unknown option " + arg);
    } else if (cl.config_path.empty()) {
      cl.config_path = arg;
    } else {
      cl.positional.push_back(arg);
    }
  }
  if (cl.config_path.empty()) fail("missing CONFIG");
  return cl;
}

}  // namespace srics::config
