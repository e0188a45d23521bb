#pragma once
// seqtopo's version, from the one place it is written: project(seqtopo VERSION ...) in the top CMakeLists.txt
// (setup.py reads it there too). Shown by `seqtopo --version`, in metrics.json and in the reports.
#include <string_view>

namespace seqtopo {

std::string_view version();

}  // namespace seqtopo
