// What the commands share: output checks before any work, text files written whole, and
// the frame parameters the command line sets.
#pragma once
#include <exception>
#include <memory>
#include <string>

#include "accel/world.h"
#include "args.h"
#include "image/image.h"
#include "sched/frame_render.h"

namespace epsray {

// The one line printed for an error and the exit code: 2 for bad input (input_error,
// usage_error), 1 for anything else.
int describe_error(const std::exception_ptr& e, std::string& line);

// Output files must be writable before any work starts: bad input writes nothing.
void check_writable(const std::string& file, const char* flag);
// An output folder: an existing folder, or one that can be made in a writable parent.
void check_out_dir(const std::string& dir);
// Writes `text` to a temporary beside `path`, renamed over it once complete, so a reader
// never sees half a file. Throws std::runtime_error when it cannot.
void write_text_file(const std::string& path, const std::string& text);
// Commands not built yet fail before any work, with a clear message (exit 1).
void reject_unbuilt(const cli_options& o);
// A NaN or infinite pixel is an internal error: nothing is written.
void check_finite(const frame_result& fr);
frame_params make_frame_params(const cli_options& o, linetree_set* trees, reprojection_state* reproj);

// `--reproject osmesa` in full mode: loads OSMesa into reproj (throws, exit 1, where it
// cannot). Called with the input checks, before any output is made and before the clock.
void open_reprojection(const cli_options& o, reprojection_state& reproj);
// The linetrees of interp and full modes, with --memory-mb's budget; none for base (their
// sample caches alone are tens of MB).
std::unique_ptr<linetree_set> make_linetrees(const cli_options& o, const world& w);

}  // namespace epsray
