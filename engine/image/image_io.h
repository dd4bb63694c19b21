// PFM and PNG files written whole or not at all: a temporary file beside the target is
// renamed over it only once complete. Throws std::runtime_error on failure.
#pragma once
#include <cstdio>
#include <functional>
#include <string>

#include "image/image.h"

namespace epsray {

// Runs `body` on a temporary file beside `path` (named path.tmp.PID) and renames it over
// `path` once body returns true and the file is closed, so a reader never sees half a
// file; on any failure the temporary is removed and std::runtime_error thrown. A path that
// is a symbolic link is written through: its target is replaced and the link kept. A path
// that exists and is not a regular file (a device, a FIFO), or lies under /dev or /proc
// (/dev/stdout), is written in place: renaming over it would replace the device, or the
// file another process has open as its stdout.
void write_atomically(const std::string& path, const std::function<bool(std::FILE*)>& body);
// Whether write_atomically writes `path` in place, as just said.
bool written_in_place(const std::string& path);

void write_pfm(const image& img, const std::string& path);
void write_png(const image& img, const std::string& path);
image read_pfm(const std::string& path);

// The 8-bit sRGB code of a linear value: clamped to [0, 1], piecewise curve, rounded.
unsigned char srgb_byte(float linear);
// The same computed directly (one pow per call); srgb_byte equals it for every float.
unsigned char srgb_byte_exact(float linear);

}  // namespace epsray
