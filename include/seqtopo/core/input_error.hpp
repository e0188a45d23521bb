#pragma once
// A problem with something the user gave us: a file or an option. The CLI prints it as
// `seqtopo: error: <subject>: <message>` and exits non-zero.
#include <stdexcept>
#include <string>

namespace seqtopo {

class InputError : public std::runtime_error {
 public:
  InputError(std::string subject, const std::string& message)
      : std::runtime_error(message), subject_(std::move(subject)) {}
  const std::string& subject() const { return subject_; }

 private:
  std::string subject_;
};

}  // namespace seqtopo
