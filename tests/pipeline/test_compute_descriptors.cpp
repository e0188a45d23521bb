// compute_descriptors: the per-image vectors without the N x N matrix (what --streaming maps from).
#include <gtest/gtest.h>

#include <algorithm>

#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/image/image_io.hpp"
#include "seqtopo/io/npy.hpp"
#include "seqtopo/pipeline/sequence_similarity.hpp"

namespace seqtopo::pipeline {
namespace {

const std::filesystem::path corridor = std::filesystem::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";

TEST(ComputeDescriptors, ImageFolderGivesOneDenseDescriptorPerImage) {
  SimilarityConfig config;
  config.descriptor = Descriptor::patch;
  const DescriptorResult r = compute_descriptors({corridor}, config);
  const auto images = list_images(corridor);
  ASSERT_EQ(r.descriptors.rows, images.size());
  EXPECT_EQ(r.descriptors.cols, dense_dimension(Descriptor::patch, config));
  EXPECT_EQ(r.descriptor, Descriptor::patch);
  EXPECT_EQ(r.frame_names.size(), images.size());
  for (const std::size_t i : {std::size_t{0}, images.size() / 2, images.size() - 1}) {
    const auto expected = dense_descriptor(image::load_image(images[i]), Descriptor::patch, config);
    const auto row = r.descriptors.row(i);
    EXPECT_TRUE(std::equal(row.begin(), row.end(), expected.begin(), expected.end())) << i;
  }
}

TEST(ComputeDescriptors, DescriptorsFileGivesItsRows) {
  const test_support::TempDir dir;
  DenseMatrix<float> x(5, 3);
  for (std::size_t k = 0; k < x.values.size(); ++k) x.values[k] = static_cast<float>(k) + 0.5F;
  io::write_npy(dir.path / "d.npy", x);
  const DescriptorResult r = compute_descriptors({dir.path / "d.npy"});
  EXPECT_EQ(r.descriptors.values, x.values);
  EXPECT_EQ(r.descriptor, Descriptor::npy);
}

TEST(ComputeDescriptors, RefusesWhatHasNoVectorForm) {
  SimilarityConfig config;  // joint histogram
  EXPECT_THROW(compute_descriptors({corridor}, config), InputError);
  const test_support::TempDir dir;
  io::write_npy(dir.path / "s.npy", DenseMatrix<float>(4, 4, 0.5F));
  EXPECT_THROW(compute_descriptors({dir.path / "s.npy", InputKind::similarity}), InputError);
}

}  // namespace
}  // namespace seqtopo::pipeline
