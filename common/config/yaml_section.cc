#include "common/config/yaml_section.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>
#include <type_traits>

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include "common/files/small_file.h"

namespace srics::config {
namespace {

// Walks a document's parse events (nothing is built) and refuses what ParsePlainYaml refuses.
class PlainYamlCheck : public YAML::EventHandler {
 public:
  explicit PlainYamlCheck(const std::string& name) : name_(name) {}
  void OnDocumentStart(const YAML::Mark&) override {}
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t anchor) override { Node(mark, anchor); }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    Refuse(mark, "an alias (*name): anchors and aliases are not accepted in a config; write the values out");
  }
  void OnScalar(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor, const std::string&) override {
    Node(mark, anchor);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                       YAML::EmitterStyle::value) override {
    Open(mark, anchor);
  }
  void OnSequenceEnd() override { --depth_; }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t anchor,
                  YAML::EmitterStyle::value) override {
    Open(mark, anchor);
  }
  void OnMapEnd() override { --depth_; }
  void OnAnchor(const YAML::Mark& mark, const std::string&) override { Anchor(mark); }

 private:
  [[noreturn]] void Refuse(const YAML::Mark& mark, const std::string& what) const {
    throw ConfigError(name_ + (mark.is_null() ? "" : ":" + std::to_string(mark.line + 1)) + ": " + what);
  }
  void Anchor(const YAML::Mark& mark) const {
    Refuse(mark, "an anchor (&name): anchors and aliases are not accepted in a config; write the values out");
  }
  void Node(const YAML::Mark& mark, YAML::anchor_t anchor) {
    if (anchor != YAML::NullAnchor) Anchor(mark);
    if (++nodes_ > kYamlMaxNodes)
      Refuse(mark, "more than " + std::to_string(kYamlMaxNodes) + " YAML nodes; a config is far smaller");
  }
  void Open(const YAML::Mark& mark, YAML::anchor_t anchor) {
    Node(mark, anchor);
    if (++depth_ > kYamlMaxDepth)
      Refuse(mark, "nested deeper than " + std::to_string(kYamlMaxDepth) + " levels; a config is far flatter");
  }

  const std::string& name_;
  int nodes_ = 0;
  int depth_ = 0;
};

// Edit distance, for "did you mean" on unknown keys.
size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1] ? 1u : 0u)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

std::string Describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsScalar()) return "'" + node.Scalar() + "'";
  if (node.IsSequence()) return "a list";
  return "a mapping";
}

std::string Join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

// The text of a mapping's key. Keys were checked by CheckKeys when the text was loaded.
std::string KeyText(const YAML::Node& key) { return key.IsScalar() ? key.Scalar() : std::string(); }

// Merges `top` into `base`; when `file` is given, records it as the origin of every key of
// `top` (a base file's own origins were recorded when it was loaded, so it passes none).
void MergeInto(YAML::Node& base, const YAML::Node& top, const std::string& path, const std::string* file,
               OriginMap* origins) {
  for (auto it = top.begin(); it != top.end(); ++it) {
    const std::string key = KeyText(it->first);
    const std::string key_path = Join(path, key);
    YAML::Node existing = base[key];
    if (existing.IsMap() && it->second.IsMap()) {
      MergeInto(existing, it->second, key_path, file, origins);
    } else {
      base[key] = YAML::Clone(it->second);
      if (!file) continue;
      // every key below this one now comes from `file`
      for (auto o = origins->begin(); o != origins->end();) {
        if (o->first.rfind(key_path + ".", 0) == 0)
          o = origins->erase(o);
        else
          ++o;
      }
      // YAML::Clone drops positions, so the line of each value is taken here from the
      // original (as for a parsed text: a mapping or list starts at its first item)
      const bool has_lines = *file != "command line";
      auto line_of = [&](const YAML::Node& n) { return has_lines ? n.Mark().line + 1 : 0; };
      std::function<void(const YAML::Node&, const std::string&, int)> mark = [&](const YAML::Node& n,
                                                                                 const std::string& p, int line) {
        (*origins)[p] = Origin{*file, line};
        if (n.IsMap())
          for (auto c = n.begin(); c != n.end(); ++c) mark(c->second, Join(p, KeyText(c->first)), line_of(c->second));
        if (n.IsSequence())
          for (size_t i = 0; i < n.size(); ++i) mark(n[i], p + "[" + std::to_string(i) + "]", line_of(n[i]));
      };
      mark(it->second, key_path, line_of(it->second));
    }
  }
}

