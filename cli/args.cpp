#include "args.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

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

std::pair<int, int> to_size(const std::string& v) {
  size_t x = v.find('x');
  if (x == std::string::npos) bad("bad --size '" + v + "': expected WxH, such as 800x600");
  int w = int(to_int("--size width", v.substr(0, x), 1, 16384));
  int h = int(to_int("--size height", v.substr(x + 1), 2, 16384));
  return {w, h};
}

}  // namespace

std::string usage_text() {
  return "usage: epsray render SCENE [--path FILE --frame K] [--size WxH] [--mode base|interp|full]\n"
         "                      [--eps E] [--threads N] [--png OUT.png] [--pfm OUT.pfm] [--stats OUT.json]\n"
         "       epsray walk   SCENE --path FILE [--size WxH] [--mode M] [--eps E] [--threads N]\n"
         "                      [--out-dir DIR] [--png] [--pfm] [--stats OUT.json] [--verify]\n"
         "       epsray view   [SCENE] [--path FILE] [--size WxH] [--eps E] [--threads N]\n"
         "                      [--record FILE] [--script FILE] [--screenshot OUT.png] [--memory-mb M]\n"
         "       epsray info\n"
         "extra: --tile-rows N (rows per tile), --tile-order cost|scan (dearest tiles first, by\n"
         "       last frame's costs; or top to bottom), --quiet (no summary on stdout),\n"
         "       --reasons OUT.png (render: the error-coded image), --verify (render too),\n"
         "       --min-cell-pixels P (no linetree cell is split into children covering fewer pixels;\n"
         "       default 16, and 32 while the camera moves: walk frames whose camera differs from the\n"
         "       last, the viewer in motion),\n"
         "       --min-prim-pixels P (primitives whose box covers fewer pixels are traced; default 1024),\n"
         "       --split 4|16 (halve the axes a failure points at, or always all four),\n"
         "       --span N (full: a plain cell's runs of pixels are filled in screen space between end\n"
         "       pixels at most N apart, the added error bounded; default 32, 0: every pixel evaluated),\n"
         "       --reproject exact|osmesa (full, render and walk: which pixels last frame's cells own,\n"
         "       by the exact per-pixel test (default) or drawn by OSMesa), --pipeline (walk, full:\n"
         "       each next frame's reprojection prepared on a thread of its own meanwhile),\n"
         "       --defer-pixels P (cells under P pixels may trace the lights and secondary rays they\n"
         "       cannot prove per pixel; default 256, and 1024 while the camera moves),\n"
         "       --failed-split-pixels P (cells refused for a discontinuity or a miss are not split\n"
         "       below P pixels; default 0, and 128 while the camera moves); each of these three,\n"
         "       given, holds whether the camera moves or not,\n"
         "       --pin (bind each worker thread to its own core, through hwloc),\n"
         "       --memory-mb M (linetrees and caches: evict least recently used cells between frames;\n"
         "       render and walk: no budget unless given, view: 256)\n"
         "baselines (perf/): --mode upsample [--upsample K] (trace every K-th pixel each way, bilinear),\n"
         "       --mode reuse [--reuse-age N] (last frame's pixels reprojected, no error control),\n"
         "       --mode lightfield [--lf-depth D] (fixed-depth linetrees, no error predicate)\n";
}

