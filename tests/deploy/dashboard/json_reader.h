#pragma once
// The dashboard tests read its documents with the project's own strict JSON parser
// (common/graph_file/json.h: one value and nothing after it, no trailing commas, no NaN, else
// Parse throws), the way the tests use them: doc["runs"][0]["env_steps"].as<uint64_t>().

#include <cstddef>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/graph_file/json.h"

namespace srics::dashboard::testing {

// A value of a parsed document; it keeps the whole document alive.
class Json {
 public:
  static Json Parse(const std::string& text) {
    auto document = std::make_shared<const graph_file::JsonValue>(graph_file::ParseJson(text));
    const graph_file::JsonValue* value = document.get();
    return Json(std::move(document), value);
  }

  bool IsNull() const { return value_->kind() == Kind::kNull; }
  // The items of an array, the members of an object, 0 for any other value.
  size_t size() const {
    if (value_->kind() == Kind::kArray) return value_->AsArray().size();
    return value_->kind() == Kind::kObject ? value_->AsObject().size() : 0;
  }
  // Throws when this is not an array or has no item i / not an object or has no such key.
  Json operator[](size_t i) const { return Json(document_, &value_->AsArray().at(i)); }
  Json operator[](int i) const { return (*this)[static_cast<size_t>(i)]; }
  Json operator[](const std::string& key) const { return Json(document_, &value_->Get(key)); }
  std::vector<Json> items() const {
    std::vector<Json> out;
    for (const graph_file::JsonValue& item : value_->AsArray()) out.push_back(Json(document_, &item));
    return out;
  }

  // The value as a string, bool or number; throws when it is of another type (or, for an
  // integer type, not an integer).
  template <typename T>
  T as() const {
    if constexpr (std::is_same_v<T, std::string>)
      return value_->AsString();
    else if constexpr (std::is_same_v<T, bool>)
      return value_->AsBool();
    else if constexpr (std::is_integral_v<T>)
      return static_cast<T>(value_->AsInt());
    else
      return static_cast<T>(value_->AsDouble());
  }

 private:
  using Kind = graph_file::JsonValue::Kind;
  Json(std::shared_ptr<const graph_file::JsonValue> document, const graph_file::JsonValue* value)
      : document_(std::move(document)), value_(value) {}

  std::shared_ptr<const graph_file::JsonValue> document_;
  const graph_file::JsonValue* value_;
};

}  // namespace srics::dashboard::testing
