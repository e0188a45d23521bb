#pragma once
// Outputs appear whole or not at all.
//
// One file: written to a hidden temporary name beside its target and renamed into place (write_file_atomic).
//
// A folder (OutputDirectory): the run writes into a new hidden sibling of the folder,
// `.<name>.seqtopo-staging-<pid>-<k>/`, lists every file in `manifest.json` (name, size, SHA-256), and commit()
// swaps the two folders with one rename(2) (renameat2 RENAME_EXCHANGE; a plain rename when the folder is new),
// then removes the old one. Whoever opens the folder sees the whole old set or the whole new one; a run that
// fails, is interrupted or is killed leaves the old set untouched. The folder holds exactly one run's files:
// nothing of an earlier run that this run did not write stays beside them.
//
// Because the folder is replaced whole, it is refused (InputError naming it, before any work) when it
//   - exists and is not a folder, or is not empty and has no manifest.json (no seqtopo run wrote it),
//   - holds anything its manifest does not list (a file a user put there would be lost), or a file whose size or
//     SHA-256 is not its manifest's (a file a user edited would be lost),
//   - is, holds, or lies inside one of the run's inputs, or holds the current working folder.
// One run writes a folder at a time: it holds the lock file `.<name>.seqtopo-lock` beside it (flock(2)) from its
// checks to the end of its swap, and a second run is refused (InputError naming the folder) while it does.
// Staging folders and old sets of processes that no longer run (killed) are removed by the next run that writes
// beside them, whichever folder they were for (temporary files: by the next write of the same file);
// remove_staged_outputs_and_exit() removes this process's own (signal handlers). The hidden siblings' names are
// bounded: a name over 128 bytes is cut and ends with 8 hex digits of its SHA-256.
#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace seqtopo::io {

// Writes bytes to path atomically. Throws InputError naming the path on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view bytes);

inline constexpr char kManifestName[] = "manifest.json";

struct ManifestEntry {
  std::string name;  // relative path, '/'-separated ("map.json", "panoramas/00001.png")
  std::uint64_t bytes = 0;
  std::string sha256;  // 64 lowercase hex digits
};

// manifest.json: {"seqtopo_manifest": 1, "command": "...", "files": [{"name", "bytes", "sha256"}, ...]}, one file
// per line, sorted by name.
struct Manifest {
  std::string command;  // "seqtopo map", or empty
  std::vector<ManifestEntry> files;
};
std::string manifest_json(const Manifest& manifest);
// Throws InputError(subject, ...) unless `text` is a manifest as manifest_json writes it.
Manifest parse_manifest(std::string_view text, const std::string& subject);
// The manifest of an output folder (InputError naming the file when it is missing or malformed).
Manifest read_manifest(const std::filesystem::path& dir);
// The files of `dir` that differ from its manifest: missing, other size or hash, or not listed ("" = none).
std::string verify_manifest(const std::filesystem::path& dir);

struct OutputOptions {
  // The files and folders the run reads: the output folder must not be, hold or lie inside any of them.
  std::vector<std::filesystem::path> inputs;
  std::string command;  // written to the manifest ("seqtopo map")
};

// What the checks of an output folder saw of its old set (the manifest's text; per file its size, time and inode
// when it matched the manifest).
struct OldSetSeen {
  std::string manifest;
  std::map<std::string, std::string> files;
};

class OutputDirectory {
 public:
  // Checks that `dir` may be replaced (see above), removes stale staging folders beside it and makes this run's.
  explicit OutputDirectory(std::filesystem::path dir, OutputOptions options = {});
  ~OutputDirectory();
  OutputDirectory(const OutputDirectory&) = delete;
  OutputDirectory& operator=(const OutputDirectory&) = delete;

  // Where to write `name` before commit (writers may create it, a file or a folder, directly there), or read back
  // what was written.
  std::filesystem::path staged(const std::string& name);
  // Writes `name` and keeps its SHA-256 for the manifest: a file written here is not rewritten through staged()
  // (commit() hashes again only files whose size differs from what write() wrote, and those writers made).
  void write(const std::string& name, std::string_view bytes);
  // The same for a file of several pieces, one after the other (a header and a large body not copied into one).
  void write_pieces(const std::string& name, std::initializer_list<std::string_view> pieces);
  // Writes the manifest and puts the staged set in place of the folder's old one; returns the final paths of
  // the staged names (not the manifest's).
  std::vector<std::filesystem::path> commit();
  const std::filesystem::path& dir() const { return dir_; }
  // This run's staging folder (until commit).
  const std::filesystem::path& staging() const { return staging_; }

 private:
  std::filesystem::path dir_;      // as given
  std::filesystem::path target_;   // absolute, symbolic links resolved
  std::filesystem::path staging_;  // the sibling being written
  OutputOptions options_;
  std::vector<std::string> names_;
  std::map<std::string, std::pair<std::uint64_t, std::string>> hashes_;  // name -> size, SHA-256 write() wrote
  std::vector<std::filesystem::path> made_parents_;  // folders the constructor created (removed if no commit)
  int lock_fd_ = -1;                                 // the staging folder, locked while this run writes it
  std::filesystem::path lock_file_;                  // `.<name>.seqtopo-lock` beside the folder
  int folder_lock_fd_ = -1;                          // held from the checks to the end of the swap
  OldSetSeen old_set_;
  bool committed_ = false;
};

// The start of a stop (a signal): false once a commit of this process has put its set in place (a swap in progress
// finishes first), since the run's outputs are then whole and in place and the stop comes too late to undo them:
// the process carries on to its own end and status. True otherwise: no output folder changes after this point, and
// the caller ends the process with remove_staged_outputs_and_exit(128 + signal).
[[nodiscard]] bool begin_stop();

// Removes every staging folder and temporary file of this process that was not committed, and the old set of a
// commit that has not finished removing it, then ends the process with `status` (_exit: nothing else runs). A
// commit in progress on another thread finishes its swap first, so the folder is the old set or the new one.
// Safe to call from any thread, once; for a signal-watching thread (the command line's SIGINT/SIGTERM).
[[noreturn]] void remove_staged_outputs_and_exit(int status);

}  // namespace seqtopo::io
