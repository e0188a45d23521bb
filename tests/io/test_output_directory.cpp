// io::OutputDirectory replaces a folder as a set (issue #18, findings 3-5), its manifest, and SHA-256.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "common/run_command.hpp"
#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/atomic_output.hpp"
#include "seqtopo/io/sha256.hpp"

namespace seqtopo::io {
namespace {
namespace fs = std::filesystem;
using test_support::read_file;

std::map<std::string, std::string> snapshot(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[e.path().lexically_relative(dir).generic_string()] = read_file(e.path());
  }
  return files;
}

std::size_t entries(const fs::path& dir) {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& e : fs::directory_iterator(dir)) ++n;
  return n;
}

void write_to(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

// A pid that no longer runs: a child that has exited and been waited for.
pid_t dead_pid() {
  const pid_t pid = ::fork();
  if (pid == 0) ::_exit(0);
  ::waitpid(pid, nullptr, 0);
  return pid;
}

class OutputDirectoryTest : public ::testing::Test {
 protected:
  void commit_set(const std::map<std::string, std::string>& files) {
    OutputDirectory out(out_);
    for (const auto& [name, bytes] : files) out.write(name, bytes);
    out.commit();
  }
  void expect_refused(const fs::path& dir, const std::string& fragment, OutputOptions options = {}) {
    try {
      OutputDirectory out(dir, std::move(options));
      ADD_FAILURE() << dir << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.subject(), dir.string());
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
  const test_support::TempDir dir_;
  const fs::path out_ = dir_.path / "out";
};

TEST(Sha256, KnownDigests) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(sha256_hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  Sha256 million;  // a million 'a' in uneven pieces
  const std::string piece(997, 'a');
  std::size_t left = 1000000;
  for (; left >= piece.size(); left -= piece.size()) million.update(piece);
  million.update(std::string(left, 'a'));
  EXPECT_EQ(million.hex(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}

// Findings 3 and 5: the new set replaces the old one whole; no file of the old set that the new run did not write
// stays; the manifest lists exactly the files, with sizes and hashes.
TEST_F(OutputDirectoryTest, CommitReplacesTheWholeSet) {
  commit_set({{"a.txt", "old a"}, {"b.txt", "old b"}, {"sub/c.txt", "old c"}});
  EXPECT_EQ(verify_manifest(out_), "");
  commit_set({{"a.txt", "new a"}, {"d.txt", "new d"}});
  const auto files = snapshot(out_);
  ASSERT_EQ(files.size(), 3U);
  EXPECT_EQ(files.at("a.txt"), "new a");
  EXPECT_EQ(files.at("d.txt"), "new d");
  EXPECT_FALSE(fs::exists(out_ / "sub"));
  const Manifest m = read_manifest(out_);
  ASSERT_EQ(m.files.size(), 2U);
  EXPECT_EQ(m.files[0].name, "a.txt");
  EXPECT_EQ(m.files[0].bytes, 5U);
  EXPECT_EQ(m.files[0].sha256, sha256_hex("new a"));
  EXPECT_EQ(verify_manifest(out_), "");
  EXPECT_EQ(entries(dir_.path), 1U) << "no staging folder or old set left beside it";
}

// A file written in pieces is their concatenation, and the manifest has its size and hash (an .npy's header and
// values, written without a copy into one buffer).
TEST_F(OutputDirectoryTest, PiecesAreOneFile) {
  const std::string header = "\x93NUMPY header\n", body(100000, '\x7f');
  {
    OutputDirectory out(out_);
    out.write_pieces("m.npy", {header, "", body});
    out.write_pieces("empty.bin", {});
    out.commit();
  }
  EXPECT_EQ(read_file(out_ / "m.npy"), header + body);
  EXPECT_EQ(read_file(out_ / "empty.bin"), "");
  const Manifest m = read_manifest(out_);
  ASSERT_EQ(m.files.size(), 2U);
  EXPECT_EQ(m.files[1].name, "m.npy");
  EXPECT_EQ(m.files[1].bytes, header.size() + body.size());
  EXPECT_EQ(m.files[1].sha256, sha256_hex(header + body));
  EXPECT_EQ(m.files[0].sha256, sha256_hex(""));
  EXPECT_EQ(verify_manifest(out_), "");
}

TEST_F(OutputDirectoryTest, FilesWrittenByOthersAreListedToo) {
  {
    OutputDirectory out(out_, {.inputs = {}, .command = "seqtopo test"});
    out.write("a.txt", "a");
    const fs::path folder = out.staged("images");
    fs::create_directories(folder);
    std::ofstream(folder / "1.png") << "png";
    std::ofstream(out.staged("b.svg")) << "svg";
    out.commit();
  }
  const Manifest m = read_manifest(out_);
  EXPECT_EQ(m.command, "seqtopo test");
  ASSERT_EQ(m.files.size(), 3U);
  EXPECT_EQ(m.files[1].name, "b.svg");
  EXPECT_EQ(m.files[2].name, "images/1.png");
  EXPECT_EQ(m.files[2].sha256, sha256_hex("png"));
  EXPECT_EQ(verify_manifest(out_), "");
  std::ofstream(out_ / "b.svg") << "changed";
  EXPECT_NE(verify_manifest(out_).find("b.svg"), std::string::npos);
}

// Finding 3: a run that fails before its commit leaves the old set as it was, and nothing beside it.
TEST_F(OutputDirectoryTest, AFailedRunLeavesTheOldSetUntouched) {
  commit_set({{"a.txt", "old a"}});
  const auto before = snapshot(out_);
  {
    OutputDirectory out(out_);
    out.write("a.txt", "new a");
    out.write("x.txt", "new x");
  }
  EXPECT_EQ(snapshot(out_), before);
  EXPECT_EQ(entries(dir_.path), 1U);
  // a staged name never written fails the commit, and also leaves the old set
  {
    OutputDirectory out(out_);
    out.write("a.txt", "new a");
    (void)out.staged("never.txt");
    EXPECT_THROW(out.commit(), InputError);
  }
  EXPECT_EQ(snapshot(out_), before);
  EXPECT_EQ(entries(dir_.path), 1U);
}

// The folder changed during the run (a user put a file in it): the commit refuses, the folder stays as it is.
TEST_F(OutputDirectoryTest, AFolderThatChangedDuringTheRunIsNotReplaced) {
  commit_set({{"a.txt", "old a"}});
  OutputDirectory out(out_);
  out.write("a.txt", "new a");
  write_to(out_ / "notes.txt", "mine");
  EXPECT_THROW(out.commit(), InputError);
  EXPECT_EQ(read_file(out_ / "notes.txt"), "mine");
  EXPECT_EQ(read_file(out_ / "a.txt"), "old a");
}

TEST_F(OutputDirectoryTest, FoldersThatAreNotOneRunsOutputsAreRefused) {
  dir_.write("file", "x");
  expect_refused(dir_.path / "file", "not a folder");
  fs::create_directories(out_);
  dir_.write("out/notes.txt", "mine");
  expect_refused(out_, "no manifest.json");
  fs::remove(out_ / "notes.txt");
  commit_set({{"a.txt", "a"}});
  dir_.write("out/notes.txt", "mine");
  expect_refused(out_, "holds 'notes.txt'");
  fs::remove(out_ / "notes.txt");
  fs::create_directory(out_ / "empty");
  expect_refused(out_, "holds 'empty/'");
  fs::remove(out_ / "empty");
  dir_.write("out/manifest.json", "{\"not\": \"a manifest\"}");
  EXPECT_THROW(OutputDirectory{out_}, InputError);
  EXPECT_THROW(OutputDirectory{fs::path("/")}, InputError);
}

// Finding 5: the output folder is never an input folder, inside one, or around one.
TEST_F(OutputDirectoryTest, InputsAreNeverInsideTheOutputFolder) {
  const fs::path frames = dir_.path / "frames";
  fs::create_directories(frames);
  dir_.write("frames/1.png", "png");
  expect_refused(frames, "is the input", {.inputs = {frames}, .command = ""});
  expect_refused(frames / "out", "inside the input folder", {.inputs = {frames}, .command = ""});
  expect_refused(dir_.path, "holds the input", {.inputs = {frames / "1.png"}, .command = ""});
  expect_refused(frames / ".." / "frames", "is the input", {.inputs = {frames}, .command = ""});
  // a relative spelling of the same folder
  const fs::path cwd = fs::current_path();
  fs::current_path(dir_.path);
  expect_refused(fs::path("frames"), "is the input", {.inputs = {frames}, .command = ""});
  expect_refused(fs::path("."), "current folder");
  fs::current_path(cwd);
  EXPECT_FALSE(fs::exists(frames / "out"));
  EXPECT_NO_THROW(OutputDirectory(dir_.path / "elsewhere", {.inputs = {frames, "-", "same-index"}, .command = ""}));
}

// Finding 4: the staging folder and temporary files of a process that no longer runs are removed by the next
// run beside them; a live process's are not.
TEST_F(OutputDirectoryTest, StaleStagingFoldersOfDeadProcessesAreRemoved) {
  commit_set({{"a.txt", "a"}});
  const pid_t dead = dead_pid();
  const fs::path stale = dir_.path / (".out.seqtopo-staging-" + std::to_string(dead) + "-0");
  const fs::path stale_old = dir_.path / (".out.seqtopo-old-" + std::to_string(dead) + "-3");
  const fs::path live = dir_.path / (".out.seqtopo-staging-" + std::to_string(::getppid()) + "-0");
  const fs::path other = dir_.path / (".other.seqtopo-staging-" + std::to_string(dead) + "-0");
  const fs::path other_old = dir_.path / (".x.y.seqtopo-old-" + std::to_string(dead) + "-12");
  const fs::path other_live = dir_.path / (".other.seqtopo-staging-" + std::to_string(::getppid()) + "-1");
  const fs::path not_staging = dir_.path / (".other.seqtopo-staging-" + std::to_string(dead) + "-0x");
  for (const auto& p : {stale, stale_old, live, other, other_old, other_live, not_staging}) {
    fs::create_directories(p / "sub");
    write_to(p / "sub" / "scores.npy", std::string(1000, 'x'));
  }
  { OutputDirectory out(out_); }
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_FALSE(fs::exists(stale_old));
  EXPECT_TRUE(fs::exists(live)) << "a running process's staging folder";
  // Issue 47, defect 12: a killed run's staging folder stayed until a later run wrote the same folder.
  EXPECT_FALSE(fs::exists(other)) << "a killed run's staging folder beside any run is removed";
  EXPECT_FALSE(fs::exists(other_old));
  EXPECT_TRUE(fs::exists(other_live)) << "a running process's, of another folder";
  EXPECT_TRUE(fs::exists(not_staging)) << "a name that only looks like one";
  // single files: .<name>.tmp.<pid>.<k>
  const fs::path tmp = dir_.path / (".f.json.tmp." + std::to_string(dead) + ".0");
  write_to(tmp, "partial");
  write_file_atomic(dir_.path / "f.json", "{}");
  EXPECT_FALSE(fs::exists(tmp));
  EXPECT_EQ(read_file(dir_.path / "f.json"), "{}");
}

// The signal path: remove_staged_outputs_and_exit removes what this process staged, leaves the old set, exits.
TEST_F(OutputDirectoryTest, StoppingRemovesTheStagingFolderAndExits) {
  commit_set({{"a.txt", "old a"}});
  const auto before = snapshot(out_);
  const pid_t child = ::fork();
  if (child == 0) {
    OutputDirectory out(out_);
    out.write("a.txt", "new a");
    out.write("big.npy", std::string(1 << 20, 'x'));
    remove_staged_outputs_and_exit(130);
  }
  int raw = 0;
  ::waitpid(child, &raw, 0);
  ASSERT_TRUE(WIFEXITED(raw));
  EXPECT_EQ(WEXITSTATUS(raw), 130);
  EXPECT_EQ(snapshot(out_), before);
  EXPECT_EQ(entries(dir_.path), 1U);
}

// manifest.json lists every file of the set but itself, with the size and the SHA-256 that sha256sum (another
// implementation) computes of the committed file; verify_manifest names each kind of difference, and only those.
TEST_F(OutputDirectoryTest, ManifestMatchesTheFilesAndVerifyNamesEveryDifference) {
  {
    OutputDirectory out(out_, {.inputs = {}, .command = "seqtopo test"});
    out.write("a.txt", "aaaa");
    out.write("b.txt", "bbbb");
    out.write("c.txt", "cccc");
    out.write("sub/d.bin", std::string("\0d\xff", 3));
    std::ofstream(out.staged("e.svg"), std::ios::binary) << "written by another writer";
    out.commit();
  }
  const Manifest m = read_manifest(out_);
  std::string names;
  for (const auto& f : m.files) {
    names += f.name + " ";
    EXPECT_EQ(f.bytes, fs::file_size(out_ / f.name)) << f.name;
  }
  EXPECT_EQ(names, "a.txt b.txt c.txt e.svg sub/d.bin ");
  const auto sums =
      test_support::run_command("cd '" + out_.string() + "' && sha256sum a.txt b.txt c.txt e.svg sub/d.bin");
  ASSERT_EQ(sums.status, 0) << sums.err;
  std::string expected;
  for (const auto& f : m.files) expected += f.sha256 + "  " + f.name + "\n";
  EXPECT_EQ(sums.out, expected);
  EXPECT_EQ(verify_manifest(out_), "");

  fs::remove(out_ / "a.txt");
  write_to(out_ / "b.txt", "bbbbb");  // another size
  write_to(out_ / "c.txt", "cCcc");   // the same size, other bytes
  write_to(out_ / "f.txt", "f");      // not listed
  const std::string problems = verify_manifest(out_);
  EXPECT_EQ(problems, "a.txt missing; b.txt has another size; c.txt has another SHA-256; f.txt not listed");
  EXPECT_EQ(problems.find("sub/d.bin"), std::string::npos);
  EXPECT_EQ(problems.find("e.svg"), std::string::npos);

  // no manifest: the error names the manifest file
  fs::remove(out_ / kManifestName);
  try {
    (void)read_manifest(out_);
    ADD_FAILURE() << "read without a manifest";
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), (out_ / kManifestName).string());
  }
}

// A commit with no file at all still writes a manifest (with no file), and the next run replaces that set.
TEST_F(OutputDirectoryTest, AnEmptySetHasAnEmptyManifest) {
  commit_set({});
  EXPECT_TRUE(read_manifest(out_).files.empty());
  EXPECT_EQ(snapshot(out_).size(), 1U);
  commit_set({{"a.txt", "a"}});
  ASSERT_EQ(read_manifest(out_).files.size(), 1U);
  EXPECT_EQ(verify_manifest(out_), "");
}

// Issue 47, defect 10: two runs writing one folder at once both finished and both said they wrote their files;
// one set was lost. The folder's lock refuses the second while the first holds it, naming the first's process;
// once the first has committed (or failed), the folder may be written again, and no lock file stays.
TEST_F(OutputDirectoryTest, TwoRunsNeverWriteOneFolderAtOnce) {
  commit_set({{"a.txt", "old a"}});
  {
    OutputDirectory first(out_);
    first.write("a.txt", "first");
    expect_refused(out_, "is being written by another seqtopo run (process " + std::to_string(::getpid()) + ")");
    OutputDirectory elsewhere(dir_.path / "other");  // another folder beside it is not locked
    elsewhere.write("b.txt", "b");
    elsewhere.commit();
    first.commit();
  }
  EXPECT_EQ(read_file(out_ / "a.txt"), "first");
  { OutputDirectory again(out_); }  // the first released the lock at its commit (this one at its end)
  commit_set({{"a.txt", "third"}});
  EXPECT_EQ(read_file(out_ / "a.txt"), "third");
  EXPECT_EQ(entries(dir_.path), 2U) << "out and other, no lock file or staging folder beside them";
  // A lock file a killed run left (nobody holds it) is taken, and removed by the next run beside it.
  write_to(dir_.path / ".out.seqtopo-lock", "12345");
  write_to(dir_.path / ".gone.seqtopo-lock", "12345");
  commit_set({{"a.txt", "fourth"}});
  EXPECT_EQ(entries(dir_.path), 2U);
}

// Issue 47, defect 13: a file of the old set that the user edited (its SHA-256 no longer the manifest's) was
// replaced without a word. It is refused before the run and again before the swap; the folder stays as it is.
TEST_F(OutputDirectoryTest, AnEditedFileOfTheOldSetIsNeverReplaced) {
  commit_set({{"a.txt", "old a"}, {"sub/b.txt", "old b"}});
  write_to(out_ / "sub" / "b.txt", "new b");  // the same size
  expect_refused(out_, "holds 'sub/b.txt', changed since the seqtopo run that wrote it (its SHA-256");
  write_to(out_ / "sub" / "b.txt", "longer b");
  expect_refused(out_, "holds 'sub/b.txt', changed since the seqtopo run that wrote it (its size");
  fs::remove(out_ / "sub" / "b.txt");  // moved away: the rest may be replaced
  {
    OutputDirectory out(out_);
    out.write("a.txt", "new a");
    write_to(out_ / "a.txt", "mine!");  // edited while the run lasts
    EXPECT_THROW(out.commit(), InputError);
  }
  EXPECT_EQ(read_file(out_ / "a.txt"), "mine!");
  fs::remove(out_ / "a.txt");
  commit_set({{"c.txt", "c"}});
  EXPECT_EQ(verify_manifest(out_), "");
}

// Issue 47, defect 14: a valid folder name of 225 to 255 bytes was refused ("File name too long") because the
// staging sibling's name added 30 bytes and more. The hidden siblings' names are bounded whatever the name.
TEST_F(OutputDirectoryTest, NamesUpTo255BytesAreOutputFoldersAndFiles) {
  for (const std::size_t length : {225U, 240U, 255U}) {
    SCOPED_TRACE(length);
    // ASCII, and a name of two-byte characters (never cut inside one)
    for (const std::string& name : {std::string(length, 'n'), std::string(length % 2, 'x') + [&] {
                                      std::string s;
                                      while (s.size() + 2 <= length) s += "\xc3\xa9";
                                      return s;
                                    }()}) {
      const fs::path folder = dir_.path / name;
      for (const char* text : {"first", "second"}) {  // a new folder, then a replaced one
        OutputDirectory out(folder);
        EXPECT_LE(out.staging().filename().string().size(), 200U);
        out.write("a.txt", text);
        out.commit();
        EXPECT_EQ(read_file(folder / "a.txt"), text);
      }
      EXPECT_EQ(verify_manifest(folder), "");
      write_file_atomic(dir_.path / (name.substr(0, length - 1) + "f"), "{}");
      EXPECT_EQ(read_file(dir_.path / (name.substr(0, length - 1) + "f")), "{}");
      fs::remove_all(folder);
      fs::remove(dir_.path / (name.substr(0, length - 1) + "f"));
      EXPECT_EQ(entries(dir_.path), 0U) << "nothing left beside them";
    }
  }
}

TEST(Manifest, RoundTripAndRejections) {
  Manifest m{"seqtopo map", {{"b.txt", 3, sha256_hex("b")}, {"a \"quoted\" \\ name\t.txt", 0, sha256_hex("")}}};
  const std::string text = manifest_json(m);
  const Manifest back = parse_manifest(text, "m");
  EXPECT_EQ(back.command, "seqtopo map");
  ASSERT_EQ(back.files.size(), 2U);
  EXPECT_EQ(back.files[0].name, "a \"quoted\" \\ name\t.txt") << "sorted by name";
  EXPECT_EQ(back.files[1].bytes, 3U);
  EXPECT_EQ(manifest_json(back), text);
  const std::string hash = sha256_hex("");
  for (const std::string& bad : std::vector<std::string>{
           "", "{}", "[]", "{\"seqtopo_manifest\": 2, \"files\": []}", "{\"seqtopo_manifest\": 1}",
           "{\"seqtopo_manifest\": 1, \"files\": [{\"name\": \"a\"}]}",
           "{\"seqtopo_manifest\": 1, \"files\": [{\"name\": \"../a\", \"bytes\": 1, \"sha256\": \"" + hash + "\"}]}",
           "{\"seqtopo_manifest\": 1, \"files\": [{\"name\": \"/etc/a\", \"bytes\": 1, \"sha256\": \"" + hash + "\"}]}",
           "{\"seqtopo_manifest\": 1, \"files\": [{\"name\": \"a\", \"bytes\": 1, \"sha256\": \"abc\"}]}",
           "{\"seqtopo_manifest\": 1, \"files\": [{\"name\": \"a\", \"bytes\": 99999999999999999999999, \"sha256\": "
           "\"" +
               hash + "\"}]}",
           "{\"seqtopo_manifest\": 1, \"files\": []} trailing", "{\"seqtopo_manifest\": 1, \"files\": [], \"x\": 1}",
           "{\"seqtopo_manifest\": 1, \"command\": \"unterminated, \"files\": []}"}) {
    SCOPED_TRACE(bad);
    EXPECT_THROW((void)parse_manifest(bad, "m"), InputError);
  }
}

}  // namespace
}  // namespace seqtopo::io
