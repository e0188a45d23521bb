#include "seqtopo/image/grey_matrix_file.hpp"

#include "seqtopo/core/input_error.hpp"
#include "seqtopo/image/codecs.hpp"

namespace seqtopo::image {

DenseMatrix<std::uint8_t> read_grey_matrix_image(const std::filesystem::path& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path.string(), "no such file");
  const cv::Mat grey = codecs::read_grey(path);
  if (grey.empty()) throw InputError(path.string(), "not a readable image");
  DenseMatrix<std::uint8_t> m(static_cast<std::size_t>(grey.rows), static_cast<std::size_t>(grey.cols));
  for (int r = 0; r < grey.rows; ++r) {
    const auto* row = grey.ptr<std::uint8_t>(r);
    std::copy(row, row + grey.cols, m.row(static_cast<std::size_t>(r)).begin());
  }
  return m;
}

}  // namespace seqtopo::image
