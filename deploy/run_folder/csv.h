#pragma once
// The one CSV reader of a run folder's files (eval.csv, learner.csv, nodes.csv, train.csv,
// episodes.csv, attempts.csv, recorded.csv) and the writer of those deploy/ writes (all but
// train.csv, the learner's, and recorded.csv, the video recorder's): fields separated by commas,
// quoted with doubled quotes when they hold a comma or a quote; per-entity vectors are
// ';'-joined in one field. Columns are found by name, so a file with columns added later reads
// the same. Blank lines are no rows (ignored, not counted as refused).

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace srics::run_folder {

// One CSV line into its fields (quoted fields with doubled quotes inside).
std::vector<std::string> SplitCsvLine(const std::string& line);

// `text` as one CSV field: quoted (quotes doubled) when it holds a comma or a quote. The caller
// makes sure it holds no line break (a peer's text goes through PrintableText first).
std::string QuoteCsvField(const std::string& text);

// Numbers ';'-joined into one field with `precision` significant digits ("0.1;0.25").
std::string JoinedValues(const std::vector<float>& values, int precision = 6);
std::string JoinedValues(const std::vector<double>& values, int precision = 6);
// The numbers of a ';'-joined field; empty items are skipped, a non-number reads as 0.
std::vector<double> SplitValues(const std::string& text);

// One row by column name. The lenient accessors give nothing or "" for a missing column or
// field; the strict ones throw std::invalid_argument naming the column.
class CsvRow {
 public:
  CsvRow(const std::map<std::string, size_t>* columns, const std::vector<std::string>* fields)
      : columns_(columns), fields_(fields) {}

  bool Has(const std::string& column) const;
  // "" when the column or the field is missing.
  std::string Text(const std::string& column) const;
  // A finite number, or nothing when the column is missing, empty or not a number.
  std::optional<double> Number(const std::string& column) const;

  // Strict: throw std::invalid_argument("<column>: ...").
  const std::string& TextOrThrow(const std::string& column) const;
  double Double(const std::string& column) const;
  float Float(const std::string& column) const { return static_cast<float>(Double(column)); }
  uint64_t Unsigned(const std::string& column) const;
  std::vector<float> Floats(const std::string& column) const;  // a ';'-joined list, every item a number

  const std::vector<std::string>& fields() const { return *fields_; }

 private:
  const std::map<std::string, size_t>* columns_;
  const std::vector<std::string>* fields_;
};

// A whole CSV file: its header's column positions and its rows.
class CsvTable {
 public:
  // Empty when the file cannot be opened or has no header line. With `complete_lines_only`, a
  // last line without its '\n' (a file still being written) is left out.
  static std::optional<CsvTable> Read(const std::filesystem::path& path, bool complete_lines_only = false);
  // The same from text.
  static std::optional<CsvTable> Parse(const std::string& text, bool complete_lines_only = false);

  size_t size() const { return rows_.size(); }
  bool empty() const { return rows_.empty(); }
  bool HasColumn(const std::string& column) const { return columns_.count(column) > 0; }
  const std::vector<std::string>& header() const { return header_; }
  CsvRow Row(size_t i) const { return CsvRow(&columns_, &rows_[i]); }
  // Every row, for range loops (views into this table: it must outlive them).
  std::vector<CsvRow> Rows() const;

 private:
  std::vector<std::string> header_;
  std::map<std::string, size_t> columns_;
  std::vector<std::vector<std::string>> rows_;
};

// Calls `parse` on every complete row of a CSV file (one still being written keeps its last,
// unfinished line for later) and counts in *skipped the rows it throws on. Nothing happens for
// a missing file.
void ForEachRow(const std::filesystem::path& path, const std::function<void(const CsvRow&)>& parse, uint64_t* skipped);

// A header line from column names ("a,b,c").
std::string HeaderLine(const std::vector<std::string>& columns);

}  // namespace srics::run_folder
