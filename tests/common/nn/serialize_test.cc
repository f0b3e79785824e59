// Flat weights and checkpoint files: exact round trips and one message per failure.
#include "common/nn/serialize.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/nn/modules.h"
#include "tests/common/files/test_files.h"

namespace srics::nn {
namespace {

using files::testing::ReadFile;

void WriteAll(const std::string& path, const std::string& data) {
  std::ofstream f(path, std::ios::binary | std::ios::trunc);
  f.write(data.data(), static_cast<std::streamsize>(data.size()));
}

class SerializeTest : public ::testing::Test {
 protected:
  SerializeTest() : mlp_("net", 3, {5}, 2, rng_) { mlp_.Parameters(params_); }
  void SetUp() override { path_ = (dir_ / "ckpt.bin").string(); }
  // Expects LoadParameters(path) to throw CheckpointError whose message contains `what`.
  void ExpectFailure(const std::string& what, const ParameterList<float>& params) {
    try {
      LoadParameters(path_, params);
      FAIL() << "no error, expected '" << what << "'";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path_), std::string::npos) << e.what();
    }
  }
  // Loads path_ into a fresh network of the same shape (other initial weights) and expects
  // exactly params_' values.
  void ExpectLoadsBackExactly() {
    Rng other(10);
    Mlp<float> copy("net", 3, {5}, 2, other);
    ParameterList<float> cp;
    copy.Parameters(cp);
    LoadParameters(path_, cp);
    for (size_t i = 0; i < params_.size(); ++i) EXPECT_EQ(params_[i]->value, cp[i]->value);
  }
  Rng rng_{9};
  Mlp<float> mlp_;
  ParameterList<float> params_;
  files::testing::ScratchFolder dir_{"srics_nn_serialize"};
  std::string path_;
};

TEST_F(SerializeTest, FlattenLoadRoundTripIsExact) {
  const auto flat = Flatten(params_);
  EXPECT_EQ(static_cast<int64_t>(flat.size()), NumScalars(params_));
  Rng other(10);
  Mlp<float> copy("net", 3, {5}, 2, other);
  ParameterList<float> copy_params;
  copy.Parameters(copy_params);
  EXPECT_EQ(SignatureHash(params_), SignatureHash(copy_params));
  EXPECT_NE(params_[0]->value, copy_params[0]->value);
  LoadFlat(copy_params, flat);
  for (size_t i = 0; i < params_.size(); ++i) EXPECT_EQ(params_[i]->value, copy_params[i]->value);
  EXPECT_THROW(LoadFlat(copy_params, std::span<const float>(flat).first(flat.size() - 1)), std::invalid_argument);
}

TEST_F(SerializeTest, SignatureNamesShapes) {
  EXPECT_EQ(SignatureString(params_), "net.0.w:3x5;net.0.b:1x5;net.1.w:5x2;net.1.b:1x2;");
  Mlp<float> wider("net", 3, {6}, 2, rng_);
  ParameterList<float> wp;
  wider.Parameters(wp);
  EXPECT_NE(SignatureHash(params_), SignatureHash(wp));
}

TEST_F(SerializeTest, CheckpointRoundTripIsExact) {
  SaveParameters(path_, params_);
  ExpectLoadsBackExactly();
  // several sections, e.g. weights and optimizer state
  WriteCheckpoint(
      path_, {{"policy", SignatureString(params_), Flatten(params_), {}}, {"policy.adam", "", {1.f, 2.f, 3.f}, {}}});
  const auto sections = ReadCheckpoint(path_);
  ASSERT_EQ(sections.size(), 2u);
  EXPECT_EQ(FindSection(sections, "policy.adam", path_).values, (std::vector<float>{1, 2, 3}));
  LoadSection(FindSection(sections, "policy", path_), params_, path_);
  EXPECT_THROW(FindSection(sections, "q1", path_), CheckpointError);
}

TEST_F(SerializeTest, MissingFile) { ExpectFailure("cannot open", params_); }

// A sound file (its checksum right) whose section carries the architecture's signature but not
// its number of values is refused as a checkpoint error naming both counts (the fuzzer's find:
// it was a std::invalid_argument from LoadFlat, which callers that catch CheckpointError did not).
TEST_F(SerializeTest, ASectionWithTheRightSignatureAndTheWrongCountIsRefused) {
  for (const std::vector<float>& values : {std::vector<float>{}, std::vector<float>(3, 0.5f)}) {
    WriteCheckpoint(path_, {{"parameters", SignatureString(params_), values, {}}});
    ExpectFailure("holds " + std::to_string(values.size()) + " values, its architecture has " +
                      std::to_string(NumScalars(params_)),
                  params_);
  }
}

TEST_F(SerializeTest, TruncatedFile) {
  SaveParameters(path_, params_);
  const std::string data = ReadFile(path_);
  for (size_t keep : {size_t{4}, size_t{20}, data.size() / 2, data.size() - 3}) {
    SCOPED_TRACE(keep);
    WriteAll(path_, data.substr(0, keep));
    ExpectFailure("truncated", params_);
  }
}

