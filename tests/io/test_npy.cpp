// .npy round trips, every dtype and order numpy saves, and rejections (other dtypes, NaN/Inf, wrong rank,
// truncation).
#include <gtest/gtest.h>

#include <array>
#include <bit>
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

// The 2 x 3 matrix {{1, -2, 0.5}, {65504, 2^-24, -0}} as numpy saves it in other dtypes and orders: every one
// reads as the float32 one does.
TEST_F(Npy, ReadsEveryDtypeAndOrderNumpySaves) {
  const std::vector<float> expected{1, -2, 0.5F, 65504, std::ldexp(1.0F, -24), -0.0F};
  const auto check = [&](const std::string& name, const std::string& descr, bool fortran, const std::string& data) {
    SCOPED_TRACE(name);
    const auto path = handmade(
        name, "{'descr': '" + descr + "', 'fortran_order': " + (fortran ? "True" : "False") + ", 'shape': (2, 3), }",
        data);
    const auto m = read_npy_matrix<float>(path);
    ASSERT_EQ(m.rows, 2U);
    ASSERT_EQ(m.cols, 3U);
    for (std::size_t k = 0; k < 6; ++k) EXPECT_EQ(m.values[k], expected[k]) << k;
    EXPECT_EQ(read_npy_header(path).dtype, descr);
  };
  // float16: 1 = 0x3C00, -2 = 0xC000, 0.5 = 0x3800, 65504 = 0x7BFF (the largest), 2^-24 = 0x0001 (subnormal).
  const std::vector<std::uint16_t> half{0x3C00, 0xC000, 0x3800, 0x7BFF, 0x0001, 0x8000};
  check("half.npy", "<f2", false, raw(half));
  std::vector<std::uint16_t> swapped;
  for (auto h : half) swapped.push_back(static_cast<std::uint16_t>((h >> 8) | (h << 8)));
  check("half_big.npy", ">f2", false, raw(swapped));
  // big-endian float32: each value's four bytes reversed
  std::string big;
  for (float v : expected) {
    const auto b = std::bit_cast<std::array<char, 4>>(v);
    big.append(b.rbegin(), b.rend());
  }
  check("big.npy", ">f4", false, big);
  // Fortran order: column after column
  check("fortran.npy", "<f4", true,
        raw(std::vector<float>{expected[0], expected[3], expected[1], expected[4], expected[2], expected[5]}));
  check("fortran8.npy", "=f8", true,
        raw(std::vector<double>{expected[0], expected[3], expected[1], expected[4], expected[2], expected[5]}));

  // Integers and booleans: exact small values.
  const auto ints = [&](const std::string& name, const std::string& descr, const std::string& data,
                        const std::vector<float>& want) {
    SCOPED_TRACE(name);
    const auto m = read_npy_matrix<float>(
        handmade(name, "{'descr': '" + descr + "', 'fortran_order': False, 'shape': (2, 3), }", data));
    EXPECT_EQ(m.values, want);
  };
  ints("i1.npy", "|i1", raw(std::vector<std::int8_t>{-128, -1, 0, 1, 127, 5}), {-128, -1, 0, 1, 127, 5});
  ints("u1.npy", "|u1", raw(std::vector<std::uint8_t>{0, 1, 128, 200, 255, 7}), {0, 1, 128, 200, 255, 7});
  ints("i2.npy", "<i2", raw(std::vector<std::int16_t>{-32768, -300, 0, 300, 32767, 1}),
       {-32768, -300, 0, 300, 32767, 1});
  ints("i4big.npy", ">i4", std::string("\xff\xff\xff\xfe\x00\x00\x01\x00", 8) + std::string(16, '\0'),
       {-2, 256, 0, 0, 0, 0});
  ints("u4.npy", "<u4", raw(std::vector<std::uint32_t>{4000000000U, 0, 1, 2, 3, 4}), {4e9F, 0, 1, 2, 3, 4});
  ints("i8.npy", "<i8", raw(std::vector<std::int64_t>{-5, 1LL << 40, 0, 1, 2, 3}),
       {-5, static_cast<float>(1LL << 40), 0, 1, 2, 3});
  ints("u8.npy", "<u8", raw(std::vector<std::uint64_t>{9, 8, 7, 6, 5, 4}), {9, 8, 7, 6, 5, 4});
  ints("b1.npy", "|b1", raw(std::vector<std::uint8_t>{0, 1, 1, 0, 0, 1}), {0, 1, 1, 0, 0, 1});
}

