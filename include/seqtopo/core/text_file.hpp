#pragma once
// Files the user names explicitly (a config, an odometry or ground-truth table, a strings file, a list of paths
// on stdin) are read through these, so that an endless or blocking file (/dev/zero, a FIFO, a terminal) is an
// error naming it instead of a run that grows its memory without bound or waits forever.
#include <cstddef>
#include <filesystem>
#include <istream>
#include <optional>
#include <string>
#include <string_view>

namespace seqtopo {

// The largest text file read whole: 1 GiB (an odometry log of 10^7 rows is about 0.6 GiB).
inline constexpr std::size_t kMaxTextFileBytes = std::size_t{1} << 30U;
// The longest line of a stream of file paths (PATH_MAX is 4096 bytes).
inline constexpr std::size_t kMaxPathLineBytes = 4096;

// Why `path` cannot be read as a file: "" for a regular file (or a symbolic link to one), else "no such file",
// "a folder", "a FIFO", "a character device" (/dev/zero, a terminal), "a block device", "a socket",
// "a dangling symbolic link", "a looping symbolic link" or "cannot be read: <reason>".
std::string special_file_reason(const std::filesystem::path& path);

// Throws InputError naming `path` unless it is a regular file: "<reason>, not a <what>".
void require_regular_file(const std::filesystem::path& path, std::string_view what = "file");

// The whole of a regular file of at most max_bytes bytes; InputError naming the file otherwise (not a regular
// file, cannot be opened or read, larger than max_bytes, also when it grows while being read).
std::string read_text_file(const std::filesystem::path& path, std::string_view what = "file",
                           std::size_t max_bytes = kMaxTextFileBytes);

// The next line of `in` without its '\n' (and a trailing '\r'), nullopt at the end; InputError naming `subject`
// when a line is longer than max_bytes or holds a NUL byte (binary data such as /dev/zero, not text).
std::optional<std::string> read_bounded_line(std::istream& in, const std::string& subject,
                                             std::size_t max_bytes = kMaxPathLineBytes);

}  // namespace seqtopo
