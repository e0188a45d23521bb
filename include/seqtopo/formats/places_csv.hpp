#pragma once
// Ground-truth place files: places.csv (`index,place`, one row per image, indices 0..N-1 in order)
// and junctions.csv (`place`, one true junction place per row).
#include <filesystem>
#include <vector>

namespace seqtopo::formats {

std::vector<int> read_places_csv(const std::filesystem::path& path);
std::vector<int> read_junctions_csv(const std::filesystem::path& path);

}  // namespace seqtopo::formats
