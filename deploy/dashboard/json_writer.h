#pragma once
// A small JSON text builder: objects, arrays, strings (escaped), numbers (non-finite ones as
// null, since JSON has no NaN), booleans and null. The caller nests Begin/End calls; commas
// are placed automatically.
//
//   JsonWriter json;
//   json.BeginObject();
//   json.Key("env_steps").Number(1200);
//   json.Key("curve").BeginArray().Number(0.5).Number(0.25).EndArray();
//   json.EndObject();
//   std::string text = json.Take();   // {"env_steps":1200,"curve":[0.5,0.25]}

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace srics::dashboard {

class JsonWriter {
 public:
  JsonWriter& BeginObject();
  JsonWriter& EndObject();
  JsonWriter& BeginArray();
  JsonWriter& EndArray();
  // The key of the next value inside an object.
  JsonWriter& Key(std::string_view key);
  JsonWriter& String(std::string_view text);
  // `digits` significant digits (7: a float's; 15 for Unix times); null when not finite
  JsonWriter& Number(double value, int digits = 7);
  JsonWriter& Integer(int64_t value);
  JsonWriter& Unsigned(uint64_t value);
  JsonWriter& Bool(bool value);
  JsonWriter& Null();

  // The text so far (complete once every Begin has its End), and the writer is emptied.
  std::string Take();

 private:
  void BeforeValue();
  // an object's or an array's bracket
  JsonWriter& Open(char bracket);
  JsonWriter& Close(char bracket);
  std::string out_;
  std::vector<bool> first_;  // per open container: no element yet
  bool after_key_ = false;
};

// `text` as a JSON string literal with its quotes; control characters, quotes and backslashes
// escaped, bytes >= 0x80 passed through.
std::string JsonQuoted(std::string_view text);

}  // namespace srics::dashboard
