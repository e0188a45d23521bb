#pragma once
// An 8-bit single-channel image read as a matrix (e.g. a ground-truth same-place matrix).
#include <cstdint>
#include <filesystem>

#include "seqtopo/core/dense_matrix.hpp"

namespace seqtopo::image {

// Colour images are converted to grey. Throws InputError naming the file if it cannot be read.
DenseMatrix<std::uint8_t> read_grey_matrix_image(const std::filesystem::path& path);

}  // namespace seqtopo::image
