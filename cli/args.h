// The command line of ../shared/spec/contract.md, parsed and checked before any work.
#pragma once
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "sched/frame_render.h"

namespace epsray {

// A bad flag: printed as one line, exit code 2.
struct usage_error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct cli_options {
  std::string command;  // render, walk, view, info
  bool help = false;    // SUBCOMMAND --help (or -h): print usage_text(command), exit 0
  // The argument list as given, with "epsray" for the executable (the stats' provenance).
  std::vector<std::string> command_line;
  std::string scene;
  std::string path;
  std::optional<int> frame;
  std::optional<std::pair<int, int>> size;
  render_mode mode = render_mode::full;
  float eps = 0.05f;
  int threads = 0;  // 0: all hardware threads
  int tile_rows = 0;
  tile_order order = tile_order::costly_first;
  // render: png is SCENE-STEM.png in the current folder when neither --png nor --pfm is given.
  std::string png, pfm, stats, out_dir, reasons;
  std::string record, script, screenshot;  // view only
  // The interpolation knobs start at the engine's defaults (interp_params), stated once.
  float min_prim_pixels = interp_params{}.min_prim_pixels;
  // Unset: interp_params' values at rest and its moving_ ones while the camera moves;
  // given: the same value for both.
  std::optional<float> min_cell_pixels, failed_split_pixels, defer_pixels;
  bool four_way = interp_params{}.four_way;
  bool object_gate = interp_params{}.object_gate;
  bool plain_frames = interp_params{}.plain_frames;
  bool mirror = interp_params{}.mirror;
  bool light_cache = interp_params{}.light_cache;
  int span_segment = interp_params{}.span_segment;  // full: screen-space span segments; 0: none
  bool reproject_osmesa = false;  // full: draw last frame's cells with OSMesa, not the exact per-pixel test
  bool pipeline = false;  // walk, full: prepare each next frame's reprojection on a thread of its own
  // walk: every frame whose index is a multiple of keyframe starts afresh, with new linetrees
  // and no cells to reproject (0: never); under mpirun, segments start only at keyframes.
  int keyframe = 0;
  bool pin = false;  // bind worker threads to cores (hwloc)
  double memory_mb = 0;  // linetree memory budget; 0: none
  int upsample = 2, reuse_age = 4, lf_depth = 4;  // the baselines' knobs (frame_params)
  bool png_flag = false, pfm_flag = false, verify = false, quiet = false;
  bool base_cost = false;  // frame_params::base_cost
};

// args: the command line without the executable. Accepts `--flag value` and `--flag=value`.
cli_options parse_args(const std::vector<std::string>& args);
// The overall usage (epsray --help), or one subcommand's flags with their defaults.
std::string usage_text();
std::string usage_text(const std::string& command);
// A file name as usage messages quote it: 'name', or C-escaped in double quotes when it
// holds control characters, so the message stays one line.
std::string quote_file(const std::string& name);

}  // namespace epsray
