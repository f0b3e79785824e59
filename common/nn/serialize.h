// Parameters as one flat float vector (the PolicyWeights payload) and checkpoint files.
//
// The architecture signature names every parameter and its shape in list order
// ("policy.attn.entity.w:9x80;..."); its 64-bit FNV-1a hash travels with the weights so a
// receiver can refuse weights of another architecture.
//
// Checkpoint file layout (little-endian):
//   magic "SRICSNN1" (8 bytes) | format version u32 | section count u32 |
//   per section: name length u32, name, signature length u32, signature, value count u64,
//                values (float32) |
//   checksum u64 (FNV-1a over every byte before it).
#ifndef SRICS_COMMON_NN_SERIALIZE_H_
#define SRICS_COMMON_NN_SERIALIZE_H_

#include <cstdint>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/nn/tensor.h"

namespace srics::nn {

// The human-readable architecture signature of a parameter list.
template <typename T>
std::string SignatureString(const ParameterList<T>& params);

// FNV-1a 64-bit hash of SignatureString: the compact signature sent with weights.
template <typename T>
std::uint64_t SignatureHash(const ParameterList<T>& params);

// FNV-1a 64-bit hash of raw bytes.
std::uint64_t Fnv1a(const void* data, size_t size, std::uint64_t seed = 14695981039346656037ull);

// All parameter values in list order, row-major within each parameter.
template <typename T>
std::vector<float> Flatten(const ParameterList<T>& params);

// Loads Flatten's output; throws std::invalid_argument (naming both sizes) when the count
// differs, and leaves the parameters unchanged in that case.
template <typename T>
void LoadFlat(const ParameterList<T>& params, std::span<const float> flat);

// Thrown by ReadCheckpoint and LoadParameters; what() says what was wrong with which file.
class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// One named block of a checkpoint: e.g. "policy" parameters, "policy.adam" optimizer state.
struct CheckpointSection {
  std::string name;
  std::string signature;  // SignatureString of what the values belong to (may be empty)
  std::vector<float> values;
};

// The format version written by WriteCheckpoint.
inline constexpr std::uint32_t kCheckpointVersion = 1;

// Writes sections atomically (to path + ".tmp", then rename). Throws CheckpointError.
void WriteCheckpoint(const std::string& path, const std::vector<CheckpointSection>& sections);

// Reads a checkpoint. Throws CheckpointError saying "cannot open", "truncated",
// "not a checkpoint (bad magic)", "unsupported format version", or "checksum mismatch
// (corrupted)".
std::vector<CheckpointSection> ReadCheckpoint(const std::string& path);

// Writes one section holding params (name "parameters").
template <typename T>
void SaveParameters(const std::string& path, const ParameterList<T>& params);

// Reads a SaveParameters file (or the section `section` of any checkpoint) into params.
// Throws CheckpointError; an "architecture mismatch" message names both signatures' hashes
// and the first differing parameter.
template <typename T>
void LoadParameters(const std::string& path, const ParameterList<T>& params,
                    const std::string& section = "parameters");

// Finds a section by name in sections read from path; throws CheckpointError if absent.
const CheckpointSection& FindSection(const std::vector<CheckpointSection>& sections,
                                     const std::string& name, const std::string& path);

// Checks that a section's signature matches params and loads its values.
template <typename T>
void LoadSection(const CheckpointSection& section, const ParameterList<T>& params,
                 const std::string& path);

}  // namespace srics::nn

#endif  // SRICS_COMMON_NN_SERIALIZE_H_
