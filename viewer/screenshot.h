// Screenshots as PNGs: the rendered picture alone, or the whole window (HUD and all) as the
// last draw left it in the back buffer.
#pragma once
#include <string>
#include <vector>

#include "image/image.h"

namespace epsray {

// Reads the current context's back buffer (width x height pixels) after drawing, before the
// swap. Throws std::runtime_error when the file cannot be written.
void save_screenshot(int width, int height, const std::string& path);
// RGB bytes, top row first (a shown_frame's display), as they are.
void save_picture(const std::vector<unsigned char>& rgb, int width, int height, const std::string& path);

// Screen bytes as the linear image write_png takes: each byte becomes the linear value
// whose sRGB code it is, so write_png writes the same bytes back.
image image_from_srgb_bytes(const std::vector<unsigned char>& rgb, int width, int height);
float linear_from_srgb_byte(unsigned char b);

}  // namespace epsray