YAML::Node LoadMergedYamlImpl(const std::filesystem::path& file, OriginMap* origins, int depth) {
  if (depth > 8) throw ConfigError(file.string() + ": 'extends' chain deeper than 8 files (a cycle?)");
  if (!std::filesystem::exists(file)) throw ConfigError(file.string() + ": no such config file");
  YAML::Node top = LoadPlainYamlFile(file.string());
  if (top.IsNull()) top = YAML::Node(YAML::NodeType::Map);
  if (!top.IsMap()) throw ConfigError(file.string() + ": expected a mapping at the top level");
  CheckKeys(top, "", file.string(), true);
  YAML::Node merged(YAML::NodeType::Map);
  if (top["extends"]) {
    // one base file or a list of them, merged in order (later ones win)
    const YAML::Node bases = top["extends"];
    std::vector<std::string> names;
    if (bases.IsScalar()) {
      names.push_back(bases.Scalar());
    } else if (bases.IsSequence()) {
      for (const auto& b : bases) {
        if (!b.IsScalar()) names.clear();
        if (!b.IsScalar()) break;
        names.push_back(b.Scalar());
      }
    }
    if (names.empty())
      throw ConfigError(file.string() + ": extends: expected a file name (or a list of them) relative to this file");
    for (const auto& name : names) {
      YAML::Node base = LoadMergedYamlImpl(file.parent_path() / name, origins, depth + 1);
      MergeInto(merged, base, "", nullptr, origins);
    }
    top.remove("extends");
  }
  const std::string file_name = file.string();
  MergeInto(merged, top, "", &file_name, origins);
  return merged;
}

// A scalar that decodes as N (finite, for floating point) within [lo, hi], or nothing.
template <typename N>
std::optional<N> DecodeInRange(const YAML::Node& value, N lo, N hi) {
  N parsed = 0;
  if (!value.IsScalar() || !YAML::convert<N>::decode(value, parsed)) return std::nullopt;
  if constexpr (std::is_floating_point_v<N>)
    if (!std::isfinite(parsed)) return std::nullopt;
  if (parsed < lo || parsed > hi) return std::nullopt;
  return parsed;
}

// "<what> in [lo, hi]", the expectation of a range.
template <typename N>
std::string InRange(const std::string& what, N lo, N hi) {
  std::ostringstream text;
  text << what << " in [" << lo << ", " << hi << "]";
  return text.str();
}

}  // namespace

YamlSection::YamlSection(YAML::Node node, std::string path, std::shared_ptr<const OriginMap> origins,
                         std::string default_file, YAML::Node resolved)
    : node_(std::move(node)),
      path_(std::move(path)),
      origins_(std::move(origins)),
      default_file_(std::move(default_file)),
      resolved_(std::move(resolved)) {
  if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) {
    throw ConfigError(Where("") + ": " + (path_.empty() ? "<top>" : path_) + ": expected a mapping, got " +
                      Describe(node_));
  }
}

std::string YamlSection::KeyPath(const std::string& key) const { return Join(path_, key); }

std::string YamlSection::Where(const std::string& key) const {
  if (origins_ && !origins_->empty()) {
    // merged files: the deepest recorded prefix of this key path names the file it came
    // from; its line is known only for the key itself (merged nodes have no positions)
    const std::string full = key.empty() ? path_ : KeyPath(key);
    std::string p = full;
    while (true) {
      auto it = origins_->find(p);
      if (it != origins_->end()) {
        const Origin& origin = it->second;
        if (p == full && origin.line > 0) return origin.file + ":" + std::to_string(origin.line);
        return origin.file;
      }
      size_t dot = p.rfind('.');
      if (dot == std::string::npos) break;
      p = p.substr(0, dot);
    }
    return default_file_;
  }
  // one parsed text: the nodes still carry their positions
  const YAML::Node& const_node = node_;
  YAML::Node value = (!key.empty() && node_.IsMap()) ? YAML::Node(const_node[key]) : node_;
  if (value.IsDefined() && value.Mark().line >= 0) return default_file_ + ":" + std::to_string(value.Mark().line + 1);
  return default_file_;
}

bool YamlSection::Has(const std::string& key) const {
  known_keys_.insert(key);
  if (!node_.IsMap()) return false;
  const YAML::Node& const_node = node_;
  return static_cast<bool>(const_node[key]);
}

YAML::Node YamlSection::Get(const std::string& key) {
  consumed_.insert(key);
  const YAML::Node& const_node = node_;
  return const_node[key];
}

std::string YamlSection::Quote(const std::string& key) const {
  const YAML::Node& const_node = node_;
  return Describe(node_.IsMap() ? YAML::Node(const_node[key]) : YAML::Node());
}

