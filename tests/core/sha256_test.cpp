// SHA-256 against the FIPS 180-4 / NIST known answers, in one piece and streamed in odd chunks.
#include "exoid/core/sha256.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

namespace exoid::core {
namespace {

TEST(Sha256, KnownAnswers) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  const std::string million(1000000, 'a');
  EXPECT_EQ(sha256Hex(million), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

TEST(Sha256, StreamedInOddChunksAndFromAFileIsTheSame) {
  std::string text;
  for (int i = 0; i < 5000; ++i) text += static_cast<char>(i * 31 % 251);
  Sha256 s;
  for (std::size_t i = 0; i < text.size(); i += 63) s.update(std::string_view(text).substr(i, 63));
  const std::string whole = sha256Hex(text);
  EXPECT_EQ(s.hexDigest(), whole);
  const std::string path = ::testing::TempDir() + "/sha256_test.bin";
  std::ofstream(path, std::ios::binary) << text;
  EXPECT_EQ(sha256OfFile(path), whole);
  std::filesystem::remove(path);
  EXPECT_THROW(sha256OfFile(path), std::runtime_error);
}

}  // namespace
}  // namespace exoid::core
