#pragma once
// Fuzz input helpers (tests/fuzz only): a reader that fills the generated C types of
// idl/srics.idl from fuzz bytes, and the writer that encodes a C sample the same way (the
// seed corpora). Format, front to back, little-endian: scalars as their bytes; a char[N]
// string as a u16 length (cut to N, so it may lack its terminator) and its bytes; a sequence
// as a u32 element count and the elements (the count is cut to the bytes left and to
// kMaxElements, so every buffer holds its _length elements as a DDS sample does).
// Missing bytes read as zeros.

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace srics::fuzz {

inline constexpr uint32_t kMaxElements = 1u << 20;

class WireReader {
 public:
  WireReader(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  ~WireReader() {
    for (void* p : owned_) ::operator delete(p);
  }
  WireReader(const WireReader&) = delete;
  WireReader& operator=(const WireReader&) = delete;

  size_t left() const { return size_ - pos_; }

  template <typename V>
  requires std::is_arithmetic_v<V> || std::is_enum_v<V>
  void operator()(V& out) {
    unsigned char bytes[sizeof(V)] = {};
    Take(bytes, sizeof(V));
    std::memcpy(&out, bytes, sizeof(V));
  }
  template <size_t N>
  void operator()(char (&out)[N]) {
    uint16_t length = 0;
    (*this)(length);
    std::memset(out, 0, N);
    Take(out, std::min<size_t>({length, N, left()}));
  }
  template <typename Seq>
  requires requires(Seq s) { s._buffer; }
  void operator()(Seq& out) {
    using Element = std::remove_pointer_t<decltype(out._buffer)>;
    uint32_t count = 0;
    (*this)(count);
    count = static_cast<uint32_t>(std::min<size_t>({count, kMaxElements, left() / sizeof(Element)}));
    out._length = out._maximum = count;
    out._release = false;
    out._buffer = nullptr;
    if (count == 0) return;
    void* buffer = ::operator new(count * sizeof(Element));
    owned_.push_back(buffer);
    Take(buffer, count * sizeof(Element));
    out._buffer = static_cast<Element*>(buffer);
  }

 private:
  void Take(void* out, size_t n) {
    n = std::min(n, left());
    if (n > 0) std::memcpy(out, data_ + pos_, n);
    pos_ += n;
  }
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  std::vector<void*> owned_;
};

class WireWriter {
 public:
  template <typename V>
  requires std::is_arithmetic_v<V> || std::is_enum_v<V>
  void operator()(const V& in) { bytes_.append(reinterpret_cast<const char*>(&in), sizeof(V)); }
  template <size_t N>
  void operator()(const char (&in)[N]) {
    const uint16_t length = static_cast<uint16_t>(strnlen(in, N));
    (*this)(length);
    bytes_.append(in, length);
  }
  template <typename Seq>
  requires requires(Seq s) { s._buffer; }
  void operator()(const Seq& in) {
    (*this)(static_cast<uint32_t>(in._length));
    bytes_.append(reinterpret_cast<const char*>(in._buffer), in._length * sizeof(*in._buffer));
  }
  const std::string& bytes() const { return bytes_; }
  void Byte(uint8_t b) { bytes_.push_back(static_cast<char>(b)); }

 private:
  std::string bytes_;
};

// Writes `bytes` as file `name` in `dir` (the seed generators).
inline void WriteSeed(const std::string& dir, const std::string& name, const std::string& bytes) {
  std::filesystem::create_directories(dir);
  std::ofstream out(dir + "/" + name, std::ios::binary | std::ios::trunc);
  out << bytes;
  if (!out) throw std::runtime_error("cannot write seed " + dir + "/" + name);
}

// Set by tests/fuzz.sh --seeds: the harness writes its seed corpus there and exits.
inline const char* SeedDir() { return std::getenv("SRICS_FUZZ_WRITE_SEEDS"); }

}  // namespace srics::fuzz
