#pragma once
// Strict, typed reading of one YAML mapping. Internal to the config library: algorithms and
// mains never include yaml-cpp; they see only the plain structs of the *_config.h headers.
//
// A key that is absent keeps the struct's default (defaults live only in the structs); a key
// that is present must have the right type and range; a key nobody read is an error at
// Finish(), so a typo never passes silently. Every key read is also recorded with the value it
// resolved to, given or default (resolved()): a run folder keeps what its binary's defaults were.

#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common/config/config_error.h"

namespace srics::config {

// Where a key path came from: the file (or "command line") and the 1-based line of its value
// in it (0 = unknown). Recorded while files are merged, because merged nodes are copies that
// no longer carry their position.
struct Origin {
  std::string file;
  int line = 0;
};

// Origins by key path ("transport.domain_id", "actors.list[0].name"), filled when merging.
using OriginMap = std::map<std::string, Origin>;

class YamlSection {
 public:
  // `path` is the dotted key path of this mapping ("" for the root).
  // `resolved`: the mapping every read key and its value are recorded into (a new one if absent)
  YamlSection(YAML::Node node, std::string path, std::shared_ptr<const OriginMap> origins, std::string default_file,
              YAML::Node resolved = YAML::Node(YAML::NodeType::Map));

  bool Has(const std::string& key) const;
  // Each Read* leaves *out untouched when the key is absent and throws ConfigError when the
  // value is of the wrong type or out of range. Ranges are inclusive.
  void ReadInt(const std::string& key, int* out, int64_t lo, int64_t hi);
  void ReadUint64(const std::string& key, uint64_t* out, uint64_t lo = 0);
  void ReadDouble(const std::string& key, double* out, double lo, double hi);
  void ReadBool(const std::string& key, bool* out);
  void ReadString(const std::string& key, std::string* out, bool allow_empty = true);
  void ReadDoubleList(const std::string& key, std::vector<double>* out, size_t size, double lo,
                      double hi);  // size 0 = any length
  void ReadIntList(const std::string& key, std::vector<int>* out, int64_t lo, int64_t hi);
  template <typename Enum>
  void ReadEnum(const std::string& key, Enum* out, const std::vector<std::pair<std::string, Enum>>& names);

  // A nested mapping; absent gives an empty mapping so nested defaults apply.
  YamlSection Child(const std::string& key);
  // A sequence of mappings (for lists of objects); absent gives an empty list.
  std::vector<YamlSection> ChildList(const std::string& key);

  // Throws for every key of this mapping that no Read*/Child call consumed.
  void Finish() const;

  // Throws ConfigError "<file>:<line>: <path.key>: expected <expected>, got <got>".
  [[noreturn]] void Fail(const std::string& key, const std::string& expected) const;
  // Same, for a rule that involves several keys (no single value to quote).
  [[noreturn]] void FailRule(const std::string& key, const std::string& message) const;

  const std::string& path() const { return path_; }
  // Every key read so far below this mapping with its resolved value (nested sections included).
  const YAML::Node& resolved() const { return resolved_; }
  std::string KeyPath(const std::string& key) const;

 private:
  YAML::Node Get(const std::string& key);
  template <typename T>
  void Record(const std::string& key, const T& value) {
    resolved_[key] = value;
  }
  // A key left at its default: recorded, unless the default is empty ("none": an empty string
  // or list given explicitly may not be valid, and the record stays a valid set of keys).
  template <typename T>
  void RecordDefault(const std::string& key, const T& value) {
    if constexpr (requires { value.empty(); }) {
      if (value.empty()) return;
    }
    Record(key, value);
  }
  std::string Where(const std::string& key) const;
  std::string Quote(const std::string& key) const;

  YAML::Node node_;
  std::string path_;
  std::shared_ptr<const OriginMap> origins_;
  std::string default_file_;
  YAML::Node resolved_;
  std::set<std::string> consumed_;
  mutable std::set<std::string> known_keys_;  // for "did you mean" at Finish()
};

template <typename Enum>
void YamlSection::ReadEnum(const std::string& key, Enum* out, const std::vector<std::pair<std::string, Enum>>& names) {
  std::string text;
  std::string expected = "one of";
  for (const auto& [name, value] : names) expected += " '" + name + "'";
  if (Has(key)) {
    YAML::Node value = Get(key);
    if (!value.IsScalar()) Fail(key, expected);
    text = value.Scalar();
    bool known = false;
    for (const auto& [name, v] : names) {
      if (name == text) *out = v, known = true;
    }
    if (!known) Fail(key, expected);
  }
  for (const auto& [name, v] : names) {
    if (v == *out) {
      resolved_[key] = name;
      break;
    }
  }
}

// Limits of a config text: a config is a few kB of plain mappings and lists, and every text
// read (a config file, a resolved-config.yaml, an override's value) is held to them before it is
// built into nodes, so that a small file cannot expand into gigabytes.
inline constexpr int kYamlMaxNodes = 100000;
inline constexpr int kYamlMaxDepth = 64;

// Parses YAML text (`name` for messages: a file or "command line"). Throws ConfigError naming
// `name` and the line for text that is not valid YAML, that uses anchors or aliases (`&a`,
// `*a`: expanded, nine aliases of nine aliases ... of a list grow exponentially; no config
// needs them), or that has more than kYamlMaxNodes nodes or nests deeper than kYamlMaxDepth.
YAML::Node ParsePlainYaml(const std::string& text, const std::string& name);

// Reads a config file (at most files::kSmallFileMaxBytes) and parses it with ParsePlainYaml.
YAML::Node LoadPlainYamlFile(const std::string& file);

// Reads a YAML file, following `extends: other.yaml` (relative to the file) recursively and
// merging mappings key by key (the extending file wins; sequences are replaced whole).
// Records in *origins which file each key path came from.
YAML::Node LoadMergedYaml(const std::string& file, OriginMap* origins);

// Throws ConfigError "<file>:<line>: <path>: expected a plain key ..., got a list as a key" for
// the first key of a mapping (at any depth below `node`) that is not a non-empty scalar: YAML
// allows lists, mappings and nothing as keys; a config does not. `path` names `node`.
void CheckKeys(const YAML::Node& node, const std::string& path, const std::string& file, bool has_lines);

// Applies "a.b.c=value" (value parsed as YAML) on top of a loaded tree.
void ApplyOverride(YAML::Node* root, const std::string& assignment, OriginMap* origins);

}  // namespace srics::config
