// epsray view: fly through a scene while the engine renders frames within epsilon.
#pragma once
#include "args.h"

namespace epsray {

int run_view(const cli_options& o);

}  // namespace epsray