cli_options parse_args(const std::vector<std::string>& a) {
  cli_options o;
  if (a.empty()) bad("no command given (render, walk, view or info); try 'epsray --help'");
  o.command = a[0];
  if (o.command != "render" && o.command != "walk" && o.command != "view" && o.command != "info")
    bad("unknown command '" + o.command + "' (render, walk, view or info)");
  const bool walk = o.command == "walk";
  const bool view = o.command == "view";
  for (size_t i = 1; i < a.size(); ++i) {
    const std::string& f = a[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= a.size()) bad(f + " needs a value");
      return a[++i];
    };
    // The viewer always renders in full mode and writes only what its own flags name.
    if (view && (f == "--mode" || f == "--frame" || f == "--png" || f == "--pfm" || f == "--stats" ||
                 f == "--verify" || f == "--reasons" || f == "--quiet" || f == "--pin"))
      bad("unknown option '" + f + "' for view");
    if (f.rfind("--", 0) != 0) {
      if (!o.scene.empty() || o.command == "info") bad("unexpected argument '" + f + "'");
      o.scene = f;
    } else if (f == "--path") o.path = value();
    else if (f == "--frame") o.frame = int(to_int("--frame", value(), 0, 100000000));
    else if (f == "--size") o.size = to_size(value());
    else if (f == "--mode") {
      const std::string& m = value();
      if (!parse_mode(m, o.mode))
        bad("bad --mode '" + m + "': expected base, interp or full (or a baseline: upsample, reuse, lightfield)");
    } else if (f == "--eps") o.eps = float(to_number("--eps", value(), 0, 1e6));
    else if (f == "--threads") o.threads = int(to_int("--threads", value(), 1, 1024));
    else if (f == "--tile-rows") o.tile_rows = int(to_int("--tile-rows", value(), 1, 16384));
    else if (f == "--tile-order") {
      const std::string& v = value();
      if (v != "cost" && v != "scan") bad("bad --tile-order '" + v + "': expected cost or scan");
      o.order = v == "cost" ? tile_order::costly_first : tile_order::scan;
    }
    else if (f == "--png") {
      if (walk) o.png_flag = true;
      else o.png = value();
    } else if (f == "--pfm") {
      if (walk) o.pfm_flag = true;
      else o.pfm = value();
    } else if (f == "--stats") o.stats = value();
    else if (f == "--out-dir" && walk) o.out_dir = value();
    else if (f == "--record" && view) o.record = value();
    else if (f == "--script" && view) o.script = value();
    else if (f == "--screenshot" && view) o.screenshot = value();
    else if (f == "--verify") o.verify = true;
    else if (f == "--reasons" && !walk) o.reasons = value();
    else if (f == "--min-cell-pixels") o.min_cell_pixels = float(to_number("--min-cell-pixels", value(), 0, 1e9));
    else if (f == "--min-prim-pixels") o.min_prim_pixels = float(to_number("--min-prim-pixels", value(), 0, 1e9));
    else if (f == "--failed-split-pixels")
      o.failed_split_pixels = float(to_number("--failed-split-pixels", value(), 0, 1e9));
    else if (f == "--defer-pixels")
      o.defer_pixels = float(to_number("--defer-pixels", value(), 0, 1e9));
    else if (f == "--span") o.span_segment = int(to_int("--span", value(), 0, 65536));
    else if (f == "--split") {
      const std::string& v = value();
      if (v != "4" && v != "16") bad("bad --split '" + v + "': expected 4 or 16");
      o.four_way = v == "4";
    } else if (f == "--reproject" && !view) {
      const std::string& v = value();
      if (v != "exact" && v != "osmesa") bad("bad --reproject '" + v + "': expected exact or osmesa");
      o.reproject_osmesa = v == "osmesa";
    } else if (f == "--pipeline" && walk) o.pipeline = true;
    else if (f == "--quiet") o.quiet = true;
    else if (f == "--pin") o.pin = true;
    else if (f == "--memory-mb") o.memory_mb = to_number("--memory-mb", value(), 1, 1e6);
    else if (f == "--upsample" && !view) o.upsample = int(to_int("--upsample", value(), 1, 64));
    else if (f == "--reuse-age" && !view) o.reuse_age = int(to_int("--reuse-age", value(), 0, 60000));
    else if (f == "--lf-depth" && !view) o.lf_depth = int(to_int("--lf-depth", value(), 0, 16));
    else bad("unknown option '" + f + "' for " + o.command);
  }
  if (o.command != "info" && !view && o.scene.empty()) bad(o.command + " needs a SCENE file");  // view: the art room
  if (o.frame && o.path.empty()) bad("--frame needs --path");
  if (walk && o.path.empty()) bad("walk needs --path FILE");
  if (!o.script.empty() && !o.screenshot.empty())
    bad("--screenshot and --script do not combine; use the script's screenshot command");
  if (walk && (o.png_flag || o.pfm_flag) && o.out_dir.empty()) bad("--png/--pfm with walk need --out-dir DIR");
  return o;
}

}  // namespace epsray
