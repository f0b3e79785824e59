#pragma once
// What the wire adds to the domain types of common/rl, without any DDS header: the contract
// version, the IDL's string bounds, the envelope every sample travels in, and what a reader
// receives for a value (the wire's precision). Per topic the generated C type of
// idl/srics.idl is the one wire type; common/transport converts it to and from the domain
// type once each way (convert.h). Field meanings and units: idl/README.md.

#include <cstddef>
#include <cstdint>
#include <string>

#include "common/rl/updates.h"

namespace srics::transport {

// Must equal srics::WIRE_CONTRACT_VERSION in idl/srics.idl (checked by a static_assert in the
// transport library). Readers reject samples carrying any other value.
inline constexpr uint32_t kContractVersion = 4;

// Bounds of the IDL's bounded strings (characters, without the terminating NUL).
inline constexpr size_t kRunIdMaxLength = 64;
inline constexpr size_t kArchitectureMaxLength = 256;
inline constexpr size_t kRoleMaxLength = 32;
inline constexpr size_t kHostMaxLength = 128;
inline constexpr size_t kDetailMaxLength = 256;

// What a sample carries besides its domain value: writers stamp it, readers check it
// (validation.h) and tell monitors the run id.
struct Envelope {
  uint32_t contract_version = kContractVersion;
  std::string run_id;
};

// The value a reader of the topic receives for `value`: floats at the wire's precision. The
// in-process run feeds its monitor these, so its files and display equal a DDS monitor's.
rl::LearnerReport AsReceived(const rl::LearnerReport& value);
rl::EvalReport AsReceived(const rl::EvalReport& value);
rl::GraphUpdate AsReceived(const rl::GraphUpdate& value);  // structure: masks and depths only

}  // namespace srics::transport
