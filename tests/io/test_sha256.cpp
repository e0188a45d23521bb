// io::Sha256 beyond the short test vectors (test_output_directory.cpp): a message whose padding takes a third block,
// every length around the padding's block boundaries against coreutils' sha256sum (another implementation), and the
// incremental interface against the one-shot one for every split of a message, and moves.
#include <gtest/gtest.h>

#include <cstddef>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/run_command.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/io/sha256.hpp"

namespace seqtopo::io {
namespace {

// Bytes 0..255 in a scrambled order, zeros included: no text-only shortcut can pass.
std::string message(std::size_t length) {
  std::string m(length, '\0');
  for (std::size_t k = 0; k < length; ++k) m[k] = static_cast<char>((k * 167 + 13) % 256);
  return m;
}

TEST(Sha256, ThreeBlockMessage) {
  // The 896-bit message of FIPS 180-2's SHA-384/512 examples (the 448-bit one of SHA-256 is in KnownDigests): 112
  // bytes, so the padding and the length go into a third 64-byte block.
  EXPECT_EQ(
      sha256_hex("abcdefghbcdefghicdefghijdefghijkefghijklfghijklmghijklmnhijklmnoijklmnopjklmnopqklmnopqrlmnopqrs"
                 "mnopqrstnopqrstu"),
      "cf5b16a778af8380036ce59e7b0492370b249b11e8f07a51afac45037afee9d1");
  // one byte changed changes the digest
  EXPECT_NE(sha256_hex("abd"), sha256_hex("abc"));
}

// The padding: 55 bytes fit one block with the length, 56 need a second; 64, 119, 120 and 128 likewise. Every length
// from 0 to 200 is hashed here and by sha256sum.
TEST(Sha256, EveryLengthAroundTheBlockBoundariesAgreesWithSha256sum) {
  const test_support::TempDir dir;
  constexpr std::size_t kLongest = 200;
  std::ostringstream command;
  command << "cd '" << dir.path.string() << "' && sha256sum";
  for (std::size_t length = 0; length <= kLongest; ++length) {
    dir.write(std::to_string(length), message(length));
    command << ' ' << length;
  }
  const auto r = test_support::run_command(command.str());
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  std::size_t checked = 0;
  for (std::string digest, name; lines >> digest >> name; ++checked) {
    SCOPED_TRACE(::testing::Message() << "length " << name);
    EXPECT_EQ(sha256_hex(message(std::stoul(name))), digest);
  }
  EXPECT_EQ(checked, kLongest + 1);
}

TEST(Sha256, PiecesGiveTheDigestOfTheWhole) {
  for (const std::size_t length : {0, 1, 55, 56, 63, 64, 65, 127, 128, 129, 300}) {
    const std::string m = message(length);
    const std::string whole = sha256_hex(m);
    for (std::size_t split = 0; split <= length; ++split) {
      Sha256 h;
      h.update(std::string_view(m).substr(0, split));
      h.update(std::string_view(m).substr(split));
      ASSERT_EQ(h.hex(), whole) << "length " << length << " split at " << split;
    }
    // byte by byte, with empty updates between
    Sha256 bytes;
    for (const char c : m) {
      bytes.update({});
      bytes.update(std::string_view(&c, 1));
    }
    EXPECT_EQ(bytes.hex(), whole) << "length " << length;
  }
}

// The digest object owns OpenSSL's context: a move hands it over; a spent or moved-from object refuses input
// instead of hashing into freed state.
TEST(Sha256, MovesAndMisuse) {
  const std::string m = message(1000);
  Sha256 h;
  h.update(std::string_view(m).substr(0, 400));
  Sha256 moved = std::move(h);
  moved.update(std::string_view(m).substr(400));
  EXPECT_EQ(moved.hex(), sha256_hex(m));
  EXPECT_THROW(moved.update("x"), std::logic_error);
  EXPECT_THROW((void)moved.hex(), std::logic_error);
  EXPECT_THROW(h.update("x"), std::logic_error);  // NOLINT(bugprone-use-after-move): the moved-from state is defined
  Sha256 assigned;
  assigned = Sha256();
  assigned.update("abc");
  EXPECT_EQ(assigned.hex(), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace seqtopo::io
