#pragma once
// A strict JSON reader for the dashboard tests: the document must be exactly JSON (RFC 8259:
// no trailing commas, no NaN, one value, nothing after it), else Parse throws. Values are read
// the way the tests use them: doc["runs"][0]["env_steps"].as<uint64_t>().

#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace srics::dashboard::testing {

class Json {
 public:
  enum class Type { kNull, kBool, kNumber, kString, kArray, kObject };

  static Json Parse(const std::string& text) {
    size_t at = 0;
    Json value = ParseValue(text, &at);
    SkipSpace(text, &at);
    if (at != text.size()) throw std::invalid_argument("JSON: text after the value at " + std::to_string(at));
    return value;
  }

  bool IsNull() const { return type_ == Type::kNull; }
  Type type() const { return type_; }
  size_t size() const { return type_ == Type::kArray ? items_.size() : fields_.size(); }
  const Json& operator[](size_t i) const {
    if (type_ != Type::kArray || i >= items_.size()) throw std::out_of_range("JSON: no item " + std::to_string(i));
    return items_[i];
  }
  const Json& operator[](int i) const { return (*this)[static_cast<size_t>(i)]; }
  const Json& operator[](const std::string& key) const {
    auto it = fields_.find(key);
    if (type_ != Type::kObject || it == fields_.end()) throw std::out_of_range("JSON: no key " + key);
    return it->second;
  }
  const std::vector<Json>& items() const { return items_; }
  bool has(const std::string& key) const { return fields_.count(key) > 0; }

  template <typename T>
  T as() const {
    if constexpr (std::is_same_v<T, std::string>) {
      if (type_ != Type::kString) throw std::invalid_argument("JSON: not a string");
      return text_;
    } else if constexpr (std::is_same_v<T, bool>) {
      if (type_ != Type::kBool) throw std::invalid_argument("JSON: not a bool");
      return text_ == "true";
    } else {
      if (type_ != Type::kNumber) throw std::invalid_argument("JSON: not a number");
      if constexpr (std::is_integral_v<T> && std::is_unsigned_v<T>) return static_cast<T>(std::strtoull(text_.c_str(), nullptr, 10));
      else if constexpr (std::is_integral_v<T>) return static_cast<T>(std::strtoll(text_.c_str(), nullptr, 10));
      else return static_cast<T>(std::strtod(text_.c_str(), nullptr));
    }
  }

 private:
  static void SkipSpace(const std::string& s, size_t* at) {
    while (*at < s.size() && (s[*at] == ' ' || s[*at] == '\n' || s[*at] == '\r' || s[*at] == '\t')) ++*at;
  }
  static void Expect(const std::string& s, size_t* at, char c) {
    if (*at >= s.size() || s[*at] != c)
      throw std::invalid_argument(std::string("JSON: expected '") + c + "' at " + std::to_string(*at));
    ++*at;
  }
  static std::string ParseString(const std::string& s, size_t* at) {
    Expect(s, at, '"');
    std::string out;
    while (*at < s.size() && s[*at] != '"') {
      char c = s[(*at)++];
      if (static_cast<unsigned char>(c) < 0x20) throw std::invalid_argument("JSON: control character in a string");
      if (c == '\\') {
        if (*at >= s.size()) break;
        const char e = s[(*at)++];
        switch (e) {
          case '"': case '\\': case '/': out += e; break;
          case 'n': out += '\n'; break;
          case 't': out += '\t'; break;
          case 'r': out += '\r'; break;
          case 'b': out += '\b'; break;
          case 'f': out += '\f'; break;
          case 'u': {
            if (*at + 4 > s.size()) throw std::invalid_argument("JSON: short \\u escape");
            const unsigned code = static_cast<unsigned>(std::stoul(s.substr(*at, 4), nullptr, 16));
            *at += 4;
            if (code < 0x80) out += static_cast<char>(code);
            else out += '?';  // the tests only need ASCII
            break;
          }
          default: throw std::invalid_argument("JSON: bad escape");
        }
      } else {
        out += c;
      }
    }
    Expect(s, at, '"');
    return out;
  }
  static Json ParseValue(const std::string& s, size_t* at) {
    SkipSpace(s, at);
    if (*at >= s.size()) throw std::invalid_argument("JSON: unexpected end");
    Json v;
    const char c = s[*at];
    if (c == '{') {
      v.type_ = Type::kObject;
      ++*at;
      SkipSpace(s, at);
      if (*at < s.size() && s[*at] == '}') return ++*at, v;
      while (true) {
        SkipSpace(s, at);
        std::string key = ParseString(s, at);
        SkipSpace(s, at);
        Expect(s, at, ':');
        v.fields_[key] = ParseValue(s, at);
        SkipSpace(s, at);
        if (*at < s.size() && s[*at] == ',') { ++*at; continue; }
        Expect(s, at, '}');
        return v;
      }
    }
    if (c == '[') {
      v.type_ = Type::kArray;
      ++*at;
      SkipSpace(s, at);
      if (*at < s.size() && s[*at] == ']') return ++*at, v;
      while (true) {
        v.items_.push_back(ParseValue(s, at));
        SkipSpace(s, at);
        if (*at < s.size() && s[*at] == ',') { ++*at; continue; }
        Expect(s, at, ']');
        return v;
      }
    }
    if (c == '"') {
      v.type_ = Type::kString;
      v.text_ = ParseString(s, at);
      return v;
    }
    for (const char* word : {"null", "true", "false"}) {
      if (s.compare(*at, std::string(word).size(), word) == 0) {
        *at += std::string(word).size();
        v.type_ = word[0] == 'n' ? Type::kNull : Type::kBool;
        v.text_ = word;
        return v;
      }
    }
    // a number: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?
    const size_t start = *at;
    auto digits = [&] {
      const size_t from = *at;
      while (*at < s.size() && s[*at] >= '0' && s[*at] <= '9') ++*at;
      if (*at == from) throw std::invalid_argument("JSON: bad value at " + std::to_string(from));
    };
    if (s[*at] == '-') ++*at;
    if (*at < s.size() && s[*at] == '0') ++*at;
    else digits();
    if (*at < s.size() && s[*at] == '.') ++*at, digits();
    if (*at < s.size() && (s[*at] == 'e' || s[*at] == 'E')) {
      ++*at;
      if (*at < s.size() && (s[*at] == '+' || s[*at] == '-')) ++*at;
      digits();
    }
    v.type_ = Type::kNumber;
    v.text_ = s.substr(start, *at - start);
    return v;
  }

  Type type_ = Type::kNull;
  std::string text_;
  std::vector<Json> items_;
  std::map<std::string, Json> fields_;
};

}  // namespace srics::dashboard::testing
