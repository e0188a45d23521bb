#include "seqtopo/core/text_file.hpp"

#include <fstream>
#include <system_error>

#include "seqtopo/core/input_error.hpp"

namespace seqtopo {

namespace fs = std::filesystem;

std::string special_file_reason(const fs::path& path) {
  std::error_code ec;
  const auto own = fs::symlink_status(path, ec);
  if (ec || !fs::exists(own)) return "no such file";
  const auto target = fs::status(path, ec);
  if (ec) {
    if (fs::is_symlink(own)) {
      return ec == std::errc::too_many_symbolic_link_levels ? "a looping symbolic link" : "a dangling symbolic link";
    }
    return "cannot be read: " + ec.message();
  }
  if (!fs::exists(target)) return fs::is_symlink(own) ? "a dangling symbolic link" : "no such file";
  if (fs::is_regular_file(target)) return {};
  if (fs::is_directory(target)) return "a folder";
  if (fs::is_fifo(target)) return "a FIFO";
  if (fs::is_character_file(target)) return "a character device";
  if (fs::is_block_file(target)) return "a block device";
  if (fs::is_socket(target)) return "a socket";
  return "not a regular file";
}

void require_regular_file(const fs::path& path, std::string_view what) {
  const std::string why = special_file_reason(path);
  if (why.empty()) return;
  if (why == "no such file") throw InputError(path.string(), "no such " + std::string(what));
  const bool vowel = !what.empty() && std::string_view("aeiou").find(what.front()) != std::string_view::npos;
  throw InputError(path.string(), why + (vowel ? ", not an " : ", not a ") + std::string(what));
}

std::string read_text_file(const fs::path& path, std::string_view what, std::size_t max_bytes) {
  require_regular_file(path, what);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path.string(), "cannot open the " + std::string(what));
  // Read at most one byte past the bound: a file that grows while it is read (a log still written) stops there.
  std::string text;
  char buffer[1 << 16];
  while (in) {
    in.read(buffer, sizeof buffer);
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > max_bytes) {
      throw InputError(path.string(),
                       "larger than " + std::to_string(max_bytes) + " bytes, too large for a " + std::string(what));
    }
  }
  if (in.bad()) throw InputError(path.string(), "cannot read the " + std::string(what));
  return text;
}

std::optional<std::string> read_bounded_line(std::istream& in, const std::string& subject, std::size_t max_bytes) {
  std::string line;
  for (;;) {
    const int c = in.get();
    if (c == std::char_traits<char>::eof()) {
      if (line.empty()) return std::nullopt;
      break;
    }
    if (c == '\n') break;
    if (c == '\0') throw InputError(subject, "holds a NUL byte: binary data, not lines of text");
    if (line.size() >= max_bytes) {
      throw InputError(subject, "a line longer than " + std::to_string(max_bytes) + " bytes");
    }
    line.push_back(static_cast<char>(c));
  }
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

}  // namespace seqtopo
