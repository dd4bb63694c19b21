#include "scene/nff.h"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "scene/camera.h"
#include "scene/line_reader.h"

namespace epsray {

namespace {

// Rigid motion plus uniform scale: keeps spheres spheres and boxes boxes, which is all
// the analytic primitives allow (no ellipsoids).
struct xform {
  glm::mat3 rot{1.0f};
  vec3 offset{0.0f};
  float scale = 1;
  vec3 point(vec3 p) const { return rot * (p * scale) + offset; }
  vec3 dir(vec3 d) const { return rot * d; }
};

struct parser {
  line_reader in;
  std::string base_dir;
  scene s;
  material current;  // NFF: the material before any `f`
  std::vector<xform> stack{xform{}};
  int view_line = 0;
  bool saw_from = false, saw_at = false, saw_up = false, saw_angle = false, saw_res = false;

  parser(std::string_view text, const std::string& name, std::string dir)
      : in(text, name), base_dir(std::move(dir)) {}

  [[noreturn]] void fail(const text_line& l, const std::string& m) const { in.fail(l.number, m); }
  float num(const text_line& l, size_t i, const char* what) const { return in.number(l, i, what); }
  vec3 vec(const text_line& l, size_t i, const char* what) const {
    return {num(l, i, what), num(l, i + 1, what), num(l, i + 2, what)};
  }
  const xform& top() const { return stack.back(); }

  // Upper bounds keep the radiance finite (docs/fuzzing.md): a pixel multiplies a light by
  // Kd, C and a checker colour, then by Ks or T at each of 4 bounces. With these bounds one
  // light contributes below 1e29: it would take billions of lights to reach FLT_MAX.
  static constexpr float max_intensity = 1e6f;  // light colours, ambient, background
  static constexpr float max_factor = 1e3f;     // material and checker colours, Kd, Ks, T

  void check_colour(const text_line& l, vec3 c, const char* what, float max = max_intensity) const {
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(l, std::string(what) + " must be non-negative");
    if (c.x > max || c.y > max || c.z > max) fail(l, std::string(what) + " must be at most " + std::to_string(long(max)));
  }
  void check_factor(const text_line& l, float k, const char* what) const {
    if (k < 0) fail(l, std::string(what) + " must be non-negative");
    if (k > max_factor) fail(l, std::string(what) + " must be at most " + std::to_string(long(max_factor)));
  }

  int material_index() {
    // Share materials between consecutive primitives; a new `f` or texture starts another.
    if (s.materials.empty()) s.materials.push_back(current);
    return int(s.materials.size()) - 1;
  }
  void set_material(const material& m) {
    current = m;
    s.materials.push_back(current);
  }

  void add(primitive p, const text_line& l) {
    p.material = material_index();
    p.line = l.number;
    s.prims.push_back(p);
  }

  void parse_material(const text_line& l) {
    in.expect_count(l, 8, "material (f)");
    material m = current;
    m.color = vec(l, 1, "material colour");
    check_colour(l, m.color, "material colour", max_factor);
    m.kd = num(l, 4, "Kd");
    m.ks = num(l, 5, "Ks");
    m.shine = num(l, 6, "Shine");
    m.t = num(l, 7, "T");
    m.ior = num(l, 8, "ior");
    check_factor(l, m.kd, "Kd");
    check_factor(l, m.ks, "Ks");
    check_factor(l, m.t, "T");
    if (m.t > 0 && m.ior <= 0) fail(l, "ior must be positive when T > 0");
    set_material(m);
  }

  void parse_sphere(const text_line& l) {
    in.expect_count(l, 4, "sphere");
    primitive p;
    p.kind = prim_kind::sphere;
    p.a = top().point(vec(l, 1, "sphere centre"));
    p.r0 = num(l, 4, "sphere radius") * top().scale;
    if (p.r0 == 0) fail(l, "sphere radius is zero");
    add(p, l);
  }

  primitive cone_from(const text_line& l, const char* what) {
    in.expect_count(l, 8, what);
    primitive p;
    p.kind = prim_kind::cone;
    vec3 base = vec(l, 1, "cone base"), apex = vec(l, 5, "cone apex");
    float r0 = num(l, 4, "cone base radius"), r1 = num(l, 8, "cone apex radius");
    if (r0 == 0 && r1 == 0) fail(l, "both cone radii are zero");
    if ((r0 < 0 && r1 > 0) || (r0 > 0 && r1 < 0)) fail(l, "cone radii have opposite signs");
    float len = glm::length(apex - base);
    float size = std::max({std::fabs(r0), std::fabs(r1), glm::length(base), glm::length(apex), 1e-30f});
    if (!(len > 1e-6f * size)) fail(l, "cone ends coincide");
    p.a = top().point(base);
    p.b = top().point(apex);
    p.r0 = r0 * top().scale;
    p.r1 = r1 * top().scale;
    return p;
  }

