#pragma once
// The command line of every SRICS-DDS program, on Debian's CLI11. A program describes its
// options on a CLI::App, then:
//
//   CLI::App app{"what the program does", "srics-monitor"};
//   cli::Configure(app);                       // --help, --version
//   app.add_option("CONFIG", config)->required();
//   if (const auto code = cli::Parse(app, argc, argv)) return *code;
//
// Parse prints the help or the version (exit 0), or "<program>: <what is wrong>" naming the
// argument and a hint to --help on stderr (exit 2, kExitUsage), and returns nothing when the
// program goes on. Functions that return a program's options from a list of arguments (the
// launcher's ParseRunArgs and the like, used by tests) use ParseOrThrow instead.

#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "common/cli/exit_codes.h"

namespace srics::cli {

// The project's version ("0.1.0"): project(VERSION) of the top-level CMakeLists.txt.
const char* Version();

// The house conventions on an app or a subcommand: -h/--help, --version ("<name> <version>"),
// option defaults shown in the help. Subcommands added afterwards need their own call.
void Configure(CLI::App& app);

// Parses argv. Returns nothing when the program goes on; else the exit code after printing
// the help or version (0) or the error (kExitUsage).
std::optional<int> Parse(CLI::App& app, int argc, char** argv);

// Parses a list of arguments (without the program name); throws std::invalid_argument with
// CLI11's message (it names the argument) on an error, --help or --version.
void ParseOrThrow(CLI::App& app, const std::vector<std::string>& args);

// Prints "<program>: <message>" and the hint to --help on stderr; returns kExitUsage. For
// errors found after parsing (an argument that does not fit another one).
int UsageError(const std::string& program, const std::string& message);

// The name a subcommand error is reported under: "srics run", or the app's own name.
std::string CommandName(const CLI::App& app);

// A CONFIG argument as given when that file exists, else the installed config of that name:
// <prefix>/share/srics-dds/configs/<name> beside the program's <prefix>/bin (cmake --install,
// the .deb), so `srics run default.yaml` works from any folder. "deploy/configs/x.yaml", as
// the checkout's READMEs write it, is looked up as "x.yaml" there. Unchanged when neither
// exists (loading it then names the file).
std::string FindConfig(const std::string& given);
// The same as a CLI11 transform: app.add_option("CONFIG", file)->transform(cli::InstalledConfig()).
CLI::Validator InstalledConfig();
// <prefix>/share/srics-dds of the running program ("" when it is not installed so).
std::string InstalledDataDir();

// --set key.path=value: a config override, repeatable, one value each (every program that
// loads a config takes it).
CLI::Option* AddSetOption(CLI::App& app, std::vector<std::string>* overrides, const std::string& help);

// Validators of option text, run before conversion; the error names the option
// ("--actors: expected a positive integer, got '0'"); a max at or above INT_MAX is no bound.
CLI::Validator Integer(int64_t min, int64_t max = std::numeric_limits<int64_t>::max());
CLI::Validator Number(double min);  // a finite number >= min ("--stop-timeout 2.5")

}  // namespace srics::cli
