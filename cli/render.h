// epsray render: one frame of a scene, from its own view or a path's camera.
#pragma once
#include "args.h"

namespace epsray {

int run_render(const cli_options& o);

}  // namespace epsray
