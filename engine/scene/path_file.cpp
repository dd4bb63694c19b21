#include "scene/path_file.h"

#include "scene/camera.h"
#include "scene/line_reader.h"

namespace epsray {

camera_path parse_camera_path(std::string_view text, const std::string& name) {
  line_reader in(text, name);
  camera_path out;
  out.file = name;
  text_line l;
  while (in.next(l)) {
    if (l.words.size() != 10) {
      in.fail(l.number, "camera needs 10 numbers (from, at, up, angle), got " + std::to_string(l.words.size()));
    }
    camera_view v;
    v.from = {in.number(l, 0, "from"), in.number(l, 1, "from"), in.number(l, 2, "from")};
    v.at = {in.number(l, 3, "at"), in.number(l, 4, "at"), in.number(l, 5, "at")};
    v.up = {in.number(l, 6, "up"), in.number(l, 7, "up"), in.number(l, 8, "up")};
    v.angle = in.number(l, 9, "angle");
    if (!(v.angle > 0 && v.angle < 180)) in.fail(l.number, "angle must be between 0 and 180 degrees");
    if (const char* problem = view_problem(v)) in.fail(l.number, problem);
    out.frames.push_back(v);
  }
  if (out.frames.empty()) in.fail(in.last_line() ? in.last_line() : 1, "camera path has no frames");
  return out;
}

camera_path load_camera_path(const std::string& path) { return parse_camera_path(read_text_file(path), path); }

}  // namespace epsray
