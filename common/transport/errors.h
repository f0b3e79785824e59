#pragma once
// Exceptions of the transport. DDS failures carry the DDS return code and its text
// (dds_strretcode); back-pressure is not an exception but WriteResult::kBackPressure.

#include <cstdint>
#include <stdexcept>
#include <string>

namespace srics::transport {

// A DDS call failed: `what()` is "<operation>: <dds_strretcode text> (<code>)".
class DdsError : public std::runtime_error {
 public:
  DdsError(const std::string& operation, int32_t retcode);
  // The DDS_RETCODE_* value (negative).
  int32_t retcode() const { return retcode_; }

 private:
  int32_t retcode_;
};

// A message could not be sent because it breaks the contract (string too long, sizes that do
// not match the declared layout, ...); thrown by writers before anything goes on the wire.
class InvalidMessage : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace srics::transport
