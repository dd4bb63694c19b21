#include "args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "scene/input_error.h"

namespace epsray {

namespace {

[[noreturn]] void bad(const std::string& m) { throw usage_error("epsray: " + m); }

long to_int(const std::string& flag, const std::string& v, long lo, long hi) {
  char* end = nullptr;
  errno = 0;
  long x = std::strtol(v.c_str(), &end, 10);
  if (v.empty() || *end || errno == ERANGE || x < lo || x > hi)
    bad("bad " + flag + " '" + v + "': expected an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
  return x;
}

double to_number(const std::string& flag, const std::string& v, double lo, double hi) {
  char* end = nullptr;
  double x = std::strtod(v.c_str(), &end);
  if (v.empty() || *end || !std::isfinite(x) || x < lo || x > hi) {
    std::ostringstream m;
    m << "bad " << flag << " '" << v << "': expected a finite number from " << lo << " to " << hi;
    bad(m.str());
  }
  return x;
}

// The switches that take on or off.
bool on_off(const std::string& flag, const std::string& v) {
  if (v != "on" && v != "off") bad("bad " + flag + " '" + v + "': expected on or off");
  return v == "on";
}

std::pair<int, int> to_size(const std::string& v) {
  size_t x = v.find('x');
  if (x == std::string::npos) bad("bad --size '" + v + "': expected WxH, such as 800x600");
  int w = int(to_int("--size width", v.substr(0, x), 1, 16384));
  int h = int(to_int("--size height", v.substr(x + 1), 2, 16384));
  return {w, h};
}

std::string num(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

// Which subcommands take a flag.
enum : unsigned { R = 1, W = 2, V = 4, RW = R | W, ALL = R | W | V };

unsigned command_bit(const std::string& c) {
  return c == "render" ? unsigned(R) : c == "walk" ? unsigned(W) : c == "view" ? unsigned(V) : 0u;
}

using arg = const std::string&;
using setter = void (*)(cli_options&, arg flag, arg value);

// One flag of one or more subcommands: how it is shown in their usage and what it sets.
// A flag whose meaning differs between subcommands has one entry for each.
struct flag_spec {
  const char* name;
  const char* value;  // the value's name in the usage; null: a switch, which takes none
  unsigned commands;
  bool names_file;    // the value is a file or folder name, which cannot be empty
  std::string help;   // the default said where there is one; usage_text wraps it
  setter set;
};

// The flags that mean the same for several subcommands but are described for each.
void set_path(cli_options& o, arg, arg v) { o.path = v; }
void set_memory(cli_options& o, arg f, arg v) { o.memory_mb = to_number(f, v, 1, 1e6); }

const std::vector<flag_spec>& flags() {
  const interp_params ip;
  static const std::vector<flag_spec> table = {
      {"--path", "FILE", R, true, "camera path (a camera a line, docs/cli.md), checked whole; renders frame --frame K",
       set_path},
      {"--path", "FILE", W, true, "camera path, required: every line is one frame, rendered in order", set_path},
      {"--path", "FILE", V, true, "camera path: the view starts at its first camera, L plays it", set_path},
      {"--frame", "K", R, false, "the path's frame to render, counted from 0 (default 0; needs --path)",
       [](cli_options& o, arg f, arg v) { o.frame = int(to_int(f, v, 0, 100000000)); }},
      {"--size", "WxH", ALL, false, "image size (default: the scene's resolution)",
       [](cli_options& o, arg, arg v) { o.size = to_size(v); }},
      {"--mode", "M", RW, false,
       "base (every pixel traced), interp (radiance interpolants), full (interpolants, "
       "reprojection and span filling), or a baseline: upsample, reuse, lightfield (default full)",
       [](cli_options& o, arg, arg m) {
         if (!parse_mode(m, o.mode))
           bad("bad --mode '" + m + "': expected base, interp or full (or a baseline: upsample, reuse, lightfield)");
       }},
      {"--eps", "E", ALL, false, "the relative error bound (default " + num(ip.eps) + "; 0 reproduces base exactly)",
       [](cli_options& o, arg f, arg v) { o.eps = float(to_number(f, v, 0, 1e6)); }},
      {"--threads", "N", ALL, false, "worker threads (default: all hardware threads); images do not depend on N",
       [](cli_options& o, arg f, arg v) { o.threads = int(to_int(f, v, 1, 1024)); }},
      {"--png", "OUT.png", R, true,
       "8-bit sRGB image (default: SCENE-STEM.png in the current folder, SCENE-STEM the "
       "scene's file name without folder and extension, when neither --png nor --pfm is given)",
       [](cli_options& o, arg, arg v) { o.png = v; }},
      {"--pfm", "OUT.pfm", R, true, "linear floating-point image (PFM, little-endian)",
       [](cli_options& o, arg, arg v) { o.pfm = v; }},
      {"--reasons", "OUT.png", R, true, "the error-coded image: why each pixel was interpolated or traced",
       [](cli_options& o, arg, arg v) { o.reasons = v; }},
      {"--out-dir", "DIR", W, true, "folder for the frames, made if absent (its parent must exist)",
       [](cli_options& o, arg, arg v) { o.out_dir = v; }},
      {"--png", nullptr, W, false, "write DIR/frame_0000.png, DIR/frame_0001.png, ... (needs --out-dir)",
       [](cli_options& o, arg, arg) { o.png_flag = true; }},
      {"--pfm", nullptr, W, false, "write DIR/frame_0000.pfm, DIR/frame_0001.pfm, ... (needs --out-dir)",
       [](cli_options& o, arg, arg) { o.pfm_flag = true; }},
      {"--stats", "OUT.json", RW, true, "statistics per frame, with what made them (docs/cli.md)",
       [](cli_options& o, arg, arg v) { o.stats = v; }},
      {"--verify", nullptr, RW, false,
       "also trace every pixel and report the error against eps (slow; images unchanged)",
       [](cli_options& o, arg, arg) { o.verify = true; }},
      {"--base-cost", nullptr, RW, false,
       "base, interp, full: also trace every pixel by base mode's code and time it by the path that served the "
       "pixel (stats: base_code_ms; slow; images unchanged)",
       [](cli_options& o, arg, arg) { o.base_cost = true; }},
      {"--quiet", nullptr, RW, false, "no summary on stdout, no progress line on stderr",
       [](cli_options& o, arg, arg) { o.quiet = true; }},
      {"--record", "FILE", V, true, "P starts and stops recording the camera path to FILE (a path walk reads)",
       [](cli_options& o, arg, arg v) { o.record = v; }},
      {"--script", "FILE", V, true,
       "drive the viewer from a text file of commands (frames N, key W N, screenshot FILE, "
       "quit, ...; README.md)",
       [](cli_options& o, arg, arg v) { o.script = v; }},
      {"--screenshot", "OUT.png", V, true, "render one refined frame, save the window to OUT.png and exit",
       [](cli_options& o, arg, arg v) { o.screenshot = v; }},
      {"--memory-mb", "M", RW, false,
       "budget for linetrees and caches, in MB: least recently used cells are evicted "
       "between frames (default: no budget)",
       set_memory},
      {"--memory-mb", "M", V, false, "budget for linetrees and caches, in MB (default 256)", set_memory},
      {"--reproject", "exact|osmesa", RW, false,
       "full: which pixels last frame's cells own, by the exact per-pixel test or drawn "
       "by OSMesa (default exact)",
       [](cli_options& o, arg, arg v) {
         if (v != "exact" && v != "osmesa") bad("bad --reproject '" + v + "': expected exact or osmesa");
         o.reproject_osmesa = v == "osmesa";
       }},
      {"--pipeline", nullptr, W, false, "full: prepare each next frame's reprojection on a thread of its own",
       [](cli_options& o, arg, arg) { o.pipeline = true; }},
      {"--keyframe", "N", W, false,
       "start afresh (new linetrees, no cells to reproject) at every frame whose index is a multiple of N "
       "(default 0: never); under mpirun, ranks' segments then start at keyframes only and every frame is "
       "the same whatever the number of ranks (docs/mpi.md)",
       [](cli_options& o, arg f, arg v) { o.keyframe = int(to_int(f, v, 0, 100000000)); }},
      {"--span", "N", ALL, false,
       "full: fill a plain cell's runs of pixels in screen space between end pixels at "
       "most N apart, the added error bounded (default " +
           std::to_string(ip.span_segment) + "; 0: every pixel evaluated)",
       [](cli_options& o, arg f, arg v) { o.span_segment = int(to_int(f, v, 0, 65536)); }},
      {"--min-cell-pixels", "P", ALL, false,
       "no linetree cell is split into children covering fewer pixels (default " + num(ip.min_cell_pixels) +
           ", " + num(ip.moving_min_cell_pixels) + " while the camera moves; given, it holds for both)",
       [](cli_options& o, arg f, arg v) { o.min_cell_pixels = float(to_number(f, v, 0, 1e9)); }},
      {"--failed-split-pixels", "P", ALL, false,
       "cells refused for a discontinuity or a miss are not split below P pixels (default " +
           num(ip.failed_split_pixels) + ", " + num(ip.moving_failed_split_pixels) +
           " while the camera moves; given, it holds for both)",
       [](cli_options& o, arg f, arg v) {
         o.failed_split_pixels = float(to_number(f, v, 0, 1e9));
       }},
      {"--defer-pixels", "P", ALL, false,
       "cells under P pixels may trace per pixel the lights and secondary rays they cannot prove (default " +
           num(ip.defer_pixels) + ", " + num(ip.moving_defer_pixels) +
           " while the camera moves; given, it holds for both)",
       [](cli_options& o, arg f, arg v) { o.defer_pixels = float(to_number(f, v, 0, 1e9)); }},
      {"--min-prim-pixels", "P", ALL, false,
       "primitives whose box covers fewer pixels are traced (default " + num(ip.min_prim_pixels) + ")",
       [](cli_options& o, arg f, arg v) { o.min_prim_pixels = float(to_number(f, v, 0, 1e9)); }},
      {"--object-gate", "on|off", ALL, false,
       std::string("full: trace, with no linetree, objects whose cells cost more than they saved in the last "
                   "frame by the counts of rays and pixels (default ") + (ip.object_gate ? "on" : "off") + ")",
       [](cli_options& o, arg f, arg v) { o.object_gate = on_off(f, v); }},
      {"--plain-frames", "on|off", ALL, false,
       std::string("full, with the object gate: trace whole frames plainly, for 8 frames and more, after a frame whose "
                   "cells saved under a fifth of a plain frame's rays (default ") +
           (ip.plain_frames ? "on" : "off") + ")",
       [](cli_options& o, arg f, arg v) { o.plain_frames = on_off(f, v); }},
      {"--mirror", "on|off", ALL, false,
       std::string("full: a planar reflector's reflections through the mirrored eye, from reprojected cells (default ") +
           (ip.mirror ? "on" : "off") + ")",
       [](cli_options& o, arg f, arg v) { o.mirror = on_off(f, v); }},
      {"--light-cache", "on|off", ALL, false,
       std::string("interp and full: test shadow rays against per-light lists of what may block them, kept for "
                   "the whole walk; images are the same either way (default ") +
           (ip.light_cache ? "on" : "off") + ")",
       [](cli_options& o, arg f, arg v) { o.light_cache = on_off(f, v); }},
      {"--split", "4|16", ALL, false,
       std::string("split a refused cell along the axes the failure points at (4) or always all four (16) (default ") +
           (ip.four_way ? "4" : "16") + ")",
       [](cli_options& o, arg, arg v) {
         if (v != "4" && v != "16") bad("bad --split '" + v + "': expected 4 or 16");
         o.four_way = v == "4";
       }},
      {"--tile-rows", "N", ALL, false, "image rows per tile (default: about 8 tiles per thread, 1 to 16 rows)",
       [](cli_options& o, arg f, arg v) { o.tile_rows = int(to_int(f, v, 1, 16384)); }},
      {"--tile-order", "cost|scan", ALL, false,
       "tiles handed to threads dearest first by last frame's costs, or top to bottom (default cost)",
       [](cli_options& o, arg, arg v) {
         if (v != "cost" && v != "scan") bad("bad --tile-order '" + v + "': expected cost or scan");
         o.order = v == "cost" ? tile_order::costly_first : tile_order::scan;
       }},
      {"--pin", nullptr, RW, false, "bind each worker thread to its own core (hwloc)",
       [](cli_options& o, arg, arg) { o.pin = true; }},
      {"--upsample", "K", RW, false, "upsample baseline: trace every K-th pixel each way, bilinear (default 2)",
       [](cli_options& o, arg f, arg v) { o.upsample = int(to_int(f, v, 1, 64)); }},
      {"--reuse-age", "N", RW, false,
       "reuse baseline: frames a pixel's radiance may be carried before it is traced again (default 4)",
       [](cli_options& o, arg f, arg v) { o.reuse_age = int(to_int(f, v, 0, 60000)); }},
      {"--lf-depth", "D", RW, false, "lightfield baseline: halvings of every axis of each linetree (default 4)",
       [](cli_options& o, arg f, arg v) { o.lf_depth = int(to_int(f, v, 0, 16)); }},
  };
  return table;
}

const flag_spec* find_flag(const std::string& name, unsigned command) {
  for (const flag_spec& f : flags())
    if (name == f.name && (f.commands & command)) return &f;
  return nullptr;
}

const char* synopsis(const std::string& c) {
  if (c == "render")
    return "usage: epsray render SCENE [--path FILE [--frame K]] [--size WxH] [--mode M] [--eps E]\n"
           "                     [--threads N] [--png OUT.png] [--pfm OUT.pfm] [--stats OUT.json] [options]\n"
           "Renders one frame of SCENE (an NFF file), from the scene's own view or a path's camera.\n";
  if (c == "walk")
    return "usage: epsray walk SCENE --path FILE [--size WxH] [--mode M] [--eps E] [--threads N]\n"
           "                   [--out-dir DIR] [--png] [--pfm] [--stats OUT.json] [--verify] [options]\n"
           "Renders every camera of the path in order, keeping what it learned between frames.\n"
           "SIGINT or SIGTERM stops it after the frame in hand: the frames done and their stats\n"
           "are kept (\"interrupted\": true), and it exits 130 or 143.\n"
           "Under mpirun -np K, K ranks render contiguous segments of the path (docs/mpi.md).\n";
  if (c == "view")
    return "usage: epsray view [SCENE] [--path FILE] [--size WxH] [--eps E] [--threads N] [options]\n"
           "Opens a window on SCENE (default: the art room) and renders while you move.\n";
  return "usage: epsray info\n"
         "Prints the version, the hardware threads and the machine's topology as hwloc sees it.\n";
}

}  // namespace

std::string quote_file(const std::string& name) {
  const std::string p = printable_name(name);
  return p == name ? "'" + name + "'" : p;
}

std::string usage_text() {
  return "usage: epsray render SCENE [--path FILE --frame K] [--size WxH] [--mode base|interp|full]\n"
         "                      [--eps E] [--threads N] [--png OUT.png] [--pfm OUT.pfm] [--stats OUT.json]\n"
         "       epsray walk   SCENE --path FILE [--size WxH] [--mode M] [--eps E] [--threads N]\n"
         "                      [--out-dir DIR] [--png] [--pfm] [--stats OUT.json] [--verify]\n"
         "       epsray view   [SCENE] [--path FILE] [--size WxH] [--eps E] [--threads N]\n"
         "                      [--record FILE] [--script FILE] [--screenshot OUT.png] [--memory-mb M]\n"
         "       epsray info\n"
         "       epsray --version\n"
         "'epsray SUBCOMMAND --help' lists that subcommand's flags with their defaults; a flag's\n"
         "value may follow it (--eps 0.1) or be joined to it (--eps=0.1). docs/cli.md says more.\n"
         "exit codes: 0 done, 1 failed (nothing written), 2 bad input (one line on stderr,\n"
         "nothing written), 130 / 143 interrupted by SIGINT / SIGTERM.\n";
}

std::string usage_text(const std::string& command) {
  const unsigned bit = command_bit(command);
  if (!bit && command != "info") return usage_text();
  std::string out = synopsis(command);
  if (!bit) return out;
  out += "\noptions:\n";
  // Each flag's help starts at one column and is wrapped to 100 characters.
  constexpr size_t column = 26, width = 100;
  auto line = [&](const std::string& flag, const std::string& help) {
    std::string text = "  " + flag;
    text += text.size() < column ? std::string(column - text.size(), ' ') : "\n" + std::string(column, ' ');
    size_t used = column;
    std::istringstream words(help);
    std::string word;
    for (bool first = true; words >> word; first = false) {
      if (!first && used + 1 + word.size() > width) text += "\n" + std::string(column, ' '), used = column;
      else if (!first) text += ' ', ++used;
      text += word, used += word.size();
    }
    out += text + "\n";
  };
  for (const flag_spec& f : flags())
    if (f.commands & bit) line(std::string(f.name) + (f.value ? std::string(" ") + f.value : ""), f.help);
  line("--help, -h", "this text");
  return out;
}

cli_options parse_args(const std::vector<std::string>& a) {
  cli_options o;
  o.command_line.push_back("epsray");
  o.command_line.insert(o.command_line.end(), a.begin(), a.end());
  if (a.empty()) bad("no command given (render, walk, view or info); try 'epsray --help'");
  o.command = a[0];
  if (o.command != "render" && o.command != "walk" && o.command != "view" && o.command != "info")
    bad("unknown command '" + o.command + "' (render, walk, view or info)");
  // Help wins over any other argument, right or wrong.
  for (size_t i = 1; i < a.size(); ++i)
    if (a[i] == "--help" || a[i] == "-h") {
      o.help = true;
      return o;
    }
  const unsigned bit = command_bit(o.command);
  for (size_t i = 1; i < a.size(); ++i) {
    const std::string& given = a[i];
    if (given.rfind("--", 0) != 0) {
      if (!o.scene.empty() || o.command == "info") bad("unexpected argument " + quote_file(given));
      if (given.empty()) bad("bad SCENE '': a file name cannot be empty");
      o.scene = given;
      continue;
    }
    // --flag=value is --flag value.
    const size_t eq = given.find('=');
    const std::string name = given.substr(0, eq);
    const flag_spec* f = find_flag(name, bit);
    if (!f) {
      if (name == "--frame") bad("--frame is for render only (" + o.command + " takes no single frame)");
      bad("unknown option '" + name + "' for " + o.command);
    }
    std::string value;
    if (!f->value) {
      if (eq != std::string::npos) bad(name + " takes no value");
    } else if (eq != std::string::npos) {
      value = given.substr(eq + 1);
    } else {
      if (i + 1 >= a.size()) bad(name + " needs a value");
      value = a[++i];
    }
    if (f->names_file && value.empty()) bad("bad " + name + " '': a file name cannot be empty");
    f->set(o, name, value);
  }
  // view's default scene is the art room.
  if (o.command != "info" && o.command != "view" && o.scene.empty()) bad(o.command + " needs a SCENE file");
  if (o.frame && o.path.empty()) bad("--frame needs --path");
  if (o.command == "walk" && o.path.empty()) bad("walk needs --path FILE");
  if (!o.script.empty() && !o.screenshot.empty())
    bad("--screenshot and --script do not combine; use the script's screenshot command");
  if (o.base_cost && (o.mode == render_mode::upsample || o.mode == render_mode::reuse))
    bad("--base-cost is for modes base, interp and full (and lightfield), not " + std::string(mode_name(o.mode)));
  if (o.command == "walk" && (o.png_flag || o.pfm_flag) && o.out_dir.empty())
    bad("--png/--pfm with walk need --out-dir DIR");
  // POV-Ray's convention: a render always leaves an image, named after the scene.
  if (o.command == "render" && o.png.empty() && o.pfm.empty())
    o.png = std::filesystem::path(o.scene).stem().string() + ".png";
  return o;
}

}  // namespace epsray