  void add_disk(const text_line& l, vec3 centre, vec3 normal, float radius) {
    primitive d;
    d.kind = prim_kind::disk;
    d.a = centre;
    d.b = glm::normalize(normal);
    d.r0 = radius;
    add(d, l);
  }

  void parse_polygon(const text_line& header, bool patch) {
    const char* what = patch ? "patch (pp)" : "polygon (p)";
    in.expect_count(header, 1, what);
    long n = in.integer(header, 1, patch ? "patch vertex count" : "polygon vertex count", 3, 1000000);
    primitive p;
    p.kind = patch ? prim_kind::patch : prim_kind::polygon;
    p.first = int(s.vertices.size());
    p.count = int(n);
    text_line l;
    for (long i = 0; i < n; ++i) {
      if (!in.next(l)) {
        std::ostringstream m;
        m << what << " ends early: expected " << n << " vertices, got " << i;
        in.fail(in.last_line() ? in.last_line() : header.number, m.str());
      }
      size_t want = patch ? 6 : 3;
      if (l.words.size() != want) {
        std::ostringstream m;
        m << (patch ? "patch vertex needs 6 numbers (point, normal), got " : "polygon vertex needs 3 numbers, got ")
          << l.words.size();
        if (!l.words.empty() && !looks_number(l.words[0])) m << " ('" << l.words[0] << "' is not a number)";
        fail(l, m.str());
      }
      s.vertices.push_back(top().point(vec(l, 0, "vertex")));
      if (patch) {
        vec3 nrm = vec(l, 3, "vertex normal");
        if (nrm == vec3(0)) fail(l, "patch vertex normal is zero");
        s.normals.push_back(glm::normalize(top().dir(nrm)));
      }
    }
    check_polygon(header, p);
    if (!patch) s.normals.resize(s.vertices.size(), vec3(0));
    add(p, header);
  }

  static bool looks_number(std::string_view w) {
    return !w.empty() && (std::isdigit(static_cast<unsigned char>(w[0])) || w[0] == '-' || w[0] == '+' || w[0] == '.');
  }

  // whitted.md 2: the normal comes from the first two edges; every vertex lies in that plane.
  void check_polygon(const text_line& l, const primitive& p) const {
    const vec3* v = &s.vertices[size_t(p.first)];
    vec3 lo = v[0], hi = v[0];
    for (int i = 1; i < p.count; ++i) lo = glm::min(lo, v[i]), hi = glm::max(hi, v[i]);
    double extent = glm::length(glm::dvec3(hi - lo));
    glm::dvec3 e0 = glm::dvec3(v[1]) - glm::dvec3(v[0]), e1 = glm::dvec3(v[2]) - glm::dvec3(v[1]);
    glm::dvec3 n = glm::cross(e0, e1);
    double nl = glm::length(n);
    if (!(extent > 0) || !(nl > 1e-12 * extent * extent))
      fail(l, "degenerate polygon: its first two edges are zero or collinear");
    n /= nl;
    for (int i = 0; i < p.count; ++i) {
      double d = std::fabs(glm::dot(n, glm::dvec3(v[i]) - glm::dvec3(v[0])));
      if (d > 1e-3 * extent) {
        std::ostringstream m;
        m << "polygon is not planar: vertex " << i << " is " << d << " from the plane of the first edges";
        fail(l, m.str());
      }
    }
  }

  void parse_box(const text_line& l) {
    in.expect_count(l, 6, "box");
    vec3 lo = vec(l, 1, "box corner"), hi = vec(l, 4, "box corner");
    vec3 size = glm::abs(hi - lo);
    if (!(size.x > 0 && size.y > 0 && size.z > 0)) fail(l, "box has zero size along an axis");
    primitive p;
    p.kind = prim_kind::box;
    p.a = top().point((lo + hi) * 0.5f);
    p.b = size * 0.5f * top().scale;
    p.frame = top().rot;
    add(p, l);
  }

  void parse_disk(const text_line& l) {
    in.expect_count(l, 7, "disk");
    vec3 c = vec(l, 1, "disk centre"), n = vec(l, 4, "disk normal");
    float r = num(l, 7, "disk radius");
    if (n == vec3(0)) fail(l, "disk normal is zero");
    if (!(r > 0)) fail(l, "disk radius must be positive");
    add_disk(l, top().point(c), top().dir(n), r * top().scale);
  }

