#pragma once
// Parameters as one flat float vector (the PolicyWeights payload) and checkpoint files.
//
// The architecture signature names every parameter and its shape in list order
// ("policy.attn.entity.w:9x80;..."); its 64-bit FNV-1a hash travels with the weights so a
// receiver can refuse weights of another architecture.
//
// Checkpoint file layout (little-endian), format version 2:
//   magic "SRICSNN1" (8 bytes) | format version u32 | section count u32 |
//   per section: name length u32, name, signature length u32, signature, value count u64,
//                values (float32), byte count u64, bytes |
//   checksum u64 (FNV-1a over every byte before it).
// Version 1 (before the replay was checkpointed) has no byte count and bytes; it is still
// read (its sections have empty bytes).

#include <cstdint>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "common/files/durable_file.h"
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

// A checkpoint file whose bytes are damaged: truncated, not a checkpoint (bad magic), or a
// checksum mismatch. (A whole file of another architecture or a newer format is a
// CheckpointError but not corrupt: an older generation would not fit better.)
class CorruptCheckpointError : public CheckpointError {
 public:
  using CheckpointError::CheckpointError;
};

// One named block of a checkpoint: e.g. "policy" parameters, "policy.adam" optimizer state.
struct CheckpointSection {
  std::string name;
  std::string signature;  // SignatureString of what the values belong to (may be empty)
  std::vector<float> values;
  std::string bytes;  // anything else (a replay buffer, counters, RNG states): ByteWriter
};

// The format version written by WriteCheckpoint, and the oldest one ReadCheckpoint reads.
inline constexpr std::uint32_t kCheckpointVersion = 2;
inline constexpr std::uint32_t kOldestCheckpointVersion = 1;

// Builds the bytes of a section: fixed-width values and length-prefixed arrays, little-endian
// as the machine writes them (the checkpoint is read back by the same build family).
class ByteWriter {
 public:
  template <typename V>
  void Put(V value) {
    static_assert(std::is_trivially_copyable_v<V>);
    bytes_.append(reinterpret_cast<const char*>(&value), sizeof(V));
  }
  // a count (u64), then the elements
  template <typename V>
  void PutVector(const std::vector<V>& values) {
    static_assert(std::is_trivially_copyable_v<V>);
    Put<std::uint64_t>(values.size());
    bytes_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(V));
  }
  void PutString(const std::string& text) {
    Put<std::uint64_t>(text.size());
    bytes_ += text;
  }
  std::string Take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

// Reads what a ByteWriter wrote. Every read past the end throws CheckpointError
// "<what>: truncated ...", so a malformed section is an error, never a wild read.
class ByteReader {
 public:
  ByteReader(const std::string& bytes, std::string what) : bytes_(bytes), what_(std::move(what)) {}
  template <typename V>
  V Get() {
    V value;
    std::memcpy(&value, Take(sizeof(V)), sizeof(V));
    return value;
  }
  template <typename V>
  std::vector<V> GetVector() {
    const auto count = Get<std::uint64_t>();
    if (count > remaining() / sizeof(V)) Fail(count * sizeof(V));
    std::vector<V> values(count);
    const char* bytes = Take(count * sizeof(V));
    if (count > 0) std::memcpy(values.data(), bytes, count * sizeof(V));  // data() may be null for none
    return values;
  }
  std::string GetString() {
    const auto count = Get<std::uint64_t>();
    if (count > remaining()) Fail(count);
    return std::string(Take(count), count);
  }
  size_t remaining() const { return bytes_.size() - pos_; }
  bool done() const { return pos_ == bytes_.size(); }

 private:
  const char* Take(size_t n) {
    if (n > remaining()) Fail(n);
    const char* p = bytes_.data() + pos_;
    pos_ += n;
    return p;
  }
  [[noreturn]] void Fail(size_t wanted) const {
    throw CheckpointError(what_ + ": truncated (needs " + std::to_string(wanted) + " more bytes at offset " +
                          std::to_string(pos_) + ", has " + std::to_string(remaining()) + ")");
  }
  const std::string& bytes_;
  std::string what_;
  size_t pos_ = 0;
};

// A random stream's whole state as text (what std::mt19937_64 prints), and back. SetRngState
// throws CheckpointError naming `what` when the text is not such a state (the stream is
// unchanged then).
std::string RngState(const Rng& rng);
void SetRngState(Rng* rng, const std::string& state, const std::string& what);

// The bytes of a checkpoint file holding `sections`.
std::string CheckpointBytes(const std::vector<CheckpointSection>& sections);

// Writes sections durably (files::WriteFileDurably: to path + ".tmp", fsynced, renamed, the
// folder fsynced); with keep > 1 as the newest of `keep` generations (files::WriteGeneration:
// the previous one becomes path.1, ...). Throws CheckpointError naming the file and saying
// that the previous checkpoint is kept and the temporary file removed. Takes the sections (move
// them in) and frees them once the file's bytes are built, so the process holds about one copy
// of its state beside the state, not two, while the file is written
// (process::SetUpHeap says where that memory goes afterwards).
void WriteCheckpoint(const std::string& path, std::vector<CheckpointSection> sections, int keep = 1,
                     files::FileSystem& fs = files::FileSystem::Posix());

// Reads a checkpoint of any version from kOldestCheckpointVersion to kCheckpointVersion.
// Throws CheckpointError saying "cannot open" or "unsupported format version", or
// CorruptCheckpointError saying "truncated", "not a checkpoint (bad magic)" or "checksum
// mismatch (corrupted)".
std::vector<CheckpointSection> ReadCheckpoint(const std::string& path);

// Writes one section holding params (name "parameters").
template <typename T>
void SaveParameters(const std::string& path, const ParameterList<T>& params);

// Reads a SaveParameters file (or the section `section` of any checkpoint) into params.
// Throws CheckpointError; an "architecture mismatch" message names both signatures' hashes
// and the first differing parameter.
template <typename T>
void LoadParameters(const std::string& path, const ParameterList<T>& params, const std::string& section = "parameters");

// Finds a section by name in sections read from path; throws CheckpointError if absent.
const CheckpointSection& FindSection(const std::vector<CheckpointSection>& sections, const std::string& name,
                                     const std::string& path);

// Checks that a section's signature matches params and loads its values.
template <typename T>
void LoadSection(const CheckpointSection& section, const ParameterList<T>& params, const std::string& path);

}  // namespace srics::nn
