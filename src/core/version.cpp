#include "core/version.h"

namespace gyrosid {

std::string version_string() {
  const std::string commit = GYROSID_GIT_COMMIT;
  return std::string(GYROSID_VERSION) + (commit.empty() ? "" : " (git " + commit + ")");
}

}  // namespace gyrosid
