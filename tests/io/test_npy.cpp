// .npy round trips and rejections (Fortran order, wrong dtype, NaN/Inf, wrong rank, truncation).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>

#include "common/temp_dir.hpp"
#include "seqtopo/core/input_error.hpp"
#include "seqtopo/io/npy.hpp"

namespace seqtopo::io {
namespace {
namespace fs = std::filesystem;

class Npy : public ::testing::Test {
 protected:
  // Writes a .npy by hand: header dict text (padded as numpy does) then raw bytes.
  fs::path handmade(const std::string& name, const std::string& dict, const std::string& data, int version = 1) {
    std::string header = dict;
    const std::size_t prefix = version == 1 ? 10 : 12;
    while ((prefix + header.size() + 1) % 64 != 0) header += ' ';
    header += '\n';
    std::string bytes("\x93NUMPY", 6);
    bytes.push_back(static_cast<char>(version));
    bytes.push_back('\0');
    if (version == 1) {
      const auto len = static_cast<std::uint16_t>(header.size());
      bytes.append(reinterpret_cast<const char*>(&len), 2);
    } else {
      const auto len = static_cast<std::uint32_t>(header.size());
      bytes.append(reinterpret_cast<const char*>(&len), 4);
    }
    bytes += header + data;
    return dir_.write(name, bytes);
  }

  template <typename T>
  static std::string raw(const std::vector<T>& v) {
    return {reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T)};
  }

  void expect_rejected(const fs::path& path, const std::string& fragment) {
    try {
      (void)read_npy_matrix<float>(path);
      FAIL() << "accepted " << path;
    } catch (const InputError& e) {
      EXPECT_EQ(e.subject(), path.string());
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }

  const test_support::TempDir dir_;
};

TEST_F(Npy, RoundTripFloatAndDouble) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1e6, 1e6);
  for (std::size_t rows : {1, 3, 17}) {
    for (std::size_t cols : {1, 5, 64}) {
      DenseMatrix<float> f(rows, cols);
      DenseMatrix<double> d(rows, cols);
      for (auto& v : f.values) v = static_cast<float>(u(rng));
      for (auto& v : d.values) v = u(rng);
      write_npy(dir_.path / "f.npy", f);
      write_npy(dir_.path / "d.npy", d);
      EXPECT_EQ(read_npy_matrix<float>(dir_.path / "f.npy"), f);
      EXPECT_EQ(read_npy_matrix<double>(dir_.path / "d.npy"), d);
      const auto header = read_npy_header(dir_.path / "d.npy");
      EXPECT_EQ(header.dtype, "<f8");
      EXPECT_EQ(header.shape, (std::vector<std::size_t>{rows, cols}));
      EXPECT_EQ(header.data_offset % 64, 0U) << "numpy aligns the data to 64 bytes";
      // The two parts written without a copy are the same bytes.
      EXPECT_EQ(npy_header(d) + std::string(npy_body(d)), encode_npy(d));
      EXPECT_EQ(npy_header(f).size(), header.data_offset);
      EXPECT_EQ(npy_header(f) + std::string(npy_body(f)), encode_npy(f));
    }
  }
}

TEST_F(Npy, ReadsWhatNumpyWrites) {
  // numpy.save(np.arange(6, dtype='<f4').reshape(2, 3)) writes exactly this header text.
  const auto path = handmade("np.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }",
                             raw(std::vector<float>{0, 1, 2, 3, 4, 5}));
  const auto m = read_npy_matrix<float>(path);
  ASSERT_EQ(m.rows, 2U);
  ASSERT_EQ(m.cols, 3U);
  EXPECT_EQ(m(1, 2), 5.0F);
  // version 2 headers too, and float64 converted to float32
  const auto v2 = handmade("v2.npy", "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 2), }",
                           raw(std::vector<double>{0.5, -2}), 2);
  EXPECT_EQ(read_npy_matrix<float>(v2)(0, 1), -2.0F);
}

TEST_F(Npy, Rejections) {
  const std::string six = raw(std::vector<float>{0, 1, 2, 3, 4, 5});
  expect_rejected(handmade("fortran.npy", "{'descr': '<f4', 'fortran_order': True, 'shape': (2, 3), }", six),
                  "Fortran");
  expect_rejected(handmade("int.npy", "{'descr': '<i4', 'fortran_order': False, 'shape': (2, 3), }", six), "dtype");
  expect_rejected(handmade("big.npy", "{'descr': '>f4', 'fortran_order': False, 'shape': (2, 3), }", six), "dtype");
  expect_rejected(handmade("1d.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (6,), }", six), "2-D");
  expect_rejected(handmade("3d.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 2, 3), }", six), "2-D");
  expect_rejected(handmade("short.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (3, 3), }", six),
                  "truncated");
  expect_rejected(handmade("empty.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (0, 3), }", ""), "empty");
  expect_rejected(handmade("nan.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }",
                           raw(std::vector<float>{0, 1, 2, NAN, 4, 5})),
                  "row 1, column 0");
  expect_rejected(handmade("inf.npy", "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 2), }",
                           raw(std::vector<double>{INFINITY, 0})),
                  "non-finite");
  std::ofstream(dir_.path / "text.npy") << "not numpy at all";
  expect_rejected(dir_.path / "text.npy", "magic");
  expect_rejected(dir_.path / "missing.npy", "cannot open");
}

// Shapes whose byte count wraps around 2^64 (issue #18, finding 8): (2^61 - 1) x 1 of 8 bytes is 2^64 - 8 bytes,
// plus the header offset wraps to a small number and once passed the truncation check, so the reader tried to
// allocate 2^64 bytes ("out of memory", no file named). Every reader names the file and says "truncated".
TEST_F(Npy, ShapesWhoseByteCountWrapsAreTruncated) {
  const std::string data = raw(std::vector<double>(8, 1.0));
  for (const std::string shape :
       {"(2305843009213693951, 1)", "(1, 2305843009213693951)", "(4611686018427387903, 1)", "(4294967296, 4294967296)",
        "(18446744073709551615, 1)", "(2305843009213693951,)", "(2, 1152921504606846976, 8)"}) {
    for (const std::string dtype : {"<f8", "<f4"}) {
      SCOPED_TRACE(shape + " " + dtype);
      const auto path =
          handmade("wrap.npy", "{'descr': '" + dtype + "', 'fortran_order': False, 'shape': " + shape + ", }", data);
      try {
        (void)read_npy_header(path);
        FAIL() << "header accepted";
      } catch (const InputError& e) {
        EXPECT_EQ(e.subject(), path.string());
        EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
      }
      try {
        (void)read_npy_matrix<float>(path);
        FAIL() << "matrix accepted";
      } catch (const InputError& e) {
        EXPECT_EQ(e.subject(), path.string());
      }
    }
  }
  // The exact fit still reads: 8 doubles as 2 x 4 and 8 x 1.
  EXPECT_NO_THROW((void)read_npy_matrix<float>(
      handmade("fit.npy", "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 4), }", data)));
  EXPECT_NO_THROW(
      (void)read_npy_header(handmade("fit1.npy", "{'descr': '<f8', 'fortran_order': False, 'shape': (8, 1), }", data)));
}

}  // namespace
}  // namespace seqtopo::io
