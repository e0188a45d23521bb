#include "seqtopo/core/running_median.hpp"

namespace seqtopo {

void RunningMedian::add(double value) {
  if (lower_.empty() || value <= lower_.top()) {
    lower_.push(value);
  } else {
    upper_.push(value);
  }
  if (lower_.size() > upper_.size() + 1) {
    upper_.push(lower_.top());
    lower_.pop();
  } else if (upper_.size() > lower_.size()) {
    lower_.push(upper_.top());
    upper_.pop();
  }
}

double RunningMedian::median() const {
  if (lower_.empty()) return 0;
  return lower_.size() == upper_.size() ? upper_.top() : lower_.top();
}

void RunningMedian::clear() {
  lower_ = {};
  upper_ = {};
}

}  // namespace seqtopo
