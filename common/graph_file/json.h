#pragma once
// A small JSON reader for the graph file: objects, arrays, numbers, strings, true, false,
// null. Strict (no trailing commas or comments), depth-limited, and every accessor checks
// the type, so an untrusted file can only produce an exception, never a crash.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace srics::graph_file {

class JsonValue {
 public:
  enum class Kind { kNull, kBool, kNumber, kString, kArray, kObject };

  Kind kind() const { return kind_; }
  bool is_object() const { return kind_ == Kind::kObject; }

  // Typed access; throws std::runtime_error naming the expected type on a mismatch.
  double AsDouble() const;
  // A number that is an integer in [-2^53, 2^53].
  int64_t AsInt() const;
  bool AsBool() const;
  const std::string& AsString() const;
  const std::vector<JsonValue>& AsArray() const;
  const std::map<std::string, JsonValue>& AsObject() const;
  // Member of an object; throws std::runtime_error naming the key when it is missing.
  const JsonValue& Get(const std::string& key) const;

 private:
  friend class JsonParser;
  Kind kind_ = Kind::kNull;
  bool boolean_ = false;
  double number_ = 0;
  std::string string_;
  std::vector<JsonValue> array_;
  std::map<std::string, JsonValue> object_;
};

// Parses a whole document; throws std::runtime_error with the byte offset on a syntax error.
JsonValue ParseJson(const std::string& text);

}  // namespace srics::graph_file
