// The joint histogram and kappa auto on the real corridor loop (84 images, ground truth): the descriptor is
// deliberately poor (mapping paper IV-A), but true revisits must still be clearly closer than other pairs.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>

#include "seqtopo/image/image_io.hpp"
#include "seqtopo/image/joint_histogram.hpp"
#include "seqtopo/pipeline/sequence_input.hpp"
#include "seqtopo/similarity/distance_matrix.hpp"
#include "seqtopo/similarity/similarity_from_distance.hpp"

namespace seqtopo::image {
namespace {

namespace fs = std::filesystem;

TEST(Corridor, RevisitsAreCloserAndKappaAutoKeepsThemPositive) {
  const fs::path folder = fs::path(SEQTOPO_SOURCE_DIR) / "data" / "rtabmap-corridor";  // bundled copy
  const auto files = pipeline::list_images(folder);
  ASSERT_EQ(files.size(), 84U);
  EXPECT_EQ(files.front().filename(), "1.jpg");
  EXPECT_EQ(files.back().filename(), "84.jpg");
  std::vector<similarity::SparseHistogram> histograms(files.size());
  const auto n = static_cast<std::ptrdiff_t>(files.size());
#pragma omp parallel for schedule(dynamic, 1)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    histograms[static_cast<std::size_t>(k)] = joint_histogram(load_image(files[static_cast<std::size_t>(k)]));
  }
  const auto d =
      similarity::distance_matrix(similarity::DescriptorSet::from_sparse(histograms), similarity::Distance::chi2);
  const similarity::KappaRule rule;
  const auto choice = similarity::choose_kappa(d, true, rule);
  const auto s = similarity::similarity_from_distance(d, choice.kappa);

  const cv::Mat truth = cv::imread((folder / "ground_truth.bmp").string(), cv::IMREAD_GRAYSCALE);
  ASSERT_EQ(truth.rows, 84);
  std::vector<float> same, other;
  std::size_t positive_same = 0, positive = 0;
  for (int i = 0; i < 84; ++i) {
    for (int j = 0; j + static_cast<int>(rule.min_separation) <= i; ++j) {
      const bool revisit = truth.at<std::uint8_t>(i, j) > 0 || truth.at<std::uint8_t>(j, i) > 0;
      const float v = d(static_cast<std::size_t>(i), static_cast<std::size_t>(j));
      (revisit ? same : other).push_back(v);
      const bool pos = s(static_cast<std::size_t>(i), static_cast<std::size_t>(j)) > 0;
      positive += pos ? 1 : 0;
      positive_same += pos && revisit ? 1 : 0;
    }
  }
  ASSERT_FALSE(same.empty());
  // Area under the ROC curve of "smaller distance = revisit": 0.5 would be chance.
  std::size_t wins = 0;
  for (float a : same) {
    for (float b : other) wins += a < b ? 1 : 0;
  }
  const double auc = static_cast<double>(wins) / (static_cast<double>(same.size()) * static_cast<double>(other.size()));
  EXPECT_GT(auc, 0.65);
  // S > 0 for about the fraction the rule chose, and those pairs are revisits far more often than chance.
  const double candidates = static_cast<double>(same.size() + other.size());
  EXPECT_NEAR(static_cast<double>(positive) / candidates, choice.fraction, 0.01);
  const double base_rate = static_cast<double>(same.size()) / candidates;
  EXPECT_GT(static_cast<double>(positive_same) / static_cast<double>(positive), 3.0 * base_rate);
}

}  // namespace
}  // namespace seqtopo::image
