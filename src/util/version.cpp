#include "util/version.hpp"

#include "kanesens/git_revision.hpp"
#include "kanesens/version_config.hpp"

namespace kanesens {

std::string version_short() {
  return std::string(KANESENS_VERSION_STRING) + " (git " + KANESENS_GIT_REVISION + ")";
}

// A build for an instruction set says so: its results may differ at round-off from the baseline's.
std::string instruction_set() {
  const std::string arch = KANESENS_ARCH;
  return arch.empty() ? "the compiler's baseline" : "-march=" + arch;
}

}  // namespace kanesens
