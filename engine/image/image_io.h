// PFM and PNG files written whole or not at all: a temporary file beside the target is
// renamed over it only once complete. Throws std::runtime_error on failure.
#pragma once
#include <string>

#include "image/image.h"

namespace epsray {

void write_pfm(const image& img, const std::string& path);
void write_png(const image& img, const std::string& path);
image read_pfm(const std::string& path);

// The 8-bit sRGB code of a linear value: clamped to [0, 1], piecewise curve, rounded.
unsigned char srgb_byte(float linear);
// The same computed directly (one pow per call); srgb_byte equals it for every float.
unsigned char srgb_byte_exact(float linear);

}  // namespace epsray
