#include "deploy/analysis/column.h"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

#include "common/cli/exit_codes.h"
#include "deploy/run_folder/csv.h"

namespace srics::analysis {

std::optional<double> ColumnMax(const ColumnOptions& options) {
  const std::string name = options.file.string();
  const std::optional<run_folder::CsvTable> table = run_folder::CsvTable::Read(options.file);
  if (!table) throw std::invalid_argument(name + ": no such file, or no header line");
  std::vector<std::pair<std::string, std::string>> conditions;
  for (const std::string& condition : options.where) {
    const size_t eq = condition.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("--where " + condition + ": expected NAME=VALUE");
    conditions.emplace_back(condition.substr(0, eq), condition.substr(eq + 1));
  }
  for (const std::string& column : [&] {
         std::vector<std::string> all{options.column};
         for (const auto& [column, value] : conditions) all.push_back(column);
         return all;
       }())
    if (!table->HasColumn(column)) throw std::invalid_argument(name + ": no column '" + column + "'");
  std::optional<double> largest;
  for (const run_folder::CsvRow& row : table->Rows()) {
    if (!std::all_of(conditions.begin(), conditions.end(),
                     [&](const auto& condition) { return row.Text(condition.first) == condition.second; }))
      continue;
    if (const std::optional<double> value = row.Number(options.column))
      largest = largest ? std::max(*largest, *value) : *value;
  }
  return largest;
}

int Column(const ColumnOptions& options) {
  try {
    std::printf("%.15g\n", ColumnMax(options).value_or(0.0));
    return kExitDone;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "srics column: %s\n", e.what());
    return kExitFailed;
  }
}

}  // namespace srics::analysis
