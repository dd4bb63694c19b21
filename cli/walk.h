// epsray walk: every camera of a path in order, keeping the linetrees between frames.
#pragma once
#include "args.h"

namespace epsray {

int run_walk(const cli_options& o);

}  // namespace epsray
