#pragma once
// Small comma-separated files with an exact header (places.csv, points.csv, adjacency.csv, ...).
// Blank lines and lines starting with '#' are skipped; CRLF line ends are accepted. Fields are not
// quoted (none of these files needs commas inside a field).
#include <cstddef>
#include <filesystem>
#include <istream>
#include <string>
#include <vector>

namespace seqtopo::io {

struct CsvRow {
  std::string where;                // "file:line", for error messages about this row
  std::vector<std::string> fields;  // as many as the header has
};

// Skips a UTF-8 byte-order mark at the stream's start (spreadsheets write one before the header); every text
// file reader calls it after opening.
void skip_byte_order_mark(std::istream& in);

// Throws InputError naming the file (missing, empty) or file:line (another header, a row with
// another number of fields).
std::vector<CsvRow> read_csv(const std::filesystem::path& path, const std::vector<std::string>& header);

}  // namespace seqtopo::io