  void parse_capped_cone(const text_line& l) {
    primitive c = cone_from(l, "capped cone (cc)");
    if (c.r0 < 0 || c.r1 < 0) fail(l, "capped cone radii must be non-negative");
    add(c, l);
    vec3 axis = c.b - c.a;
    if (c.r0 > 0) add_disk(l, c.a, -axis, c.r0);
    if (c.r1 > 0) add_disk(l, c.b, axis, c.r1);
  }

  void parse_light(const text_line& l) {
    size_t n = l.words.size() - 1;
    if (n != 3 && n != 6) {
      std::ostringstream m;
      m << "light (l) needs 3 or 6 numbers, got " << n;
      fail(l, m.str());
    }
    light li;
    li.position = top().point(vec(l, 1, "light position"));
    if (n == 6) {
      li.color = vec(l, 4, "light colour");
      check_colour(l, li.color, "light colour");
      li.has_color = true;
    }
    s.lights.push_back(li);
  }

  void parse_texture(const text_line& l) {
    if (l.words.size() < 2) fail(l, "texture needs a kind: checker, image or none");
    std::string_view kind = l.words[1];
    material m = current;
    if (kind == "none") {
      if (l.words.size() != 2) fail(l, "texture none takes no numbers");
      m.texture = -1;
      set_material(m);
      return;
    }
    texture t;
    if (kind == "checker") {
      if (l.words.size() != 10) {
        std::ostringstream msg;
        msg << "texture checker needs 8 numbers (two colours, two scales), got " << l.words.size() - 2;
        fail(l, msg.str());
      }
      t.kind = texture_kind::checker;
      t.color_a = vec(l, 2, "checker colour");
      t.color_b = vec(l, 5, "checker colour");
      check_colour(l, t.color_a, "checker colour", max_factor);
      check_colour(l, t.color_b, "checker colour", max_factor);
      t.scale = {num(l, 8, "texture scale"), num(l, 9, "texture scale")};
    } else if (kind == "image") {
      if (l.words.size() != 5) {
        std::ostringstream msg;
        msg << "texture image needs a file and two scales, got " << l.words.size() - 2 << " words";
        fail(l, msg.str());
      }
      t.kind = texture_kind::image;
      t.file = std::string(l.words[2]);
      t.scale = {num(l, 3, "texture scale"), num(l, 4, "texture scale")};
      load_image(l, t);
    } else {
      fail(l, "unknown texture kind '" + std::string(kind) + "' (checker, image or none)");
    }
    if (!(t.scale.x > 0 && t.scale.y > 0)) fail(l, "texture scales must be positive");
    s.textures.push_back(std::move(t));
    m.texture = int(s.textures.size()) - 1;
    set_material(m);
  }

  void load_image(const text_line& l, texture& t) {
    std::filesystem::path p(t.file);
    if (p.is_relative() && !base_dir.empty()) p = std::filesystem::path(base_dir) / p;
    int w = 0, h = 0, comp = 0;
    unsigned char* data = stbi_load(p.string().c_str(), &w, &h, &comp, 3);
    if (!data) fail(l, "texture file '" + t.file + "' cannot be read: " + stbi_failure_reason());
    t.width = w;
    t.height = h;
    t.texels.resize(size_t(w) * size_t(h));
    auto to_linear = [](unsigned char c) {
      float x = c / 255.0f;
      return x <= 0.04045f ? x / 12.92f : std::pow((x + 0.055f) / 1.055f, 2.4f);
    };
    for (size_t i = 0; i < t.texels.size(); ++i)
      t.texels[i] = {to_linear(data[3 * i]), to_linear(data[3 * i + 1]), to_linear(data[3 * i + 2])};
    stbi_image_free(data);
  }

  void parse_transform(const text_line& l, std::string_view key) {
    if (key == "push") {
      in.expect_count(l, 0, "push");
      if (stack.size() > 64) fail(l, "transforms nested deeper than 64");
      stack.push_back(top());
    } else if (key == "pop") {
      in.expect_count(l, 0, "pop");
      if (stack.size() == 1) fail(l, "pop without a matching push");
      stack.pop_back();
    } else if (key == "translate") {
      in.expect_count(l, 3, "translate");
      stack.back().offset = top().point(vec(l, 1, "translation"));
    } else if (key == "rotate") {
      in.expect_count(l, 4, "rotate");
      vec3 axis = vec(l, 1, "rotation axis");
      float deg = num(l, 4, "rotation angle");
      if (axis == vec3(0)) fail(l, "rotation axis is zero");
      glm::mat3 r = rotation(glm::normalize(axis), glm::radians(deg));
      stack.back().rot = top().rot * r;
    } else {  // scale
      in.expect_count(l, 1, "scale");
      float k = num(l, 1, "scale");
      if (!(k > 0)) fail(l, "scale must be positive (only uniform scaling keeps primitives analytic)");
      stack.back().scale *= k;
    }
  }