TEST_F(SerializeTest, CorruptedPayload) {
  SaveParameters(path_, params_);
  std::string data = ReadFile(path_);
  data[data.size() - 20] ^= 0x10;  // a bit inside the weights
  WriteAll(path_, data);
  ExpectFailure("checksum mismatch (corrupted)", params_);
}

TEST_F(SerializeTest, BadMagic) {
  WriteAll(path_, "this is not a checkpoint, just some text of a decent length");
  ExpectFailure("bad magic", params_);
}

TEST_F(SerializeTest, UnsupportedVersion) {
  SaveParameters(path_, params_);
  std::string data = ReadFile(path_);
  data[8] = 99;  // the version field follows the 8-byte magic
  WriteAll(path_, data);
  ExpectFailure("unsupported format version 99 (this build reads versions 1 to 2)", params_);
}

TEST_F(SerializeTest, ArchitectureMismatch) {
  SaveParameters(path_, params_);
  Mlp<float> wider("net", 3, {6}, 2, rng_);
  ParameterList<float> wp;
  wider.Parameters(wp);
  ExpectFailure("architecture mismatch", wp);
  try {
    LoadParameters(path_, wp);
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("net.0.w:3x5"), std::string::npos) << e.what();
  }
}

TEST_F(SerializeTest, ByteSectionsRoundTripAndReadersReportTruncation) {
  ByteWriter w;
  w.Put<std::uint32_t>(7);
  w.PutVector(std::vector<std::uint16_t>{1, 2, 3});
  w.PutString("state text");
  std::string bytes = w.Take();
  WriteCheckpoint(path_, {{"values", "", {4.f}, {}}, {"blob", "", {}, bytes}});
  const auto sections = ReadCheckpoint(path_);
  ASSERT_EQ(sections.size(), 2u);
  EXPECT_EQ(sections[0].values, std::vector<float>{4.f});
  EXPECT_TRUE(sections[0].bytes.empty());
  ByteReader r(FindSection(sections, "blob", path_).bytes, "blob");
  EXPECT_EQ(r.Get<std::uint32_t>(), 7u);
  EXPECT_EQ(r.GetVector<std::uint16_t>(), (std::vector<std::uint16_t>{1, 2, 3}));
  EXPECT_EQ(r.GetString(), "state text");
  EXPECT_TRUE(r.done());
  EXPECT_THROW(r.Get<std::uint8_t>(), CheckpointError);
  // a count larger than what follows is "truncated", never an allocation of that size
  ByteWriter big;
  big.Put<std::uint64_t>(std::uint64_t{1} << 60);
  const std::string huge = big.Take();
  ByteReader h(huge, "huge");
  try {
    h.GetVector<float>();
    FAIL() << "no error";
  } catch (const CheckpointError& e) {
    EXPECT_NE(std::string(e.what()).find("huge: truncated"), std::string::npos) << e.what();
  }
}

// Found by tests/fuzz (fuzz_checkpoint): a section without values and an empty ByteWriter
// vector were read with memcpy into a null vector data() (undefined behaviour that UBSan
// reports; the plain build shows nothing, ./tests/fuzz.sh does on its seed corpus).
TEST_F(SerializeTest, EmptySectionsAndVectorsAreRead) {
  ByteWriter w;
  w.PutVector(std::vector<float>{});
  WriteCheckpoint(path_, {{"empty", "", {}, {}}, {"blob", "", {}, w.Take()}});
  const auto sections = ReadCheckpoint(path_);
  ASSERT_EQ(sections.size(), 2u);
  EXPECT_TRUE(sections[0].values.empty());
  ByteReader r(sections[1].bytes, "blob");
  EXPECT_TRUE(r.GetVector<float>().empty());
  EXPECT_TRUE(r.done());
}

TEST_F(SerializeTest, RandomStreamStateRoundTrips) {
  Rng a(42);
  a();
  Rng b(1);
  SetRngState(&b, RngState(a), "rng");
  EXPECT_EQ(a(), b());
  EXPECT_THROW(SetRngState(&b, "not a state", "rng"), CheckpointError);
}

// A file of format version 1 (sections without bytes, written before the replay was
// checkpointed) is still read.
TEST_F(SerializeTest, Version1FilesAreStillRead) {
  const std::vector<float> flat = Flatten(params_);
  const std::string sig = SignatureString(params_);
  std::string buf("SRICSNN1", 8);
  auto put = [&buf](auto v) { buf.append(reinterpret_cast<const char*>(&v), sizeof v); };
  put(std::uint32_t{1});
  put(std::uint32_t{1});
  put(std::uint32_t{10});
  buf += "parameters";
  put(static_cast<std::uint32_t>(sig.size()));
  buf += sig;
  put(static_cast<std::uint64_t>(flat.size()));
  buf.append(reinterpret_cast<const char*>(flat.data()), flat.size() * sizeof(float));
  put(Fnv1a(buf.data(), buf.size()));
  WriteAll(path_, buf);
  ExpectLoadsBackExactly();
  EXPECT_TRUE(ReadCheckpoint(path_)[0].bytes.empty());
}

}  // namespace
}  // namespace srics::nn
