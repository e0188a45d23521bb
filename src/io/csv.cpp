#include "seqtopo/io/csv.hpp"

#include <fstream>
#include <sstream>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/core/text_file.hpp"

namespace seqtopo::io {

void skip_byte_order_mark(std::istream& in) {
  char bom[3] = {};
  if (in.read(bom, 3) && bom[0] == '\xEF' && bom[1] == '\xBB' && bom[2] == '\xBF') return;
  in.clear();
  in.seekg(0);
}

std::vector<CsvRow> read_csv(const std::filesystem::path& path, const std::vector<std::string>& header) {
  std::string header_text;
  for (std::size_t k = 0; k < header.size(); ++k) header_text += (k ? "," : "") + header[k];
  std::istringstream in(read_text_file(path, "CSV file"));
  skip_byte_order_mark(in);
  std::vector<CsvRow> rows;
  bool header_seen = false;
  std::string line;
  std::size_t line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line.front() == '#') continue;
    CsvRow row{path.string() + ":" + std::to_string(line_no), {}};
    std::stringstream fields(line);
    for (std::string field; std::getline(fields, field, ',');) row.fields.push_back(field);
    if (!line.empty() && line.back() == ',') row.fields.emplace_back();  // a trailing empty field
    if (!header_seen) {
      if (row.fields != header)
        throw InputError(row.where, "expected the header '" + header_text + "', got '" + line + "'");
      header_seen = true;
      continue;
    }
    if (row.fields.size() != header.size()) {
      throw InputError(row.where, "expected " + std::to_string(header.size()) + " comma-separated fields (" +
                                      header_text + "), got " + std::to_string(row.fields.size()));
    }
    rows.push_back(std::move(row));
  }
  if (!header_seen) throw InputError(path.string(), "empty file (expected the header '" + header_text + "')");
  return rows;
}

}  // namespace seqtopo::io
