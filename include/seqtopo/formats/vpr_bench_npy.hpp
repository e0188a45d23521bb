#pragma once
// VPR-Bench's ground truth, `ground_truth_new.npy`: a NumPy object array of shape (Q, 2) saved with
// numpy.save(..., allow_pickle=True), one row per query image: [query index, the indices of its true reference
// images] (a list, a NumPy integer array or one integer). The objects are pickled (Python 2 or 3, protocols 0-5);
// this reads the restricted set of pickle opcodes and NumPy constructors such a file holds and never runs code.
#include <cstddef>
#include <string_view>
#include <vector>

namespace seqtopo::formats {

struct QueryMatches {
  std::size_t query = 0;
  std::vector<std::size_t> maps;  // in the file's order
};

// True when `bytes` is a .npy file whose dtype is Python objects ('|O'): VPR-Bench's form, not a numeric matrix.
bool npy_holds_objects(std::string_view bytes);

// The rows of a VPR-Bench ground-truth file. Throws std::invalid_argument saying what is wrong (not a .npy,
// not an object array of shape (Q, 2), a pickle opcode or constructor outside the set NumPy writes, a negative or
// non-integer index).
std::vector<QueryMatches> parse_vpr_bench_npy(std::string_view bytes);

}  // namespace seqtopo::formats
