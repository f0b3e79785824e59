#include "deploy/run_folder/csv.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace srics::run_folder {

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

std::string QuoteCsvField(const std::string& text) {
  if (text.find_first_of(",\"") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

namespace {
template <typename T>
std::string Joined(const std::vector<T>& values, int precision) {
  std::ostringstream out;
  out << std::setprecision(precision);
  for (size_t i = 0; i < values.size(); ++i) out << (i ? ";" : "") << values[i];
  return out.str();
}
}  // namespace

std::string JoinedValues(const std::vector<float>& values, int precision) { return Joined(values, precision); }
std::string JoinedValues(const std::vector<double>& values, int precision) { return Joined(values, precision); }

std::vector<double> SplitValues(const std::string& text) {
  std::vector<double> values;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ';');)
    if (!item.empty()) values.push_back(std::strtod(item.c_str(), nullptr));
  return values;
}

bool CsvRow::Has(const std::string& column) const {
  const auto it = columns_->find(column);
  return it != columns_->end() && it->second < fields_->size();
}

std::string CsvRow::Text(const std::string& column) const {
  const auto it = columns_->find(column);
  return it == columns_->end() || it->second >= fields_->size() ? "" : (*fields_)[it->second];
}

std::optional<double> CsvRow::Number(const std::string& column) const {
  const std::string text = Text(column);
  if (text.empty()) return std::nullopt;
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || !std::isfinite(value)) return std::nullopt;
  return value;
}

const std::string& CsvRow::TextOrThrow(const std::string& column) const {
  const auto it = columns_->find(column);
  if (it == columns_->end() || it->second >= fields_->size()) throw std::invalid_argument("no column " + column);
  return (*fields_)[it->second];
}

double CsvRow::Double(const std::string& column) const {
  const std::string& text = TextOrThrow(column);
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw std::invalid_argument(column + ": not a number");
  return value;
}

uint64_t CsvRow::Unsigned(const std::string& column) const {
  const std::string& text = TextOrThrow(column);
  char* end = nullptr;
  const unsigned long long value = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || text[0] == '-') throw std::invalid_argument(column + ": not a count");
  return value;
}

std::vector<float> CsvRow::Floats(const std::string& column) const {
  std::vector<float> values;
  const std::string& text = TextOrThrow(column);
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = std::min(text.find(';', start), text.size());
    const std::string item = text.substr(start, end - start);
    char* stop = nullptr;
    values.push_back(std::strtof(item.c_str(), &stop));
    if (item.empty() || *stop != '\0') throw std::invalid_argument(column + ": not a list of numbers");
    start = end + 1;
  }
  return values;
}

namespace {

// Reads a header and rows from `in`; false when there is no header line.
template <typename Stream>
bool ReadLines(Stream& in, bool complete_lines_only, std::vector<std::string>* header,
               std::map<std::string, size_t>* columns, std::vector<std::vector<std::string>>* rows) {
  std::string line;
  if (!std::getline(in, line)) return false;
  *header = SplitCsvLine(line);
  for (size_t i = 0; i < header->size(); ++i) (*columns)[(*header)[i]] = i;
  while (std::getline(in, line)) {
    if (complete_lines_only && in.eof()) break;  // the last line without its '\n' is still being written
    if (!line.empty()) rows->push_back(SplitCsvLine(line));
  }
  return true;
}

}  // namespace

std::optional<CsvTable> CsvTable::Read(const std::filesystem::path& path, bool complete_lines_only) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  CsvTable table;
  if (!ReadLines(in, complete_lines_only, &table.header_, &table.columns_, &table.rows_)) return std::nullopt;
  return table;
}

std::optional<CsvTable> CsvTable::Parse(const std::string& text, bool complete_lines_only) {
  std::istringstream in(text);
  CsvTable table;
  if (!ReadLines(in, complete_lines_only, &table.header_, &table.columns_, &table.rows_)) return std::nullopt;
  return table;
}

std::vector<CsvRow> CsvTable::Rows() const {
  std::vector<CsvRow> rows;
  rows.reserve(rows_.size());
  for (const std::vector<std::string>& fields : rows_) rows.emplace_back(&columns_, &fields);
  return rows;
}

void ForEachRow(const std::filesystem::path& path, const std::function<void(const CsvRow&)>& parse, uint64_t* skipped) {
  const std::optional<CsvTable> table = CsvTable::Read(path, /*complete_lines_only=*/true);
  if (!table) return;
  for (size_t i = 0; i < table->size(); ++i) {
    try {
      parse(table->Row(i));
    } catch (const std::exception&) {
      ++*skipped;
    }
  }
}

std::string HeaderLine(const std::vector<std::string>& columns) {
  std::string line;
  for (size_t i = 0; i < columns.size(); ++i) line += (i ? "," : "") + columns[i];
  return line;
}

}  // namespace srics::run_folder
