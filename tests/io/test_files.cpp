// FASTA reading and atomic outputs.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/fasta.hpp"

namespace seqtopo::io {
namespace {
namespace fs = std::filesystem;

class Files : public ::testing::Test {
 protected:
  const test_support::TempDir dir_;
};

TEST_F(Files, FastaRecordsAndErrors) {
  const auto records = read_fasta(dir_.write("ok.fa", ">one first\nACGT\nAC GT\r\n\n>two\nTT\n"));
  ASSERT_EQ(records.size(), 2U);
  EXPECT_EQ(records[0].name, "one first");
  EXPECT_EQ(records[0].sequence, "ACGTACGT");
  EXPECT_EQ(records[1].sequence, "TT");
  EXPECT_THROW(read_fasta(dir_.path / "missing.fa"), InputError);
  EXPECT_THROW(read_fasta(dir_.write("empty.fa", "")), InputError);
  EXPECT_THROW(read_fasta(dir_.write("nohead.fa", "ACGT\n")), InputError);
  EXPECT_THROW(read_fasta(dir_.write("emptyrec.fa", ">a\n>b\nAC\n")), InputError);
  try {
    read_fasta(dir_.write("line.fa", "\nACGT\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), (dir_.path / "line.fa").string() + ":2");
  }
}

TEST_F(Files, AtomicFileReplacesWhole) {
  write_file_atomic(dir_.path / "a.txt", "first");
  write_file_atomic(dir_.path / "a.txt", "second");
  std::ifstream in(dir_.path / "a.txt");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text, "second");
  std::size_t files = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_.path)) ++files;
  EXPECT_EQ(files, 1U) << "no temporary file may be left behind";
  EXPECT_THROW(write_file_atomic(dir_.path / "no" / "such" / "dir.txt", "x"), InputError);
}

TEST_F(Files, OutputDirectoryIsAllOrNothing) {
  const fs::path out = dir_.path / "out";
  {
    OutputDirectory staged(out);
    staged.write("one.txt", "1");
    staged.write("sub/two.txt", "2");
    // destroyed without commit: as if a later stage had failed
  }
  EXPECT_FALSE(fs::exists(out)) << "an uncommitted output directory must leave nothing behind";
  EXPECT_TRUE(fs::is_empty(dir_.path)) << "nor its staging folder";
  {
    OutputDirectory staged(out);
    staged.write("one.txt", "1");
    staged.write("sub/two.txt", "2");
    const auto written = staged.commit();
    EXPECT_EQ(written.size(), 2U);
  }
  EXPECT_TRUE(fs::exists(out / "one.txt"));
  EXPECT_TRUE(fs::exists(out / "sub" / "two.txt"));
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(out)) ++entries;
  EXPECT_EQ(entries, 3U) << "one.txt, sub/ and manifest.json";
  entries = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir_.path)) ++entries;
  EXPECT_EQ(entries, 1U) << "the staging folder must be gone";
}

}  // namespace
}  // namespace seqtopo::io

#include "seqtopo/io/csv.hpp"

namespace seqtopo::io {
namespace {

TEST_F(Files, CsvRowsUnderAnExactHeader) {
  const auto path = dir_.write("c.csv", "# made by hand\na,b\r\n1,2\n\n# comment\nx,\n");
  const auto rows = read_csv(path, {"a", "b"});
  ASSERT_EQ(rows.size(), 2U);
  EXPECT_EQ(rows[0].fields, (std::vector<std::string>{"1", "2"}));
  EXPECT_EQ(rows[0].where, path.string() + ":3");
  EXPECT_EQ(rows[1].fields, (std::vector<std::string>{"x", ""})) << "a trailing empty field is a field";
  const std::vector<std::tuple<std::string, std::string, std::string>> bad = {
      {"hdr.csv", "a,c\n1,2\n", ":1"}, {"few.csv", "a,b\n1\n", ":2"}, {"many.csv", "a,b\n1,2,3\n", ":2"}};
  for (const auto& [name, text, subject] : bad) {
    try {
      read_csv(dir_.write(name, text), {"a", "b"});
      FAIL() << name;
    } catch (const InputError& e) {
      EXPECT_EQ(e.subject(), (dir_.path / name).string() + subject) << e.what();
    }
  }
  EXPECT_THROW(read_csv(dir_.write("empty.csv", "# nothing\n"), {"a", "b"}), InputError);
  EXPECT_THROW(read_csv(dir_.path / "missing.csv", {"a", "b"}), InputError);
}

}  // namespace
}  // namespace seqtopo::io
