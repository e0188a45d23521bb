#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>
#include <random>
#include <string>

#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/formats/odometry_csv.hpp"

namespace seqtopo::formats {
namespace {

namespace fs = std::filesystem;

class OdometryCsv : public ::testing::Test {
 protected:
  // The InputError subject of reading `text`, or "" when it reads fine.
  std::string error_subject(const std::string& text, bool poses = false) {
    const fs::path p = dir_.write("bad.csv", text);
    try {
      if (poses) {
        read_poses_csv(p);
      } else {
        read_odometry_csv(p);
      }
    } catch (const InputError& e) {
      return e.subject();
    }
    return "";
  }

  const test_support::TempDir dir_;
};

TEST_F(OdometryCsv, CumulativePoses) {
  const auto poses =
      read_odometry_csv(dir_.write("odo.csv", "index,x,y,theta\n0,0,0,0\n1, 0.5 ,0.25,0.1\r\n\n2,1.0,-2,+3\n"));
  ASSERT_EQ(poses.size(), 3U);
  EXPECT_DOUBLE_EQ(poses[1].x, 0.5);
  EXPECT_DOUBLE_EQ(poses[1].y, 0.25);
  EXPECT_DOUBLE_EQ(poses[1].theta, 0.1);
  EXPECT_DOUBLE_EQ(poses[2].y, -2);
  EXPECT_DOUBLE_EQ(poses[2].theta, 3);
}

TEST_F(OdometryCsv, IncrementsAreComposedInTheRobotFrame) {
  // Forward 1 m, turn left 90 degrees, forward 1 m: the robot ends at (1, 1) facing +y.
  const auto poses =
      read_odometry_csv(dir_.write("inc.csv", "index,dx,dy,dtheta\n0,0,0,0\n1,1,0,1.5707963267948966\n2,1,0,0\n"));
  ASSERT_EQ(poses.size(), 3U);
  EXPECT_NEAR(poses[1].x, 1, 1e-12);
  EXPECT_NEAR(poses[1].y, 0, 1e-12);
  EXPECT_NEAR(poses[2].x, 1, 1e-12);
  EXPECT_NEAR(poses[2].y, 1, 1e-12);
  EXPECT_NEAR(poses[2].theta, std::numbers::pi / 2, 1e-12);
}

TEST_F(OdometryCsv, IntegratedIncrementsEqualTheCumulativeForm) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> step(-0.3, 0.6), turn(-0.4, 0.4);
  std::vector<Pose2> truth{{0.2, -0.1, 0.3}};
  for (int i = 1; i < 200; ++i) truth.push_back(compose(truth.back(), {step(rng), step(rng) / 4, turn(rng)}));
  std::string cumulative = "index,x,y,theta\n", increments = "index,dx,dy,dtheta\n";
  char buf[200];
  for (std::size_t i = 0; i < truth.size(); ++i) {
    const Pose2 d = i == 0 ? truth[0] : between(truth[i - 1], truth[i]);
    std::snprintf(buf, sizeof buf, "%zu,%.17g,%.17g,%.17g\n", i, truth[i].x, truth[i].y, truth[i].theta);
    cumulative += buf;
    std::snprintf(buf, sizeof buf, "%zu,%.17g,%.17g,%.17g\n", i, d.x, d.y, d.theta);
    increments += buf;
  }
  const auto a = read_odometry_csv(dir_.write("a.csv", cumulative));
  const auto b = read_odometry_csv(dir_.write("b.csv", increments));
  ASSERT_EQ(a.size(), truth.size());
  ASSERT_EQ(b.size(), truth.size());
  for (std::size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(a[i].x, b[i].x, 1e-9) << i;
    EXPECT_NEAR(a[i].y, b[i].y, 1e-9) << i;
    EXPECT_NEAR(wrap_angle(a[i].theta - b[i].theta), 0, 1e-9) << i;
  }
}

TEST_F(OdometryCsv, GroundTruthPosesWithAndWithoutHeading) {
  const auto xy = read_poses_csv(dir_.write("gt.csv", "index,x,y\n0,1,2\n1,3,4\n"));
  ASSERT_EQ(xy.size(), 2U);
  EXPECT_DOUBLE_EQ(xy[1].x, 3);
  EXPECT_DOUBLE_EQ(xy[1].y, 4);
  EXPECT_DOUBLE_EQ(xy[1].theta, 0);
  const auto xyt = read_poses_csv(dir_.write("gt2.csv", "index,x,y,theta\n0,1,2,0.5\n"));
  ASSERT_EQ(xyt.size(), 1U);
  EXPECT_DOUBLE_EQ(xyt[0].theta, 0.5);
}

TEST_F(OdometryCsv, ErrorsNameTheFileAndLine) {
  const std::string bad = (dir_.path / "bad.csv").string();
  EXPECT_EQ(error_subject("index,x,y\n0,0,0\n"), bad + ":1");  // wrong header for odometry
  EXPECT_EQ(error_subject("idx,x,y,theta\n0,0,0,0\n"), bad + ":1");
  EXPECT_EQ(error_subject("index,x,y,theta\n0,0,0,0\n1,0,abc,0\n"), bad + ":3");  // non-numeric
  EXPECT_EQ(error_subject("index,x,y,theta\n0,0,0,0\n1,0,1.5x,0\n"), bad + ":3");
  EXPECT_EQ(error_subject("index,x,y,theta\n0,0,0,0\n1,0,,0\n"), bad + ":3");          // empty field
  EXPECT_EQ(error_subject("index,x,y,theta\n0,0,0,0\n2,0,0,0\n"), bad + ":3");         // index skipped
  EXPECT_EQ(error_subject("index,x,y,theta\n1,0,0,0\n"), bad + ":2");                  // must start at 0
  EXPECT_EQ(error_subject("index,x,y,theta\n0,0,0,0\n0,0,0,0\n"), bad + ":3");         // repeated
  EXPECT_EQ(error_subject("index,dx,dy,dtheta\n0,0,0,0\n\n1,nan,0,0\n"), bad + ":4");  // NaN
  EXPECT_EQ(error_subject("index,x,y,theta\n0,0,0,inf\n"), bad + ":2");
  EXPECT_EQ(error_subject("index,x,y,theta\n0,0,0\n"), bad + ":2");      // too few fields
  EXPECT_EQ(error_subject("index,x,y,theta\n0,0,0,0,7\n"), bad + ":2");  // too many
  EXPECT_EQ(error_subject(""), bad);                                     // no header
  EXPECT_EQ(error_subject("index,x,y,theta\n"), bad);                    // no rows
  EXPECT_EQ(error_subject("index,x,y,theta\n0,0,0,0\n", true), "");
  EXPECT_EQ(error_subject("index,dx,dy,dtheta\n0,0,0,0\n", true), bad + ":1");  // increments are not poses
  EXPECT_EQ(error_subject("index,x,y\n0,0,q\n", true), bad + ":2");

  const fs::path missing = dir_.path / "missing.csv";
  try {
    read_odometry_csv(missing);
    FAIL() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(e.subject(), missing.string());
  }
  EXPECT_THROW(read_poses_csv(missing), InputError);
}

TEST_F(OdometryCsv, MessagesSayWhatIsWrong) {
  try {
    read_odometry_csv(dir_.write("h.csv", "index,x,y\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("index,dx,dy,dtheta"), std::string::npos) << e.what();
  }
  try {
    read_odometry_csv(dir_.write("o.csv", "index,x,y,theta\n0,0,0,0\n5,0,0,0\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("expected 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace seqtopo::formats
