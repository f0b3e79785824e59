#include "deploy/run_folder/outcome.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "common/files/durable_file.h"
#include "common/files/small_file.h"

namespace srics::run_folder {

namespace fs = std::filesystem;

std::string QuotedString(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\')
      out += '\\', out += c;
    else if (c == '\n')
      out += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20)
      out += ' ';
    else
      out += c;
  }
  return out + "\"";
}

// The inverse of QuotedString (text that is not quoted is returned as it is).
std::string UnquotedString(const std::string& text) {
  if (text.size() < 2 || text.front() != '"' || text.back() != '"') return text;
  std::string out;
  for (size_t i = 1; i + 1 < text.size(); ++i) {
    if (text[i] == '\\' && i + 2 < text.size()) {
      ++i;
      out += text[i] == 'n' ? '\n' : text[i];
    } else {
      out += text[i];
    }
  }
  return out;
}

void WriteRunOutcome(const std::string& dir, const RunOutcome& outcome) {
  std::ostringstream out;
  out << "# how this run ended (srics run): finished, interrupted or failed\n"
      << "state: " << outcome.state << "\nexit_code: " << outcome.exit_code
      << "\nreason: " << QuotedString(outcome.reason) << "\n";
  if (outcome.cpu_seconds >= 0) out << "cpu_seconds: " << std::llround(outcome.cpu_seconds) << "\n";
  files::WriteFileDurably((fs::path(dir) / "outcome.yaml").string(), out.str());
}

std::optional<RunOutcome> ReadRunOutcome(const std::string& dir) {
  const fs::path path = fs::path(dir) / "outcome.yaml";
  if (!fs::exists(path)) return std::nullopt;
  std::istringstream in(files::ReadSmallFile(path.string()));  // throws over the size limit
  RunOutcome outcome;
  bool have_state = false;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("state: ", 0) == 0)
      outcome.state = line.substr(7), have_state = true;
    else if (line.rfind("exit_code: ", 0) == 0)
      outcome.exit_code = std::atoi(line.c_str() + 11);
    else if (line.rfind("reason: ", 0) == 0)
      outcome.reason = UnquotedString(line.substr(8));
    else if (line.rfind("cpu_seconds: ", 0) == 0)
      outcome.cpu_seconds = std::atof(line.c_str() + 13);
  }
  if (!have_state) return std::nullopt;
  return outcome;
}

void RemoveRunOutcome(const std::string& dir) {
  std::error_code ignored;
  fs::remove(fs::path(dir) / "outcome.yaml", ignored);
}

bool RunFinished(const std::string& dir) {
  const std::optional<RunOutcome> outcome = ReadRunOutcome(dir);
  return outcome && outcome->state == "finished";
}

}  // namespace srics::run_folder
