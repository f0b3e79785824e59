#include "common/nn/serialize.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>

namespace srics::nn {
namespace {

constexpr char kMagic[8] = {'S', 'R', 'I', 'C', 'S', 'N', 'N', '1'};

template <typename V>
void Put(std::string& out, V v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof(V));
}

// reads from a byte buffer; every read past the end is a truncated file
class Reader {
 public:
  Reader(const std::string& data, size_t end, const std::string& path) : data_(data), end_(end), path_(path) {}
  template <typename V>
  V Get() {
    V v;
    std::memcpy(&v, Take(sizeof(V)), sizeof(V));
    return v;
  }
  const char* Take(size_t n) {
    if (n > end_ - pos_) {
      throw CorruptCheckpointError("checkpoint " + path_ + ": truncated (needs " + std::to_string(pos_ + n) +
                                   " bytes, has " + std::to_string(end_) + ")");
    }
    const char* p = data_.data() + pos_;
    pos_ += n;
    return p;
  }
  size_t pos() const { return pos_; }

 private:
  const std::string& data_;
  size_t end_;
  size_t pos_ = 0;
  const std::string& path_;
};

// first parameter entry where two signature strings differ, for the error message
std::string FirstDifference(const std::string& a, const std::string& b) {
  size_t i = 0, start = 0;
  while (i < a.size() && i < b.size() && a[i] == b[i]) {
    if (a[i] == ';') start = i + 1;
    ++i;
  }
  auto entry = [&](const std::string& s) {
    const size_t end = s.find(';', start);
    return start >= s.size() ? std::string("<end>") : s.substr(start, end - start);
  };
  return "file has '" + entry(a) + "', model has '" + entry(b) + "'";
}

}  // namespace

