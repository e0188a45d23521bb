#include "config_file.hpp"

#include "seqtopo/core/input_error.hpp"

namespace seqtopo::cli {
namespace {

std::string trim(std::string_view t) {
  const auto first = t.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = t.find_last_not_of(" \t\r");
  return std::string(t.substr(first, last - first + 1));
}

// Where a line's comment begins: the first '#' outside a quoted value (`out: "run#2"` is a value; a quote opens
// one only right after the colon, so `note: it's` has none), or the line's end.
std::size_t comment_start(std::string_view line) {
  char quote = 0, last = 0;  // last: the previous character that is not a space
  for (std::size_t k = 0; k < line.size(); ++k) {
    const char c = line[k];
    if (quote != 0) {
      if (c == quote) quote = 0;
    } else if ((c == '"' || c == '\'') && last == ':') {
      quote = c;
    } else if (c == '#') {
      return k;
    }
    if (c != ' ' && c != '\t') last = c;
  }
  return line.size();
}

}  // namespace

std::vector<ConfigEntry> parse_config(std::string_view text, const std::string& path) {
  if (text.starts_with("\xEF\xBB\xBF")) text.remove_prefix(3);  // a UTF-8 byte-order mark (editors on Windows)
  std::vector<std::string_view> lines;
  for (std::size_t start = 0; start <= text.size();) {
    const auto end = text.find('\n', start);
    lines.push_back(text.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  if (!lines.empty() && lines.back().empty()) lines.pop_back();  // the newline ending the last line
  for (const auto line : lines) {
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    if (t[0] == '{' || t[0] == '[') {
      throw InputError(
          path, "looks like JSON; a config file holds `name: value` lines (a flat YAML subset, e.g. `gap: 1.5`)");
    }
    break;
  }
  std::vector<ConfigEntry> entries;
  for (std::size_t k = 0; k < lines.size(); ++k) {
    std::string_view raw = lines[k];
    raw = raw.substr(0, comment_start(raw));
    const std::string line = trim(raw);
    if (line.empty() || line == "---") continue;
    const auto colon = line.find(':');
    const std::string where = path + ":" + std::to_string(k + 1);
    if (colon == std::string::npos) throw InputError(where, "expected `name: value`, got '" + line + "'");
    ConfigEntry e{k + 1, trim(std::string_view(line).substr(0, colon)), trim(std::string_view(line).substr(colon + 1))};
    if (e.value.size() >= 2 && (e.value.front() == '"' || e.value.front() == '\'') &&
        e.value.back() == e.value.front()) {
      e.value = e.value.substr(1, e.value.size() - 2);
    }
    if (e.name.empty()) throw InputError(where, "no name before the colon");
    entries.push_back(std::move(e));
  }
  return entries;
}

}  // namespace seqtopo::cli
