#include "version.h"

#include "epsray_commit.h"  // EPSRAY_COMMIT, written at build time (cli/version.cmake)

namespace epsray {

std::string epsray_version() { return std::string(EPSRAY_VERSION) + "+" + EPSRAY_COMMIT; }

}  // namespace epsray
