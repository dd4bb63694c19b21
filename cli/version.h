// What made an output: `epsray --version`, `epsray info` and the stats JSON's provenance.
#pragma once
#include <string>

namespace epsray {

// The project's version and the commit built, as VERSION+COMMIT ("0.2.0+1d7a189", with
// "-dirty" for uncommitted changes, "+unknown" outside a git checkout).
std::string epsray_version();

}  // namespace epsray
