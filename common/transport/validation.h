#pragma once
// Checks of received samples, pure functions on the domain value and its envelope (no DDS): a
// sample from the network is untrusted until Validate() accepted it. Readers run these on every
// sample right after its one conversion, count what they drop and log it at a limited rate;
// writers run them before sending.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "common/rl/episode.h"
#include "common/rl/updates.h"
#include "common/transport/wire.h"

namespace srics::transport {

// Sane bounds beyond which a sample is treated as malformed (keeps a hostile or corrupt
// sample from making a reader allocate or loop without limit). Episodes: rl::EpisodeLimits.
inline constexpr uint32_t kMaxEntities = rl::kMaxEntities;  // ancestor masks are 64-bit
inline constexpr uint64_t kMaxParameters = 64ull << 20;     // 64 Mi floats = 256 MiB

enum class Verdict {
  kAccept,     // well-formed and of this run
  kOtherRun,   // well-formed but of another run (ignored, counted apart)
  kMalformed,  // breaks the contract: dropped, counted, logged
};

struct Validation {
  Verdict verdict = Verdict::kAccept;
  std::string reason;   // empty when accepted; otherwise says what is wrong, for the log
  std::string counter;  // kMalformed: the rejection counter it counts in ("weights.checksum")
  bool ok() const { return verdict == Verdict::kAccept; }
};

// The envelope of every sample: kMalformed unless contract_version == kContractVersion and
// msg_run_id is non-empty and within bounds; kOtherRun when `run_id` is not empty and differs.
// Episode readers run it on the received C sample, before copying anything.
Validation ValidateEnvelope(uint32_t contract_version, const std::string& msg_run_id, std::string_view run_id);

// Each returns kMalformed with a reason for the first violation found, else kOtherRun when
// `run_id` is not empty and differs from the sample's, else kAccept. The rules (also in
// idl/README.md): the envelope above; sequence lengths match the declared layout; enums in
// range; every float finite; indices and masks inside [0, N); policy parameters within
// +-rl::kMaxAbsParameter; distances of evaluations non-negative. Episodes: rl::ValidateEpisode.
// The counter of a malformed verdict is "<topic>.<check>" (README: the table of checks).
// `checksum`: the sample's, checked against the parameters (ParameterChecksum); none skips the
// CRC (for a writer that has just computed it).
Validation Validate(const rl::WeightsUpdate& weights, const Envelope& envelope, std::optional<uint32_t> checksum,
                    std::string_view run_id);
Validation Validate(const rl::GraphUpdate& update, const Envelope& envelope, std::string_view run_id);
Validation Validate(const rl::EvalReport& report, const Envelope& envelope, std::string_view run_id);
Validation Validate(const rl::LearnerReport& stats, const Envelope& envelope, std::string_view run_id);
Validation Validate(const rl::NodeStatus& status, const Envelope& envelope, std::string_view run_id);

// CRC-32 (IEEE 802.3, as zlib's crc32) of the parameters' bytes in memory order (IEEE-754
// little-endian floats on every supported host): the PolicyWeights checksum.
uint32_t ParameterChecksum(const std::vector<float>& parameters);

}  // namespace srics::transport
