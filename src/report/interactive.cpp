#include "seqtopo/report/interactive.hpp"

#include <cstdlib>
#include <fstream>
#include <sstream>

namespace seqtopo::report {

std::filesystem::path d3_library_path() {
  if (const char* path = std::getenv("SEQTOPO_D3_JS"); path && *path) return path;
  return "/usr/share/javascript/d3/d3.min.js";
}

std::optional<std::string> read_d3_library() {
  std::ifstream in(d3_library_path(), std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  if (!in.good() && !in.eof()) return std::nullopt;
  std::string s = text.str();
  if (s.empty()) return std::nullopt;
  return s;
}

std::string script_text(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t k = 0; k < text.size(); ++k) {
    // "</" becomes "<\/" (the same string to JSON and JavaScript), "<!--" becomes "<\!--".
    if (text[k] == '<' && k + 1 < text.size() && (text[k + 1] == '/' || text[k + 1] == '!')) {
      out += "<\\";
      continue;
    }
    out += text[k];
  }
  return out;
}

}  // namespace seqtopo::report
