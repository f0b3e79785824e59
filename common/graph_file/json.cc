#include "common/graph_file/json.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>

namespace srics::graph_file {

double JsonValue::AsDouble() const {
  if (kind_ != Kind::kNumber) throw std::runtime_error("expected a number");
  return number_;
}

int64_t JsonValue::AsInt() const {
  const double v = AsDouble();
  if (v != std::floor(v) || std::abs(v) > 9007199254740992.0) throw std::runtime_error("expected an integer");
  return static_cast<int64_t>(v);
}

bool JsonValue::AsBool() const {
  if (kind_ != Kind::kBool) throw std::runtime_error("expected true or false");
  return boolean_;
}

const std::string& JsonValue::AsString() const {
  if (kind_ != Kind::kString) throw std::runtime_error("expected a string");
  return string_;
}

const std::vector<JsonValue>& JsonValue::AsArray() const {
  if (kind_ != Kind::kArray) throw std::runtime_error("expected an array");
  return array_;
}

const std::map<std::string, JsonValue>& JsonValue::AsObject() const {
  if (kind_ != Kind::kObject) throw std::runtime_error("expected an object");
  return object_;
}

const JsonValue& JsonValue::Get(const std::string& key) const {
  if (kind_ != Kind::kObject) throw std::runtime_error("expected an object");
  auto it = object_.find(key);
  if (it == object_.end()) throw std::runtime_error("missing key \"" + key + "\"");
  return it->second;
}

// Recursive descent over the text; `pos_` is the next byte.
class JsonParser {
 public:
  explicit JsonParser(const std::string& text) : text_(text) {}

  JsonValue Document() {
    JsonValue v = Value(0);
    Space();
    if (pos_ != text_.size()) Error("trailing characters");
    return v;
  }

 private:
  static constexpr int kMaxDepth = 32;

  [[noreturn]] void Error(const std::string& what) const {
    throw std::runtime_error("JSON syntax error at byte " + std::to_string(pos_) + ": " + what);
  }
  void Space() {
    while (pos_ < text_.size() &&
           (text_[pos_] == ' ' || text_[pos_] == '\n' || text_[pos_] == '\r' || text_[pos_] == '\t'))
      ++pos_;
  }
  bool Eat(char c) {
    Space();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  void Expect(char c) {
    if (!Eat(c)) Error(std::string("expected '") + c + "'");
  }
  bool Word(const char* w) {
    const std::string s(w);
    if (text_.compare(pos_, s.size(), s) == 0) {
      pos_ += s.size();
      return true;
    }
    return false;
  }

  JsonValue Value(int depth) {
    if (depth > kMaxDepth) Error("nested too deeply");
    Space();
    if (pos_ >= text_.size()) Error("unexpected end");
    JsonValue v;
    const char c = text_[pos_];
    if (c == '{') {
      ++pos_;
      v.kind_ = JsonValue::Kind::kObject;
      if (Eat('}')) return v;
      do {
        Space();
        std::string key = String();
        Expect(':');
        if (v.object_.count(key)) Error("duplicate key \"" + key + "\"");
        v.object_.emplace(std::move(key), Value(depth + 1));
      } while (Eat(','));
      Expect('}');
    } else if (c == '[') {
      ++pos_;
      v.kind_ = JsonValue::Kind::kArray;
      if (Eat(']')) return v;
      do v.array_.push_back(Value(depth + 1));
      while (Eat(','));
      Expect(']');
    } else if (c == '"') {
      v.kind_ = JsonValue::Kind::kString;
      v.string_ = String();
    } else if (Word("true")) {
      v.kind_ = JsonValue::Kind::kBool;
      v.boolean_ = true;
    } else if (Word("false")) {
      v.kind_ = JsonValue::Kind::kBool;
    } else if (Word("null")) {
      v.kind_ = JsonValue::Kind::kNull;
    } else {
      v.kind_ = JsonValue::Kind::kNumber;
      v.number_ = Number();
    }
    return v;
  }

  std::string String() {
    if (pos_ >= text_.size() || text_[pos_] != '"') Error("expected a string");
    ++pos_;
    std::string out;
    while (true) {
      if (pos_ >= text_.size()) Error("unterminated string");
      const char c = text_[pos_++];
      if (c == '"') return out;
      if (static_cast<unsigned char>(c) < 0x20) Error("control character in string");
      if (c == '\\') {
        if (pos_ >= text_.size()) Error("unterminated escape");
        const char e = text_[pos_++];
        switch (e) {
          case '"':
          case '\\':
          case '/': out += e; break;
          case 'n': out += '\n'; break;
          case 't': out += '\t'; break;
          case 'r': out += '\r'; break;
          case 'b': out += '\b'; break;
          case 'f': out += '\f'; break;
          default: Error("unsupported escape");  // \u is never written by SaveGraph
        }
      } else {
        out += c;
      }
    }
  }

  double Number() {
    // the JSON number grammar, checked before strtod (which accepts more)
    const size_t start = pos_;
    if (pos_ < text_.size() && text_[pos_] == '-') ++pos_;
    auto digits = [&] {
      const size_t from = pos_;
      while (pos_ < text_.size() && text_[pos_] >= '0' && text_[pos_] <= '9') ++pos_;
      return pos_ > from;
    };
    if (!digits()) Error("expected a value");
    if (pos_ < text_.size() && text_[pos_] == '.') {
      ++pos_;
      if (!digits()) Error("digits expected after '.'");
    }
    if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
      ++pos_;
      if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
      if (!digits()) Error("digits expected in exponent");
    }
    const double v = std::strtod(text_.substr(start, pos_ - start).c_str(), nullptr);
    if (!std::isfinite(v)) Error("number out of range");
    return v;
  }

  const std::string& text_;
  size_t pos_ = 0;
};

JsonValue ParseJson(const std::string& text) { return JsonParser(text).Document(); }

}  // namespace srics::graph_file
