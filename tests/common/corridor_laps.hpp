#pragma once
// The bundled corridor's two laps as two folders of links to its images: `dir`/lap1 (images 1-40) and `dir`/lap2
// (41-84, the revisit of 1-44), for tests of sessions and of localizing one lap in the other.
#include <filesystem>
#include <string>
#include <utility>

namespace seqtopo::test_support {

inline std::filesystem::path corridor_folder() {
  return std::filesystem::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";
}

// (lap1, lap2)
inline std::pair<std::filesystem::path, std::filesystem::path> corridor_laps(const std::filesystem::path& dir) {
  const std::filesystem::path lap1 = dir / "lap1", lap2 = dir / "lap2";
  std::filesystem::create_directories(lap1);
  std::filesystem::create_directories(lap2);
  for (int k = 1; k <= 84; ++k) {
    const std::string name = std::to_string(k) + ".jpg";
    std::filesystem::create_symlink(corridor_folder() / name, (k <= 40 ? lap1 : lap2) / name);
  }
  return {lap1, lap2};
}

}  // namespace seqtopo::test_support
