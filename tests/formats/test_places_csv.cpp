// places.csv and junctions.csv: the simulator's topological ground truth.
#include <gtest/gtest.h>

#include <string>
#include <tuple>
#include <vector>

#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/places_csv.hpp"

namespace seqtopo::formats {
namespace {

TEST(PlacesCsv, PlacesAndJunctions) {
  const test_support::TempDir dir;
  EXPECT_EQ(read_places_csv(dir.write("p.csv", "index,place\n0,3\n1,3\r\n2,7\n")), (std::vector<int>{3, 3, 7}));
  EXPECT_EQ(read_junctions_csv(dir.write("j.csv", "place\n3\n9\n")), (std::vector<int>{3, 9}));
  for (const auto& [name, text, subject] :
       std::vector<std::tuple<std::string, std::string, std::string>>{{"hdr.csv", "idx,place\n0,1\n", ":1"},
                                                                      {"order.csv", "index,place\n1,1\n", ":2"},
                                                                      {"text.csv", "index,place\n0,x\n", ":2"},
                                                                      {"cols.csv", "index,place\n0,1,2\n", ":2"}}) {
    try {
      read_places_csv(dir.write(name, text));
      FAIL() << name;
    } catch (const InputError& e) {
      EXPECT_EQ(e.subject(), (dir.path / name).string() + subject) << e.what();
    }
  }
  EXPECT_THROW(read_places_csv(dir.write("empty.csv", "index,place\n")), InputError);
}

}  // namespace
}  // namespace seqtopo::formats