  static glm::mat3 rotation(vec3 a, float rad) {
    float c = std::cos(rad), s = std::sin(rad), t = 1 - c;
    // Rodrigues' formula, column-major for GLM.
    return glm::mat3(t * a.x * a.x + c, t * a.x * a.y + s * a.z, t * a.x * a.z - s * a.y,
                     t * a.x * a.y - s * a.z, t * a.y * a.y + c, t * a.y * a.z + s * a.x,
                     t * a.x * a.z + s * a.y, t * a.y * a.z - s * a.x, t * a.z * a.z + c);
  }

  void parse_view_line(const text_line& l, std::string_view key) {
    camera_view& v = s.view;
    if (key == "from") in.expect_count(l, 3, "from"), v.from = vec(l, 1, "from"), saw_from = true;
    else if (key == "at") in.expect_count(l, 3, "at"), v.at = vec(l, 1, "at"), saw_at = true;
    else if (key == "up") in.expect_count(l, 3, "up"), v.up = vec(l, 1, "up"), saw_up = true;
    else if (key == "angle") {
      in.expect_count(l, 1, "angle");
      v.angle = num(l, 1, "angle");
      if (!(v.angle > 0 && v.angle < 180)) fail(l, "angle must be between 0 and 180 degrees");
      saw_angle = true;
    } else if (key == "hither") {
      in.expect_count(l, 1, "hither");
      num(l, 1, "hither");  // checked, then ignored (whitted.md 1)
    } else {  // resolution
      in.expect_count(l, 2, "resolution");
      v.width = int(in.integer(l, 1, "resolution width", 1, 16384));
      v.height = int(in.integer(l, 2, "resolution height", 2, 16384));
      saw_res = true;
    }
    if (view_line == 0) view_line = l.number;
  }

  void finish() {
    int end = in.last_line() ? in.last_line() : 1;
    if (in.last_line() == 0) in.fail(1, "empty scene file");
    if (s.prims.empty()) in.fail(end, "scene has no primitives");
    if (!(saw_from && saw_at && saw_up && saw_angle && saw_res)) {
      std::string missing;
      if (!saw_from) missing += " from";
      if (!saw_at) missing += " at";
      if (!saw_up) missing += " up";
      if (!saw_angle) missing += " angle";
      if (!saw_res) missing += " resolution";
      in.fail(view_line ? view_line : end, "viewpoint is missing:" + missing);
    }
    if (const char* problem = view_problem(s.view)) in.fail(view_line, std::string("viewpoint: ") + problem);
    if (s.materials.empty()) s.materials.push_back(current);
    s.has_view = true;
  }

  void run() {
    text_line l;
    while (in.next(l)) {
      std::string_view key = l.words[0];
      if (key == "v") in.expect_count(l, 0, "v"), view_line = l.number;
      else if (key == "from" || key == "at" || key == "up" || key == "angle" || key == "hither" || key == "resolution")
        parse_view_line(l, key);
      else if (key == "b") {
        in.expect_count(l, 3, "background (b)");
        s.background = vec(l, 1, "background colour");
        check_colour(l, s.background, "background colour");
      } else if (key == "l") parse_light(l);
      else if (key == "f") parse_material(l);
      else if (key == "s") parse_sphere(l);
      else if (key == "c") { primitive c = cone_from(l, "cone (c)"); add(c, l); }
      else if (key == "p") parse_polygon(l, false);
      else if (key == "pp") parse_polygon(l, true);
      else if (key == "box") parse_box(l);
      else if (key == "disk") parse_disk(l);
      else if (key == "cc") parse_capped_cone(l);
      else if (key == "texture") parse_texture(l);
      else if (key == "ambient") {
        in.expect_count(l, 3, "ambient");
        s.ambient = vec(l, 1, "ambient colour");
        check_colour(l, s.ambient, "ambient colour");
        s.has_ambient = true;
      } else if (key == "push" || key == "pop" || key == "translate" || key == "rotate" || key == "scale")
        parse_transform(l, key);
      else fail(l, "unknown entity '" + std::string(key) + "'");
    }
    finish();
  }
};

}  // namespace

scene parse_scene(std::string_view text, const std::string& name, const std::string& base_dir) {
  parser p(text, name, base_dir);
  p.s.file = name;
  p.run();
  return std::move(p.s);
}

scene load_scene(const std::string& path) {
  std::string text = read_text_file(path);
  return parse_scene(text, path, std::filesystem::path(path).parent_path().string());
}

}  // namespace epsray
