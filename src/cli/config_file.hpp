#pragma once
// `--config FILE`: the text of a config file, `name: value` lines (a flat YAML subset). `#` starts a comment,
// `---` lines and blank lines are skipped, a value may be quoted ('...' or "..."). A file that looks like JSON, or
// a line without a colon, is refused with InputError naming the file (and line). Which names and values a
// command takes is checked by the command line (main.cpp).
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

namespace seqtopo::cli {

struct ConfigEntry {
  std::size_t line = 0;  // 1-based
  std::string name, value;
};

std::vector<ConfigEntry> parse_config(std::string_view text, const std::string& path);

}  // namespace seqtopo::cli
