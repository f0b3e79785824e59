#include "common/cli/cli.h"

#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <limits>

namespace srics::cli {

const char* Version() { return SRICS_VERSION; }

namespace {

// "srics run" for the subcommand run of srics.
std::string FullName(const CLI::App* app) {
  std::string name;
  for (; app != nullptr; app = app->get_parent()) name = app->get_name() + (name.empty() ? "" : " " + name);
  return name;
}

}  // namespace

void Configure(CLI::App& app) {
  app.set_version_flag("--version", FullName(&app) + " " + Version(), "print the version and exit");
  app.get_formatter()->column_width(28);
  app.option_defaults()->always_capture_default();
}

std::string CommandName(const CLI::App& app) {
  // the innermost subcommand given on the command line
  const CLI::App* at = &app;
  for (;;) {
    const std::vector<const CLI::App*> given = at->get_subcommands([](const CLI::App*) { return true; });
    const CLI::App* next = nullptr;
    for (const CLI::App* sub : given)
      if (sub->parsed()) next = sub;
    if (next == nullptr) break;
    at = next;
  }
  return FullName(at);
}

int UsageError(const std::string& program, const std::string& message) {
  std::cerr << program << ": " << message << "\nRun with --help for more information.\n";
  return kExitUsage;
}

namespace {

// What is wrong with the command line. CLI11 reports a missing required argument before an
// unknown one, but a misspelt option ("--method") is the cause of the missing one
// ("--methods is required"): the unknown argument comes first.
std::string Message(const CLI::App& app, const CLI::ParseError& e) {
  if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
    const std::vector<std::string> extras = app.remaining(true);
    if (!extras.empty()) return "The following argument was not expected: " + extras.front();
  }
  return e.what();
}

}  // namespace

std::optional<int> Parse(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help, --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    return UsageError(CommandName(app), Message(app, e));
  }
  return std::nullopt;
}

void ParseOrThrow(CLI::App& app, const std::vector<std::string>& args) {
  std::vector<std::string> reversed(args.rbegin(), args.rend());  // CLI11 takes them from the back
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    throw std::invalid_argument(Message(app, e));
  }
}

namespace {

std::string Shown(double value) {
  std::string text = std::to_string(value);
  text.erase(text.find_last_not_of('0') + 1);
  if (!text.empty() && text.back() == '.') text.pop_back();
  return text;
}

}  // namespace

std::string InstalledDataDir() {
  std::error_code error;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return "";
  const std::filesystem::path data = exe.parent_path().parent_path() / "share" / "srics-dds";
  return std::filesystem::is_directory(data / "configs", error) ? data.string() : "";
}

std::string FindConfig(const std::string& given) {
  std::error_code error;
  if (given.empty() || std::filesystem::exists(given, error)) return given;
  const std::string data = InstalledDataDir();
  if (data.empty() || std::filesystem::path(given).is_absolute()) return given;
  std::string name = given;
  for (const char* prefix : {"./", "deploy/configs/", "configs/"})
    if (name.rfind(prefix, 0) == 0) name = name.substr(std::string(prefix).size());
  const std::filesystem::path installed = std::filesystem::path(data) / "configs" / name;
  return std::filesystem::is_regular_file(installed, error) ? installed.string() : given;
}

CLI::Option* AddSetOption(CLI::App& app, std::vector<std::string>* overrides, const std::string& help) {
  return app.add_option("--set", *overrides, help)->allow_extra_args(false)->type_name("K=V")->default_str("");
}

CLI::Validator InstalledConfig() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        text = FindConfig(text);
        return "";
      },
      "");
}

CLI::Validator Integer(int64_t min, int64_t max) {
  // no upper bound worth naming at the int limit
  const bool unbounded = max >= std::numeric_limits<int>::max();
  const std::string expected = !unbounded ? "an integer from " + std::to_string(min) + " to " + std::to_string(max)
                               : min == 0 ? "a non-negative integer"
                               : min == 1 ? "a positive integer"
                                          : "an integer >= " + std::to_string(min);
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        errno = 0;
        const long long value = std::strtoll(text.c_str(), &end, 10);
        if (text.empty() || end == text.c_str() || *end != '\0' || errno == ERANGE || value < min || value > max)
          return "expected " + expected + ", got '" + text + "'";
        return "";
      },
      "");
}

CLI::Validator Number(double min) {
  return CLI::Validator(
      [=](std::string& text) -> std::string {
        char* end = nullptr;
        const double value = std::strtod(text.c_str(), &end);
        if (text.empty() || end == text.c_str() || *end != '\0' || !std::isfinite(value) || !(value >= min))
          return "expected a number >= " + Shown(min) + ", got '" + text + "'";
        return "";
      },
      "");
}

}  // namespace srics::cli
