#include "util/version.hpp"

#include "kanesens/git_revision.hpp"
#include "kanesens/version_config.hpp"

namespace kanesens {

std::string version_short() {
  return std::string(KANESENS_VERSION_STRING) + " (git " + KANESENS_GIT_REVISION + ")";
}

}  // namespace kanesens
