#pragma once
// The median of the values so far, as they arrive: two heaps, O(log n) a value. The median is the upper one, the
// element at index n / 2 of the values sorted (as std::nth_element at size() / 2 gives it), so a rule on a whole
// sequence's median and the same rule on the values so far agree once every value is in.
#include <cstddef>
#include <functional>
#include <queue>
#include <vector>

namespace seqtopo {

class RunningMedian {
 public:
  void add(double value);
  // The upper median; 0 before any value.
  double median() const;
  std::size_t size() const { return lower_.size() + upper_.size(); }
  void clear();

 private:
  std::priority_queue<double> lower_;                                       // the lower half (one more on an odd count)
  std::priority_queue<double, std::vector<double>, std::greater<>> upper_;  // the upper half
};

}  // namespace seqtopo
