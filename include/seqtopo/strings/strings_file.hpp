#pragma once
// Strings files (INTERFACE.md): one record per line, `id<TAB>string[<TAB>x<TAB>y[<TAB>place]]`, `#` starts
// a comment, blank lines are skipped. Parsing works on text so this layer stays free of file access.
#include <cstddef>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace seqtopo::strings {

struct StringRecord {
  std::string id;
  std::string symbols;         // may be empty (a panorama without features)
  std::optional<double> x, y;  // [m]
  std::optional<std::string> place;
};

// A malformed line: `line` is 1-based.
class StringsFileError : public std::invalid_argument {
 public:
  StringsFileError(std::size_t line, const std::string& message) : std::invalid_argument(message), line_(line) {}
  std::size_t line() const { return line_; }

 private:
  std::size_t line_;
};

// Throws StringsFileError on a wrong number of fields, an empty or repeated id, a non-numeric coordinate
// or an empty place.
std::vector<StringRecord> parse_strings_tsv(std::string_view text);
std::string format_strings_tsv(const std::vector<StringRecord>& records, std::string_view header_comment = {});

}  // namespace seqtopo::strings