TEST_F(Npy, Rejections) {
  const std::string six = raw(std::vector<float>{0, 1, 2, 3, 4, 5});
  for (const char* dtype : {"<c8", "<U4", "|O", "<f16", "<f3", "f4", "<x4", "|b2"}) {
    expect_rejected(
        handmade("other.npy", std::string("{'descr': '") + dtype + "', 'fortran_order': False, 'shape': (2, 3), }",
                 six + six + six + six),
        "dtype");
  }
  expect_rejected(handmade("big.npy", "{'descr': '<f8', 'fortran_order': False, 'shape': (1, 2), }",
                           raw(std::vector<double>{1e300, 0})),
                  "too large for float32");
  expect_rejected(handmade("halfnan.npy", "{'descr': '<f2', 'fortran_order': False, 'shape': (1, 2), }",
                           raw(std::vector<std::uint16_t>{0x3C00, 0x7E00})),
                  "row 0, column 1");
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
  expect_rejected(dir_.path / "missing.npy", "no such .npy file");
}

// The header is a Python dict literal as numpy reads it (ast.literal_eval): a negative dimension is refused with
// its sign, not read as its digits; only the dict's own keys count, so 'shape' inside another key's string or a
// nested dict is not the shape; keys other than numpy's three, a key twice, and "(12)" (a number, not a tuple)
// are refused as numpy refuses them.
TEST_F(Npy, HeaderIsParsedAsThePythonDictNumpyReads) {
  const std::string data = raw(std::vector<float>(96, 1.0F));
  const auto header = [&](const std::string& name, const std::string& dict) { return handmade(name, dict, data); };
  expect_rejected(header("neg0.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (-1, 8), }"),
                  "shape (-1, 8) has a negative dimension");
  expect_rejected(header("neg1.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (12, -8), }"),
                  "shape (12, -8) has a negative dimension");
  expect_rejected(header("word.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (12, x8), }"),
                  "not an integer");
  expect_rejected(header("nottuple.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (12), }"),
                  "is not a tuple");
  // The only 'shape' is inside the descr string: there is no shape key.
  expect_rejected(header("instring.npy", "{'descr': '<f4', 'fortran_order': False, 'x': \"'shape': (2, 3)\"}"),
                  "unknown key 'x'");
  expect_rejected(header("nested.npy", "{'descr': '<f4', 'fortran_order': False, 'meta': {'shape': (2, 3)}}"),
                  "unknown key 'meta'");
  expect_rejected(header("twice.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), 'shape': (4, 4)}"),
                  "'shape' twice");
  expect_rejected(header("unclosed.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), "),
                  "not a valid .npy header");
  expect_rejected(header("trailing.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3)} junk"),
                  "text after the dict");
  expect_rejected(header("fortran.npy", "{'descr': '<f4', 'fortran_order': 'False', 'shape': (2, 3)}"),
                  "fortran_order");
  // What numpy accepts: keys in any order, double quotes, no trailing comma, spaces anywhere.
  const auto m =
      read_npy_matrix<float>(header("ok.npy", "{ \"shape\" : ( 8 , 12 ) , 'fortran_order':False,'descr':\"<f4\" }"));
  EXPECT_EQ(m.rows, 8U);
  EXPECT_EQ(m.cols, 12U);
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
