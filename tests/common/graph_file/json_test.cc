#include "common/graph_file/json.h"

#include <gtest/gtest.h>

#include <stdexcept>

namespace srics::graph_file {
namespace {

TEST(JsonTest, ParsesNestedValues) {
  const JsonValue v = ParseJson(R"({"a": [1, -2.5e-3, [true, null]], "b": "x\"y"})");
  ASSERT_TRUE(v.is_object());
  EXPECT_EQ(v.Get("a").AsArray()[0].AsInt(), 1);
  EXPECT_DOUBLE_EQ(v.Get("a").AsArray()[1].AsDouble(), -2.5e-3);
  EXPECT_EQ(v.Get("a").AsArray()[2].AsArray()[0].kind(), JsonValue::Kind::kBool);
  EXPECT_EQ(v.Get("b").AsString(), "x\"y");
}

TEST(JsonTest, RejectsMalformedText) {
  for (const char* bad : {"", "{", "{\"a\": 1,}", "[1 2]", "{\"a\" 1}", "01x", "[1] 2", "{\"a\": 1, \"a\": 2}",
                          "[1e999]", "\"abc", "[-]", "[1.]"}) {
    EXPECT_THROW(ParseJson(bad), std::runtime_error) << bad;
  }
  std::string deep(100, '[');
  EXPECT_THROW(ParseJson(deep), std::runtime_error);
}

TEST(JsonTest, TypedAccessorsCheckTypes) {
  const JsonValue v = ParseJson(R"({"n": 1.5, "s": "t"})");
  EXPECT_THROW(v.Get("n").AsInt(), std::runtime_error);
  EXPECT_THROW(v.Get("s").AsDouble(), std::runtime_error);
  EXPECT_THROW(v.Get("missing"), std::runtime_error);
  EXPECT_THROW(v.Get("n").AsArray(), std::runtime_error);
}

}  // namespace
}  // namespace srics::graph_file
