#include "seqtopo/core/version.hpp"

namespace seqtopo {

// SEQTOPO_VERSION is defined for this one file (src/CMakeLists.txt), so a new version recompiles nothing else.
std::string_view version() { return SEQTOPO_VERSION; }

}  // namespace seqtopo
