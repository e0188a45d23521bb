// VPR-Bench's ground_truth_new.npy: the object arrays NumPy pickles, as Python 2 wrote VPR-Bench's own files
// and as Python 3's numpy.save writes them today.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "common/npy_bytes.hpp"
#include "seqtopo/formats/vpr_bench_npy.hpp"

namespace seqtopo::formats {
namespace {

// A .npy header of an object array of `rows` x 2 followed by `pickle`.
std::string object_npy(std::size_t rows, const std::string& pickle) {
  return test_support::npy_v1_header("|O", rows, 2) + pickle;
}

// The opcodes of VPR-Bench's own files (Python 2, protocol 2): integers and lists of integers.
std::string python2_pickle(const std::vector<std::pair<int, std::vector<int>>>& rows) {
  const auto k = [](int v) { return std::string("K") + static_cast<char>(v); };
  std::string p =
      "\x80\x02"
      "cnumpy.core.multiarray\n_reconstruct\nq\x01"
      "cnumpy\nndarray\nq\x02";
  p += k(0) +
       "\x85U\x01"
       "b\x87Rq\x03(" +
       k(1) + k(static_cast<int>(rows.size())) + k(2) + "\x86";
  p += "cnumpy\ndtype\nq\x04U\x02O8" + k(0) + k(1) + "\x87Rq\x05(" + k(3) + "U\x01|NNN";
  p += std::string("J\xff\xff\xff\xffJ\xff\xff\xff\xff", 10) + k(63) + "tb\x89]q\x06(";
  for (const auto& [q, maps] : rows) {
    p += k(q) + "](";
    for (int m : maps) p += k(m);
    p += "e";
  }
  return p + "etb.";
}

TEST(VprBenchNpy, ReadsThePython2FilesVprBenchShips) {
  const auto bytes = object_npy(3, python2_pickle({{0, {0, 1}}, {1, {0, 1, 2}}, {2, {}}}));
  ASSERT_TRUE(npy_holds_objects(bytes));
  const auto rows = parse_vpr_bench_npy(bytes);
  ASSERT_EQ(rows.size(), 3U);
  EXPECT_EQ(rows[0].query, 0U);
  EXPECT_EQ(rows[0].maps, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(rows[1].maps, (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(rows[2].query, 2U);
  EXPECT_TRUE(rows[2].maps.empty());
}

// numpy.save of [[np.int64(0), np.array([0, 1])], [1, [2, np.int32(0)]], [2, np.array([], dtype=np.int64)]]
// (Python 3, NumPy 1.24: protocol 3, NumPy scalars and arrays among the objects).
const char kPython3[] =
    "\x93\x4e\x55\x4d\x50\x59\x01\x00\x76\x00\x7b\x27\x64\x65\x73\x63\x72\x27\x3a\x20\x27\x7c\x4f\x27"
    "\x2c\x20\x27\x66\x6f\x72\x74\x72\x61\x6e\x5f\x6f\x72\x64\x65\x72\x27\x3a\x20\x46\x61\x6c\x73\x65"
    "\x2c\x20\x27\x73\x68\x61\x70\x65\x27\x3a\x20\x28\x33\x2c\x20\x32\x29\x2c\x20\x7d\x20\x20\x20\x20"
    "\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20"
    "\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20\x20"
    "\x20\x20\x20\x20\x20\x20\x20\x0a\x80\x03\x63\x6e\x75\x6d\x70\x79\x2e\x63\x6f\x72\x65\x2e\x6d\x75"
    "\x6c\x74\x69\x61\x72\x72\x61\x79\x0a\x5f\x72\x65\x63\x6f\x6e\x73\x74\x72\x75\x63\x74\x0a\x71\x00"
    "\x63\x6e\x75\x6d\x70\x79\x0a\x6e\x64\x61\x72\x72\x61\x79\x0a\x71\x01\x4b\x00\x85\x71\x02\x43\x01"
    "\x62\x71\x03\x87\x71\x04\x52\x71\x05\x28\x4b\x01\x4b\x03\x4b\x02\x86\x71\x06\x63\x6e\x75\x6d\x70"
    "\x79\x0a\x64\x74\x79\x70\x65\x0a\x71\x07\x58\x02\x00\x00\x00\x4f\x38\x71\x08\x89\x88\x87\x71\x09"
    "\x52\x71\x0a\x28\x4b\x03\x58\x01\x00\x00\x00\x7c\x71\x0b\x4e\x4e\x4e\x4a\xff\xff\xff\xff\x4a\xff"
    "\xff\xff\xff\x4b\x3f\x74\x71\x0c\x62\x89\x5d\x71\x0d\x28\x63\x6e\x75\x6d\x70\x79\x2e\x63\x6f\x72"
    "\x65\x2e\x6d\x75\x6c\x74\x69\x61\x72\x72\x61\x79\x0a\x73\x63\x61\x6c\x61\x72\x0a\x71\x0e\x68\x07"
    "\x58\x02\x00\x00\x00\x69\x38\x71\x0f\x89\x88\x87\x71\x10\x52\x71\x11\x28\x4b\x03\x58\x01\x00\x00"
    "\x00\x3c\x71\x12\x4e\x4e\x4e\x4a\xff\xff\xff\xff\x4a\xff\xff\xff\xff\x4b\x00\x74\x71\x13\x62\x43"
    "\x08\x00\x00\x00\x00\x00\x00\x00\x00\x71\x14\x86\x71\x15\x52\x71\x16\x68\x00\x68\x01\x4b\x00\x85"
    "\x71\x17\x68\x03\x87\x71\x18\x52\x71\x19\x28\x4b\x01\x4b\x02\x85\x71\x1a\x68\x11\x89\x43\x10\x00"
    "\x00\x00\x00\x00\x00\x00\x00\x01\x00\x00\x00\x00\x00\x00\x00\x71\x1b\x74\x71\x1c\x62\x4b\x01\x5d"
    "\x71\x1d\x28\x4b\x02\x68\x0e\x68\x07\x58\x02\x00\x00\x00\x69\x34\x71\x1e\x89\x88\x87\x71\x1f\x52"
    "\x71\x20\x28\x4b\x03\x68\x12\x4e\x4e\x4e\x4a\xff\xff\xff\xff\x4a\xff\xff\xff\xff\x4b\x00\x74\x71"
    "\x21\x62\x43\x04\x00\x00\x00\x00\x71\x22\x86\x71\x23\x52\x71\x24\x65\x4b\x02\x68\x00\x68\x01\x4b"
    "\x00\x85\x71\x25\x68\x03\x87\x71\x26\x52\x71\x27\x28\x4b\x01\x4b\x00\x85\x71\x28\x68\x11\x89\x43"
    "\x00\x71\x29\x74\x71\x2a\x62\x65\x74\x71\x2b\x62\x2e";

TEST(VprBenchNpy, ReadsNumpyScalarsAndArraysAsPython3WritesThem) {
  const std::string bytes(kPython3, sizeof kPython3 - 1);
  const auto rows = parse_vpr_bench_npy(bytes);
  ASSERT_EQ(rows.size(), 3U);
  EXPECT_EQ(rows[0].query, 0U);
  EXPECT_EQ(rows[0].maps, (std::vector<std::size_t>{0, 1}));
  EXPECT_EQ(rows[1].query, 1U);
  EXPECT_EQ(rows[1].maps, (std::vector<std::size_t>{2, 0}));
  EXPECT_EQ(rows[2].query, 2U);
  EXPECT_TRUE(rows[2].maps.empty());
}

std::string error_of(const std::string& bytes) {
  try {
    parse_vpr_bench_npy(bytes);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(VprBenchNpy, RefusesWhatIsNotAGroundTruthAndRunsNoCode) {
  EXPECT_EQ(error_of("not a npy"), "not a .npy file");
  // A global outside NumPy's array constructors is refused before anything is called.
  EXPECT_EQ(error_of(object_npy(1,
                                "\x80\x02"
                                "cos\nsystem\n.")),
            "pickle: 'os system' is not one of the NumPy constructors read");
  // Truncated in the middle of the rows.
  const auto whole = python2_pickle({{0, {0}}});
  EXPECT_EQ(error_of(object_npy(1, whole.substr(0, whole.size() - 4))), "pickle: truncated");
  // A negative index.
  std::string negative = python2_pickle({{0, {5}}});
  negative.replace(negative.rfind("K\x05"), 2, std::string("J\xfe\xff\xff\xff", 5));
  EXPECT_EQ(error_of(object_npy(1, negative)), "row 0: a negative index -2");
  // Three rows declared by the header, one pickled.
  EXPECT_EQ(error_of(object_npy(3, python2_pickle({{0, {0}}}))), "the header's shape is not the array's");
  // A numeric .npy is not VPR-Bench's form.
  std::string numeric = "\x93NUMPY\x01";
  numeric += std::string("\0F\0", 3) + "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 1), }";
  EXPECT_FALSE(npy_holds_objects(numeric));
}

}  // namespace
}  // namespace seqtopo::formats
