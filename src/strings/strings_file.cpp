#include "seqtopo/strings/strings_file.hpp"

#include <charconv>
#include <cmath>
#include <set>
#include <sstream>

namespace seqtopo::strings {
namespace {

std::vector<std::string_view> split_tabs(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  for (;;) {
    const std::size_t tab = line.find('\t', start);
    fields.push_back(line.substr(start, tab == std::string_view::npos ? std::string_view::npos : tab - start));
    if (tab == std::string_view::npos) break;
    start = tab + 1;
  }
  return fields;
}

double parse_number(std::string_view field, std::size_t line, const char* what) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (ec != std::errc() || end != field.data() + field.size() || field.empty() || !std::isfinite(value)) {
    throw StringsFileError(line, std::string(what) + " '" + std::string(field) + "' is not a number");
  }
  return value;
}

// A field of an id or place: no control character (a '\r' would be read back as the line's end).
void check_text(std::string_view field, std::size_t line, const char* what) {
  for (char c : field) {
    if (static_cast<unsigned char>(c) < 32)
      throw StringsFileError(line, std::string(what) + " contains a control character");
  }
}

// The shortest text that reads back as the same double.
std::string shortest(double v) {
  char buffer[32];
  const auto [end, ec] = std::to_chars(buffer, buffer + sizeof buffer, v);
  return ec == std::errc() ? std::string(buffer, end) : std::to_string(v);
}

}  // namespace

std::vector<StringRecord> parse_strings_tsv(std::string_view text) {
  std::vector<StringRecord> records;
  std::set<std::string, std::less<>> ids;
  std::size_t line_no = 0, start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    std::string_view line = text.substr(start, end - start);
    start = end + 1;
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty() || line.front() == '#') continue;
    const auto fields = split_tabs(line);
    if (fields.size() != 2 && fields.size() != 4 && fields.size() != 5) {
      throw StringsFileError(line_no, "expected id<TAB>string[<TAB>x<TAB>y[<TAB>place]], got " +
                                          std::to_string(fields.size()) + " tab-separated field(s)");
    }
    StringRecord r;
    r.id = std::string(fields[0]);
    if (r.id.empty()) throw StringsFileError(line_no, "empty id");
    check_text(r.id, line_no, "the id");
    if (!ids.insert(r.id).second) throw StringsFileError(line_no, "repeated id '" + r.id + "'");
    r.symbols = std::string(fields[1]);
    for (char c : r.symbols) {
      if (c == ' ' || static_cast<unsigned char>(c) < 32)
        throw StringsFileError(line_no, "the string contains white space or a control character");
    }
    if (fields.size() >= 4) {
      r.x = parse_number(fields[2], line_no, "x");
      r.y = parse_number(fields[3], line_no, "y");
    }
    if (fields.size() == 5) {
      if (fields[4].empty()) throw StringsFileError(line_no, "empty place");
      check_text(fields[4], line_no, "the place");
      r.place = std::string(fields[4]);
    }
    records.push_back(std::move(r));
  }
  return records;
}

std::string format_strings_tsv(const std::vector<StringRecord>& records, std::string_view header_comment) {
  std::ostringstream out;
  if (!header_comment.empty()) out << "# " << header_comment << "\n";
  for (const StringRecord& r : records) {
    out << r.id << '\t' << r.symbols;
    if (r.x && r.y) {
      out << '\t' << shortest(*r.x) << '\t' << shortest(*r.y);
      if (r.place) out << '\t' << *r.place;
    }
    out << '\n';
  }
  return out.str();
}

}  // namespace seqtopo::strings
