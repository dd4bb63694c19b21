// The "cells" display: the linetree cells of one picked object, as the paper's figures
// show them. Each pixel whose eye ray first meets the picked object shows the leaf its
// line falls in (a colour per cell, dark where neighbouring pixels fall in different
// cells); the rest of the image is dimmed. It only looks cells up: nothing is built.
#pragma once
#include <vector>

#include "accel/world.h"
#include "image/image.h"
#include "interp/linetree.h"
#include "scene/camera.h"
#include "sched/workers.h"

namespace epsray {

// The object under (fx, fy), fractions of the image from its top-left corner, is picked
// (none when fx or fy is negative, or the point shows the background); returns its
// primitive, or -1 with the whole image dimmed. `leaves` is scratch kept by the caller
// (one entry per pixel).
int paint_cells(workers& pool, const world& w, const camera& cam, linetree_set& trees, float fx, float fy,
                const image& img, std::vector<const lt_node*>& leaves, std::vector<unsigned char>& rgb);

}  // namespace epsray