std::uint64_t Fnv1a(const void* data, size_t size, std::uint64_t seed) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = seed;
  for (size_t i = 0; i < size; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

template <typename T>
std::string SignatureString(const ParameterList<T>& params) {
  std::string s;
  for (const Parameter<T>* p : params) {
    s += p->name + ":" + std::to_string(p->value.rows()) + "x" + std::to_string(p->value.cols()) + ";";
  }
  return s;
}

template <typename T>
std::uint64_t SignatureHash(const ParameterList<T>& params) {
  const std::string s = SignatureString(params);
  return Fnv1a(s.data(), s.size());
}

template <typename T>
std::vector<float> Flatten(const ParameterList<T>& params) {
  std::vector<float> out;
  out.reserve(static_cast<size_t>(NumScalars(params)));
  for (const Parameter<T>* p : params) {
    for (Eigen::Index i = 0; i < p->value.size(); ++i) {
      out.push_back(static_cast<float>(p->value.data()[i]));
    }
  }
  return out;
}

template <typename T>
void LoadFlat(const ParameterList<T>& params, std::span<const float> flat) {
  const auto expected = static_cast<size_t>(NumScalars(params));
  if (flat.size() != expected) {
    throw std::invalid_argument("nn::LoadFlat: " + std::to_string(flat.size()) + " values for a model of " +
                                std::to_string(expected));
  }
  size_t pos = 0;
  for (Parameter<T>* p : params) {
    for (Eigen::Index i = 0; i < p->value.size(); ++i) {
      p->value.data()[i] = static_cast<T>(flat[pos++]);
    }
  }
}

std::string RngState(const Rng& rng) {
  std::ostringstream out;
  out << rng;
  return out.str();
}

void SetRngState(Rng* rng, const std::string& state, const std::string& what) {
  std::istringstream in(state);
  Rng parsed;
  in >> parsed;
  if (in.fail()) throw CheckpointError(what + ": not the state of a random stream");
  *rng = parsed;
}

std::string CheckpointBytes(const std::vector<CheckpointSection>& sections) {
  std::string buf(kMagic, sizeof(kMagic));
  Put<std::uint32_t>(buf, kCheckpointVersion);
  Put<std::uint32_t>(buf, static_cast<std::uint32_t>(sections.size()));
  for (const CheckpointSection& s : sections) {
    Put<std::uint32_t>(buf, static_cast<std::uint32_t>(s.name.size()));
    buf += s.name;
    Put<std::uint32_t>(buf, static_cast<std::uint32_t>(s.signature.size()));
    buf += s.signature;
    Put<std::uint64_t>(buf, s.values.size());
    buf.append(reinterpret_cast<const char*>(s.values.data()), s.values.size() * sizeof(float));
    Put<std::uint64_t>(buf, s.bytes.size());
    buf += s.bytes;
  }
  Put<std::uint64_t>(buf, Fnv1a(buf.data(), buf.size()));
  return buf;
}

void WriteCheckpoint(const std::string& path, std::vector<CheckpointSection> sections, int keep,
                     files::FileSystem& fs) {
  const std::string bytes = CheckpointBytes(sections);
  std::vector<CheckpointSection>().swap(sections);
  try {
    if (keep > 1)
      files::WriteGeneration(path, keep, bytes, fs);
    else
      files::WriteFileDurably(path, bytes, fs);
  } catch (const files::FileError& e) {
    throw CheckpointError(std::string("checkpoint not written: ") + e.what());
  }
}

std::vector<CheckpointSection> ReadCheckpoint(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw CheckpointError("checkpoint " + path + ": cannot open");
  const std::string data((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  if (data.size() >= sizeof(kMagic) && std::memcmp(data.data(), kMagic, sizeof(kMagic)) != 0) {
    throw CorruptCheckpointError("checkpoint " + path + ": not a checkpoint (bad magic)");
  }
  const size_t min_size = sizeof(kMagic) + 8 + 8;
  if (data.size() < min_size) {
    throw CorruptCheckpointError("checkpoint " + path + ": truncated (" + std::to_string(data.size()) + " bytes)");
  }
  std::uint64_t stored;
  std::memcpy(&stored, data.data() + data.size() - 8, 8);
  const bool checksum_ok = stored == Fnv1a(data.data(), data.size() - 8);
  Reader r(data, data.size() - 8, path);
  r.Take(sizeof(kMagic));
  const auto version = r.Get<std::uint32_t>();
  // another format version is not called corrupt (whatever its checksum): a newer build's
  // checkpoint must not be set aside by an older build
  if (version < kOldestCheckpointVersion || version > kCheckpointVersion) {
    throw CheckpointError("checkpoint " + path + ": unsupported format version " + std::to_string(version) +
                          " (this build reads versions " + std::to_string(kOldestCheckpointVersion) + " to " +
                          std::to_string(kCheckpointVersion) + ")");
  }
  // the sections are parsed before the checksum so that a cut file reports "truncated"
  std::vector<CheckpointSection> sections;
  const auto count = r.Get<std::uint32_t>();
  for (std::uint32_t i = 0; i < count; ++i) {
    CheckpointSection s;
    const auto name_len = r.Get<std::uint32_t>();
    s.name.assign(r.Take(name_len), name_len);
    const auto sig_len = r.Get<std::uint32_t>();
    s.signature.assign(r.Take(sig_len), sig_len);
    const auto n = r.Get<std::uint64_t>();
    if (n > data.size() / sizeof(float)) r.Take(data.size());  // reports truncated
    s.values.resize(n);
    const char* values = r.Take(n * sizeof(float));
    if (n > 0) std::memcpy(s.values.data(), values, n * sizeof(float));  // data() may be null for none
    if (version >= 2) {
      const auto b = r.Get<std::uint64_t>();
      if (b > data.size()) r.Take(data.size());  // reports truncated
      s.bytes.assign(r.Take(b), b);
    }
    sections.push_back(std::move(s));
  }
  if (r.pos() != data.size() - 8 || !checksum_ok) {
    throw CorruptCheckpointError("checkpoint " + path + ": checksum mismatch (corrupted)");
  }
  return sections;
}

const CheckpointSection& FindSection(const std::vector<CheckpointSection>& sections, const std::string& name,
                                     const std::string& path) {
  for (const CheckpointSection& s : sections) {
    if (s.name == name) return s;
  }
  throw CheckpointError("checkpoint " + path + ": no section '" + name + "'");
}

template <typename T>
void LoadSection(const CheckpointSection& section, const ParameterList<T>& params, const std::string& path) {
  const std::string sig = SignatureString(params);
  if (section.signature != sig) {
    const auto h = [](const std::string& s) { return std::to_string(Fnv1a(s.data(), s.size())); };
    throw CheckpointError("checkpoint " + path + ": architecture mismatch in section '" + section.name +
                          "' (signature " + h(section.signature) + " vs " + h(sig) + "; " +
                          FirstDifference(section.signature, sig) + ")");
  }
  // the signature names every shape, so a sound file holds exactly their values
  if (section.values.size() != static_cast<size_t>(NumScalars(params)))
    throw CheckpointError("checkpoint " + path + ": section '" + section.name + "' holds " +
                          std::to_string(section.values.size()) + " values, its architecture has " +
                          std::to_string(NumScalars(params)));
  LoadFlat(params, section.values);
}

template <typename T>
void SaveParameters(const std::string& path, const ParameterList<T>& params) {
  WriteCheckpoint(path, {{"parameters", SignatureString(params), Flatten(params), {}}});
}

template <typename T>
void LoadParameters(const std::string& path, const ParameterList<T>& params, const std::string& section) {
  const auto sections = ReadCheckpoint(path);
  LoadSection(FindSection(sections, section, path), params, path);
}

#define SRICS_NN_INSTANTIATE(T)                                                                        \
  template std::string SignatureString<T>(const ParameterList<T>&);                                    \
  template std::uint64_t SignatureHash<T>(const ParameterList<T>&);                                    \
  template std::vector<float> Flatten<T>(const ParameterList<T>&);                                     \
  template void LoadFlat<T>(const ParameterList<T>&, std::span<const float>);                          \
  template void LoadSection<T>(const CheckpointSection&, const ParameterList<T>&, const std::string&); \
  template void SaveParameters<T>(const std::string&, const ParameterList<T>&);                        \
  template void LoadParameters<T>(const std::string&, const ParameterList<T>&, const std::string&);
SRICS_NN_INSTANTIATE(float)
SRICS_NN_INSTANTIATE(double)
#undef SRICS_NN_INSTANTIATE

}  // namespace srics::nn