void YamlSection::Fail(const std::string& key, const std::string& expected) const {
  throw ConfigError(Where(key) + ": " + KeyPath(key) + ": expected " + expected + ", got " + Quote(key));
}

void YamlSection::FailRule(const std::string& key, const std::string& message) const {
  throw ConfigError(Where(key) + ": " + KeyPath(key) + ": " + message);
}

void YamlSection::ReadInt(const std::string& key, int* out, int64_t lo, int64_t hi) {
  if (!Has(key)) return RecordDefault(key, *out);
  const std::optional<int64_t> parsed = DecodeInRange(Get(key), lo, hi);
  if (!parsed) Fail(key, InRange("an integer", lo, hi));
  *out = static_cast<int>(*parsed);
  Record(key, *out);
}

void YamlSection::ReadUint64(const std::string& key, uint64_t* out, uint64_t lo) {
  if (!Has(key)) return RecordDefault(key, *out);
  YAML::Node value = Get(key);
  uint64_t parsed = 0;
  if (!value.IsScalar() || value.Scalar().starts_with("-") || !YAML::convert<uint64_t>::decode(value, parsed) ||
      parsed < lo)
    Fail(key, lo == 0   ? "a non-negative integer"
              : lo == 1 ? "a positive integer"
                        : "an integer >= " + std::to_string(lo));
  *out = parsed;
  Record(key, *out);
}

void YamlSection::ReadDouble(const std::string& key, double* out, double lo, double hi) {
  if (!Has(key)) return RecordDefault(key, *out);
  const std::optional<double> parsed = DecodeInRange(Get(key), lo, hi);
  if (!parsed) Fail(key, InRange("a number", lo, hi));
  *out = *parsed;
  Record(key, *out);
}

void YamlSection::ReadBool(const std::string& key, bool* out) {
  if (!Has(key)) return RecordDefault(key, *out);
  YAML::Node value = Get(key);
  bool parsed = false;
  if (!value.IsScalar() || !YAML::convert<bool>::decode(value, parsed)) Fail(key, "true or false");
  *out = parsed;
  Record(key, *out);
}

void YamlSection::ReadString(const std::string& key, std::string* out, bool allow_empty) {
  if (!Has(key)) return RecordDefault(key, *out);
  YAML::Node value = Get(key);
  if (!value.IsScalar() || (!allow_empty && value.Scalar().empty()))
    Fail(key, allow_empty ? "a string" : "a non-empty string");
  *out = value.Scalar();
  Record(key, *out);
}

void YamlSection::ReadDoubleList(const std::string& key, std::vector<double>* out, size_t size, double lo, double hi) {
  if (!Has(key)) return RecordDefault(key, *out);
  YAML::Node value = Get(key);
  const std::string expected =
      InRange(size ? "a list of " + std::to_string(size) + " numbers" : "a list of numbers", lo, hi);
  if (!value.IsSequence() || (size && value.size() != size)) Fail(key, expected);
  std::vector<double> parsed;
  for (const auto& item : value) {
    const std::optional<double> v = DecodeInRange(item, lo, hi);
    if (!v) Fail(key, expected);
    parsed.push_back(*v);
  }
  *out = std::move(parsed);
  Record(key, *out);
}

void YamlSection::ReadIntList(const std::string& key, std::vector<int>* out, int64_t lo, int64_t hi) {
  if (!Has(key)) return RecordDefault(key, *out);
  YAML::Node value = Get(key);
  const std::string expected = InRange("a list of integers", lo, hi);
  if (!value.IsSequence()) Fail(key, expected);
  std::vector<int> parsed;
  for (const auto& item : value) {
    const std::optional<int64_t> v = DecodeInRange(item, lo, hi);
    if (!v) Fail(key, expected);
    parsed.push_back(static_cast<int>(*v));
  }
  *out = std::move(parsed);
  Record(key, *out);
}

YamlSection YamlSection::Child(const std::string& key) {
  // the same node: what the child records lands here (a section read twice shares one)
  const YAML::Node& recorded = resolved_;
  YAML::Node resolved =
      recorded[key] && recorded[key].IsMap() ? YAML::Node(recorded[key]) : YAML::Node(YAML::NodeType::Map);
  resolved_[key] = resolved;
  if (!Has(key)) return YamlSection(YAML::Node(YAML::NodeType::Map), KeyPath(key), origins_, default_file_, resolved);
  YAML::Node value = Get(key);
  if (!value.IsMap() && !value.IsNull()) Fail(key, "a mapping");
  return YamlSection(value, KeyPath(key), origins_, default_file_, resolved);
}

