#include "seqtopo/io/places_csv.hpp"

#include <charconv>
#include <fstream>
#include <string>

#include "seqtopo/io/input_error.hpp"

namespace seqtopo::io {
namespace {

// Rows of integers under an exact header; errors name file:line.
std::vector<std::vector<long>> read_int_csv(const std::filesystem::path& path, const std::string& header, std::size_t columns) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string(), "cannot open file");
  std::string line;
  std::size_t line_no = 0;
  auto where = [&] { return path.string() + ":" + std::to_string(line_no); };
  if (!std::getline(in, line)) throw InputError(path.string(), "empty file (expected header '" + header + "')");
  ++line_no;
  if (!line.empty() && line.back() == '\r') line.pop_back();
  if (line != header) throw InputError(where(), "expected header '" + header + "', got '" + line + "'");
  std::vector<std::vector<long>> rows;
  while (std::getline(in, line)) {
    ++line_no;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) continue;
    std::vector<long> row;
    const char* p = line.data();
    const char* end = line.data() + line.size();
    while (p <= end) {
      long v = 0;
      auto [next, ec] = std::from_chars(p, end, v);
      if (ec != std::errc{} || (next != end && *next != ',')) throw InputError(where(), "expected integers, got '" + line + "'");
      row.push_back(v);
      p = next + 1;
    }
    if (row.size() != columns) {
      throw InputError(where(), "expected " + std::to_string(columns) + " columns, got " + std::to_string(row.size()));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace

std::vector<int> read_places_csv(const std::filesystem::path& path) {
  const auto rows = read_int_csv(path, "index,place", 2);
  std::vector<int> places;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    if (rows[k][0] != static_cast<long>(k)) {
      throw InputError(path.string() + ":" + std::to_string(k + 2), "index " + std::to_string(rows[k][0]) +
                                                                       " out of order (expected " + std::to_string(k) + ")");
    }
    places.push_back(static_cast<int>(rows[k][1]));
  }
  if (places.empty()) throw InputError(path.string(), "no rows");
  return places;
}

std::vector<int> read_junctions_csv(const std::filesystem::path& path) {
  std::vector<int> junctions;
  for (const auto& row : read_int_csv(path, "place", 1)) junctions.push_back(static_cast<int>(row[0]));
  return junctions;
}

}  // namespace seqtopo::io
