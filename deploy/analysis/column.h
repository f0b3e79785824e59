#pragma once
// `srics column FILE COLUMN [--where NAME=VALUE]...`: the largest value of one column of a run
// folder's CSV file over the rows that match, read by column name through the run folder's one
// CSV reader. For scripts that watch a run (tests/deb-check.sh, deploy/multihost/three_hosts.sh):
// no shell splits a run folder's file or computes a figure of it.

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace srics::analysis {

struct ColumnOptions {
  std::filesystem::path file;
  std::string column;
  std::vector<std::string> where;  // NAME=VALUE, every one must hold (text equality)
};

// The largest number in `column` over the rows of `file` whose fields match every condition;
// nothing when no matching row has a number there. Throws std::invalid_argument naming what is
// wrong: a missing or unreadable file, a column or a condition's column the header lacks, a
// condition without '='.
std::optional<double> ColumnMax(const ColumnOptions& options);

// Prints ColumnMax (0 when nothing matched: a run that has not got there yet) and returns 0;
// 1 with the message on stderr for a bad file, column or condition.
int Column(const ColumnOptions& options);

}  // namespace srics::analysis