std::vector<YamlSection> YamlSection::ChildList(const std::string& key) {
  std::vector<YamlSection> children;
  if (!Has(key)) return children;
  YAML::Node value = Get(key);
  if (!value.IsSequence()) Fail(key, "a list of mappings");
  YAML::Node resolved_list(YAML::NodeType::Sequence);
  resolved_[key] = resolved_list;
  for (size_t i = 0; i < value.size(); ++i) {
    if (!value[i].IsMap()) Fail(key, "a list of mappings");
    YAML::Node resolved(YAML::NodeType::Map);
    resolved_list.push_back(resolved);
    children.emplace_back(value[i], KeyPath(key) + "[" + std::to_string(i) + "]", origins_, default_file_, resolved);
  }
  return children;
}

void YamlSection::Finish() const {
  if (!node_.IsMap()) return;
  for (auto it = node_.begin(); it != node_.end(); ++it) {
    const std::string key = KeyText(it->first);
    if (consumed_.count(key)) continue;
    std::string best;
    size_t best_distance = 3;
    // suggest among the keys this mapping accepts (every Read*/Child call asked for one)
    for (const auto& k : known_keys_) {
      size_t d = EditDistance(key, k);
      if (d < best_distance) {
        best_distance = d;
        best = k;
      }
    }
    std::string message = Where(key) + ": " + KeyPath(key) + ": unknown key";
    if (!best.empty()) message += " (did you mean '" + best + "'?)";
    throw ConfigError(message);
  }
}

void CheckKeys(const YAML::Node& node, const std::string& path, const std::string& file, bool has_lines) {
  if (node.IsSequence()) {
    for (size_t i = 0; i < node.size(); ++i) CheckKeys(node[i], path + "[" + std::to_string(i) + "]", file, has_lines);
    return;
  }
  if (!node.IsMap()) return;
  for (auto it = node.begin(); it != node.end(); ++it) {
    const YAML::Node key = it->first;  // a copy: it-> is a proxy that dies with this statement
    if (!key.IsScalar() || key.Scalar().empty()) {
      const std::string where =
          has_lines && key.Mark().line >= 0 ? file + ":" + std::to_string(key.Mark().line + 1) : file;
      throw ConfigError(where + ": " + (path.empty() ? "<top>" : path) +
                        ": expected a plain key (a name such as 'domain_id'), got " +
                        (key.IsScalar() ? std::string("an empty key") : Describe(key) + " as a key"));
    }
    CheckKeys(it->second, Join(path, key.Scalar()), file, has_lines);
  }
}

YAML::Node ParsePlainYaml(const std::string& text, const std::string& name) {
  try {
    std::istringstream in(text);
    YAML::Parser parser(in);
    PlainYamlCheck check(name);
    parser.HandleNextDocument(check);  // YAML::Load builds the first document only
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw ConfigError(name + ":" + std::to_string(e.mark.line + 1) + ":" + std::to_string(e.mark.column + 1) +
                      ": not valid YAML: " + e.msg);
  }
}

YAML::Node LoadPlainYamlFile(const std::string& file) {
  try {
    return ParsePlainYaml(files::ReadSmallFile(file), file);
  } catch (const files::SmallFileError& e) {
    throw ConfigError(e.what());
  }
}

YAML::Node LoadMergedYaml(const std::string& file, OriginMap* origins) {
  return LoadMergedYamlImpl(std::filesystem::path(file), origins, 0);
}

void ApplyOverride(YAML::Node* root, const std::string& assignment, OriginMap* origins) {
  const size_t eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0)
    throw ConfigError("command line: '" + assignment + "': expected key.path=value");
  const std::string path = assignment.substr(0, eq);
  const YAML::Node value = ParsePlainYaml(assignment.substr(eq + 1), "command line: " + path);
  CheckKeys(value, path, "command line", false);
  // walk down, creating mappings as needed
  std::vector<std::string> parts;
  std::stringstream ss(path);
  for (std::string part; std::getline(ss, part, '.');) parts.push_back(part);
  // wrap the value from the inside out (reset() rebinds; yaml-cpp's operator= would assign)
  YAML::Node nested = value;
  for (size_t i = parts.size(); i-- > 0;) {
    if (parts[i].empty()) throw ConfigError("command line: '" + path + "': empty key in path");
    YAML::Node mapping(YAML::NodeType::Map);
    mapping[parts[i]] = nested;
    nested.reset(mapping);
  }
  const std::string command_line = "command line";
  MergeInto(*root, nested, "", &command_line, origins);
}

}  // namespace srics::config
