#pragma once
// The run folder and the files the launcher itself writes into it.

#include <ctime>
#include <optional>
#include <string>
#include <vector>

#include "common/config/config.h"

namespace srics::launcher {

// `requested` if not empty (created if missing; an existing folder is reused, so a stopped
// run can be continued from its checkpoint), else <run.output_dir>/<run.name>-<YYYYmmdd-HHMMSS>
// (with -2, -3, ... if that exists). Creates the folder and its logs/ and writes config.yaml
// (the effective configuration) and resolved-config.yaml (every setting, this binary's defaults
// filled in). Returns the folder's path. Throws std::runtime_error.
std::string PrepareRunFolder(const config::Config& config, const std::string& requested);

// A file's lines that are not comments ("" when it cannot be read).
std::string WithoutComments(const std::string& path);

// The first line where two texts differ ("line 3: 'a' now 'b'"), "" when equal; for messages.
std::string FirstDifference(const std::string& a, const std::string& b);

// How the run folder `dir`'s configuration differs from one now loaded ("line 3: 'a' now 'b'"),
// "" when it does not or `dir` has none: every resolved setting when the folder records them
// (resolved-config.yaml, read back through this binary's config, so a setting added since, which
// the folder lacks, takes its default as the run had it, or its earlier default if that changed
// since (config::ParseRecordedConfig); a key pinned to the value it had is no change, and a
// default that changed between binaries is one); else (folders from before
// 2026-12-03) the merged YAML.
std::string ConfigChangeSince(const std::string& dir, const std::string& effective_yaml,
                              const std::string& resolved_yaml);

// The overrides a run continued in `dir` is loaded with: the earlier defaults its record lacks
// (config::EarlierDefaultsOf: a default changed since the run started is not a change it
// gets), then `overrides` (given ones win, and are then a change CheckResumedConfig names).
// `overrides` alone when `dir` has no readable record.
std::vector<std::string> WithEarlierDefaults(const std::string& dir, const std::vector<std::string>& overrides);

// A continued run keeps the configuration it started with: when <dir>/config.yaml exists and
// its settings differ from `config`'s (ConfigChangeSince), throws std::invalid_argument naming the first
// difference, unless `allow_change`; then the old file is kept as config.yaml.<UTC time> and
// the change is appended to <dir>/config-changes.log. Nothing happens for a new folder.
void CheckResumedConfig(const config::Config& config, const std::string& dir, bool allow_change);

// The time `t` (default: now) as strftime's `format` writes it, in local time or in UTC.
std::string LocalTime(const char* format, std::time_t t = std::time(nullptr));
std::string UtcTime(const char* format, std::time_t t = std::time(nullptr));

// A run id unique to this launch: "<host>-<pid>-<YYYYmmddTHHMMSS.mmm>" (the host name cut to
// 16 characters); two calls in one process never give the same id.
std::string NewRunId();

// The run id of a run whose config says transport.run_id: auto: the one recorded in
// <run_dir>/config.yaml by an earlier launch into that folder (a resumed run keeps its id),
// else NewRunId().
std::string ChooseRunId(const std::string& run_dir);

// A run with a given graph (graph.ground_truth, or graph.file): writes it as <dir>/graph.json
// (unless the folder has one already: a continued run keeps its graph), where the graph
// service finds it and re-publishes it instead of learning. Does nothing otherwise. Throws
// std::runtime_error (an unreadable graph.file, no folder).
void SeedGraphFile(const config::Config& config, const std::string& dir);

// Where the role programs are: `bin_dir` if given (the program in it, or in its build-tree
// subfolder), else next to the running executable (installed side by side) or in the build
// tree relative to it (build/deploy/launcher/srics -> build/<subdir>/<program>). Throws
// std::runtime_error listing the places it looked.
std::string FindProgram(const std::string& program, const std::string& build_subdir, const std::string& bin_dir);

// The directory of the running executable (/proc/self/exe).
std::string ExecutableDir();

}  // namespace srics::launcher
