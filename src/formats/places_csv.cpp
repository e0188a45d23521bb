#include "seqtopo/formats/places_csv.hpp"

#include <charconv>
#include <string>

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/csv.hpp"

namespace seqtopo::formats {
namespace {

int parse_int(const io::CsvRow& row, std::size_t field) {
  const std::string& text = row.fields[field];
  int value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc{} || end != text.data() + text.size())
    throw InputError(row.where, "expected an integer, got '" + text + "'");
  return value;
}

}  // namespace

std::vector<int> read_places_csv(const std::filesystem::path& path) {
  std::vector<int> places;
  for (const auto& row : io::read_csv(path, {"index", "place"})) {
    const int index = parse_int(row, 0);
    if (index != static_cast<int>(places.size())) {
      throw InputError(row.where, "index " + std::to_string(index) + " out of order (expected " +
                                      std::to_string(places.size()) + ")");
    }
    places.push_back(parse_int(row, 1));
  }
  if (places.empty()) throw InputError(path.string(), "no rows");
  return places;
}

std::vector<int> read_junctions_csv(const std::filesystem::path& path) {
  std::vector<int> junctions;
  for (const auto& row : io::read_csv(path, {"place"})) junctions.push_back(parse_int(row, 0));
  return junctions;
}

}  // namespace seqtopo::formats
