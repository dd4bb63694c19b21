#include "scene/nff.h"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <sstream>

#include "scene/camera.h"
#include "scene/line_reader.h"
#include "scene/token_reader.h"

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

// The entities' keywords: in a token stream, where one entity's numbers end is where the
// next keyword (or the end of the file) stands.
bool is_keyword(std::string_view w) {
  static const char* const words[] = {"v", "from", "at", "up", "angle", "hither", "resolution", "b", "l", "f",
                                      "s", "c", "p", "pp", "box", "disk", "cc", "texture", "ambient", "push",
                                      "pop", "translate", "rotate", "scale"};
  for (const char* k : words)
    if (w == k) return true;
  return false;
}

constexpr float float_max = std::numeric_limits<float>::max();

bool finite3(vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// An axis of any finite length as a unit vector. Where its squared length leaves float's
// range it is scaled by its largest component first, so (1e-30, 0, 0) is the x axis
// rather than 0/0.
vec3 unit_axis(vec3 a) {
  float l2 = glm::dot(a, a);
  if (std::isnormal(l2) && l2 < float_max) return glm::normalize(a);
  float m = std::max({std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)});
  return glm::normalize(a / m);
}

struct parser {
  token_reader in;
  std::string base_dir;
  scene s;
  material current;  // NFF: the material before any `f`
  std::vector<xform> stack{xform{}};
  int view_line = 0;
  bool saw_from = false, saw_at = false, saw_up = false, saw_angle = false, saw_res = false;

  // The entity being read: its keyword's token and its name in messages.
  token key;
  const char* what = "";
  std::vector<token> words;  // the current entity's numbers, as tokens

  parser(std::string_view text, const std::string& name, std::string dir)
      : in(text, name), base_dir(std::move(dir)) {}

  [[noreturn]] void fail(int line, const std::string& m) const { in.fail(line, m); }
  // Entity-level problems are reported at the entity's keyword.
  [[noreturn]] void fail(const std::string& m) const { in.fail(key.line, m); }
  const xform& top() const { return stack.back(); }

  // Where a number was wanted but the file ended or the next entity began: at that token,
  // or at the entity's keyword when the file ends.
  [[noreturn]] void missing(const std::string& m) const {
    const token& t = in.peek();
    if (t.end()) fail(key.line, m);
    fail(t.line, m + " (the entity begins at line " + std::to_string(key.line) + ")");
  }
  static std::string count_message(const char* what, size_t n, size_t got) {
    std::ostringstream m;
    m << what << " needs " << n << (n == 1 ? " number" : " numbers") << ", got " << got;
    return m.str();
  }
  // Takes the entity's next `n` words as number slots (checked later, each at its own line).
  // Does a number slot's word stand next (neither the end of the file nor a keyword)?
  bool slot_next() const { return !in.peek().end() && !is_keyword(in.peek().text); }
  // Takes n more words as number slots; short_of() says what is wrong when they run out.
  template <class Message>
  void take_or(size_t n, Message&& short_of) {
    for (size_t i = 0; i < n; ++i) {
      if (!slot_next()) missing(short_of());
      words.push_back(in.next());
    }
  }
  void take(size_t n, size_t need_total) {
    take_or(n, [&] { return count_message(what, need_total, words.size()); });
  }
  // Numbers standing after the entity's last: false when there are none, else the first
  // one's line and the count with them (the entity was given too many).
  bool extra_numbers(int& line, size_t& got) {
    if (!looks_decimal(in.peek().text)) return false;
    line = in.peek().line, got = words.size();
    while (looks_decimal(in.peek().text)) in.next(), ++got;
    return true;
  }
  void no_more(size_t n) {
    int line;
    size_t got;
    if (!extra_numbers(line, got)) return;
    if (n == 0) fail(line, std::string(what) + " takes no numbers, got " + std::to_string(got));
    fail(line, count_message(what, n, got));
  }
  // An entity of exactly n numbers.
  void begin(const token& k, const char* name, size_t n) {
    key = k;
    what = name;
    words.clear();
    take(n, n);
    no_more(n);
  }
  float num(size_t i, const char* name) const { return parse_number(words.at(i).text, name, in.name(), words[i].line); }
  vec3 vec(size_t i, const char* name) const { return {num(i, name), num(i + 1, name), num(i + 2, name)}; }
  long integer(size_t i, const char* name, long lo, long hi) const {
    return parse_integer(words.at(i).text, name, lo, hi, in.name(), words[i].line);
  }

  // Upper bounds keep the radiance finite (docs/fuzzing.md): a pixel multiplies a light by
  // Kd, C and a checker colour, then by Ks or T at each of 4 bounces. With these bounds one
  // light contributes below 1e29: it would take billions of lights to reach FLT_MAX.
  static constexpr float max_intensity = 1e6f;  // light colours, ambient, background
  static constexpr float max_factor = 1e3f;     // material and checker colours, Kd, Ks, T

  void check_colour(vec3 c, const char* name, float max = max_intensity) const {
    if (c.x < 0 || c.y < 0 || c.z < 0) fail(std::string(name) + " must be non-negative");
    if (c.x > max || c.y > max || c.z > max) fail(std::string(name) + " must be at most " + std::to_string(long(max)));
  }
  void check_factor(float k, const char* name) const {
    if (k < 0) fail(std::string(name) + " must be non-negative");
    if (k > max_factor) fail(std::string(name) + " must be at most " + std::to_string(long(max_factor)));
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

  // The transform applied to a point or a length must stay a finite, non-degenerate float:
  // `scale 1e30` twice, or `translate 3e38 0 0` twice, is refused here rather than
  // rendering a primitive at infinity or of size zero.
  vec3 placed(vec3 p, const char* name) const {
    vec3 q = top().point(p);
    if (!finite3(q)) fail(std::string(name) + " is beyond float range once transformed");
    return q;
  }
  float sized(float r, const char* name) const {
    float k = r * top().scale;
    if (!std::isfinite(k)) fail(std::string(name) + " is beyond float range once scaled");
    if (r != 0 && !std::isnormal(k)) fail(std::string(name) + " underflows to zero once scaled");
    return k;
  }

  // A primitive's box must have float corners: the BVH and the shafts hold boxes in float.
  // (A box wider than float's range, a sky dome of radius 3e38, is fine: its hit tests and
  // delta are computed in double.)
  void check_extent(const primitive& p) const {
    glm::dvec3 lo(INFINITY), hi(-INFINITY);
    auto grow = [&](vec3 q, double r) { lo = glm::min(lo, glm::dvec3(q) - r), hi = glm::max(hi, glm::dvec3(q) + r); };
    switch (p.kind) {
      case prim_kind::sphere: grow(p.a, std::fabs(double(p.r0))); break;
      case prim_kind::disk: grow(p.a, double(p.r0)); break;
      case prim_kind::cone: {
        const double r = std::max(std::fabs(double(p.r0)), std::fabs(double(p.r1)));
        grow(p.a, r), grow(p.b, r);
        break;
      }
      case prim_kind::box: grow(p.a, 1.7321 * double(std::max({p.b.x, p.b.y, p.b.z}))); break;
      default:
        for (int i = 0; i < p.count; ++i) grow(s.vertices[size_t(p.first + i)], 0);
    }
    const double fmax = double(float_max);
    if (!(glm::all(glm::lessThanEqual(glm::abs(lo), glm::dvec3(fmax))) &&
          glm::all(glm::lessThanEqual(glm::abs(hi), glm::dvec3(fmax)))))
      fail(std::string(what) + " extends beyond float range");
  }

  void add(primitive p) {
    check_extent(p);
    p.material = material_index();
    p.line = key.line;
    s.prims.push_back(p);
  }

  void parse_material(const token& k) {
    begin(k, "material (f)", 8);
    material m = current;
    m.color = vec(0, "material colour");
    check_colour(m.color, "material colour", max_factor);
    m.kd = num(3, "Kd");
    m.ks = num(4, "Ks");
    m.shine = num(5, "Shine");
    m.t = num(6, "T");
    m.ior = num(7, "ior");
    check_factor(m.kd, "Kd");
    check_factor(m.ks, "Ks");
    check_factor(m.t, "T");
    if (m.t > 0 && m.ior <= 0) fail("ior must be positive when T > 0");
    set_material(m);
  }

  void parse_sphere(const token& k) {
    begin(k, "sphere", 4);
    primitive p;
    p.kind = prim_kind::sphere;
    vec3 c = vec(0, "sphere centre");
    float r = num(3, "sphere radius");
    if (r == 0) fail("sphere radius is zero");
    p.a = placed(c, "sphere centre");
    p.r0 = sized(r, "sphere radius");
    add(p);
  }

  primitive cone_from(const token& k, const char* name) {
    begin(k, name, 8);
    primitive p;
    p.kind = prim_kind::cone;
    vec3 base = vec(0, "cone base"), apex = vec(4, "cone apex");
    float r0 = num(3, "cone base radius"), r1 = num(7, "cone apex radius");
    if (r0 == 0 && r1 == 0) fail("both cone radii are zero");
    if ((r0 < 0 && r1 > 0) || (r0 > 0 && r1 < 0)) fail("cone radii have opposite signs");
    p.a = placed(base, "cone base");
    p.b = placed(apex, "cone apex");
    p.r0 = r0 == 0 ? 0.0f : sized(r0, "cone base radius");
    p.r1 = r1 == 0 ? 0.0f : sized(r1, "cone apex radius");
    // Checked where the cone will be: ends that a transform pushes within rounding of each
    // other are as degenerate as ends written equal.
    double len = glm::length(glm::dvec3(p.b) - glm::dvec3(p.a));
    double size = std::max({double(std::fabs(p.r0)), double(std::fabs(p.r1)), glm::length(glm::dvec3(p.a)),
                            glm::length(glm::dvec3(p.b)), 1e-30});
    if (!(len > 1e-6 * size)) fail("cone ends coincide");
    return p;
  }

  void add_disk(vec3 centre, vec3 normal, float radius) {
    primitive d;
    d.kind = prim_kind::disk;
    d.a = centre;
    d.b = unit_axis(normal);
    d.r0 = radius;
    add(d);
  }

  void parse_polygon(const token& k, bool patch) {
    key = k;
    what = patch ? "patch (pp)" : "polygon (p)";
    words.clear();
    take(1, 1);
    long n = integer(0, patch ? "patch vertex count" : "polygon vertex count", 3, 1000000);
    const size_t per = patch ? 6 : 3;
    words.clear();
    take_or(size_t(n) * per, [&] {
      std::ostringstream m;
      m << what << " ends early: expected " << n << " vertices (" << size_t(n) * per << " numbers), got "
        << words.size() << (words.size() == 1 ? " number" : " numbers");
      return m.str();
    });
    if (looks_decimal(in.peek().text)) {
      std::ostringstream m;
      m << what << " of " << n << " vertices needs " << size_t(n) * per << " numbers after its count, got more";
      fail(in.peek().line, m.str());
    }
    primitive p;
    p.kind = patch ? prim_kind::patch : prim_kind::polygon;
    p.first = int(s.vertices.size());
    p.count = int(n);
    for (long i = 0; i < n; ++i) {
      size_t w = size_t(i) * per;
      s.vertices.push_back(placed(vec(w, "vertex"), "vertex"));
      if (patch) {
        vec3 nrm = vec(w + 3, "vertex normal");
        if (nrm == vec3(0)) fail(words[w + 3].line, "patch vertex normal is zero");
        s.normals.push_back(unit_axis(top().dir(unit_axis(nrm))));
      }
    }
    check_polygon(p);
    if (!patch) s.normals.resize(s.vertices.size(), vec3(0));
    add(p);
  }

  // whitted.md 2: the normal comes from the first two edges; every vertex lies in that plane.
  void check_polygon(const primitive& p) const {
    const vec3* v = &s.vertices[size_t(p.first)];
    vec3 lo = v[0], hi = v[0];
    for (int i = 1; i < p.count; ++i) lo = glm::min(lo, v[i]), hi = glm::max(hi, v[i]);
    double extent = glm::length(glm::dvec3(hi) - glm::dvec3(lo));
    glm::dvec3 e0 = glm::dvec3(v[1]) - glm::dvec3(v[0]), e1 = glm::dvec3(v[2]) - glm::dvec3(v[1]);
    glm::dvec3 n = glm::cross(e0, e1);
    double nl = glm::length(n);
    if (!(extent > 0) || !(nl > 1e-12 * extent * extent))
      fail("degenerate polygon: its first two edges are zero or collinear");
    n /= nl;
    for (int i = 0; i < p.count; ++i) {
      double d = std::fabs(glm::dot(n, glm::dvec3(v[i]) - glm::dvec3(v[0])));
      if (d > 1e-3 * extent) {
        std::ostringstream m;
        m << "polygon is not planar: vertex " << i << " is " << d << " from the plane of the first edges";
        fail(m.str());
      }
    }
  }

  void parse_box(const token& k) {
    begin(k, "box", 6);
    vec3 lo = vec(0, "box corner"), hi = vec(3, "box corner");
    glm::dvec3 size = glm::abs(glm::dvec3(hi) - glm::dvec3(lo));
    if (!(size.x > 0 && size.y > 0 && size.z > 0)) fail("box has zero size along an axis");
    primitive p;
    p.kind = prim_kind::box;
    p.a = placed(vec3((glm::dvec3(lo) + glm::dvec3(hi)) * 0.5), "box centre");
    vec3 half(size * 0.5);
    p.b = {sized(half.x, "box size"), sized(half.y, "box size"), sized(half.z, "box size")};
    p.frame = top().rot;
    add(p);
  }

  void parse_disk(const token& k) {
    begin(k, "disk", 7);
    vec3 c = vec(0, "disk centre"), n = vec(3, "disk normal");
    float r = num(6, "disk radius");
    if (n == vec3(0)) fail("disk normal is zero");
    if (!(r > 0)) fail("disk radius must be positive");
    add_disk(placed(c, "disk centre"), top().dir(unit_axis(n)), sized(r, "disk radius"));
  }

  void parse_capped_cone(const token& k) {
    primitive c = cone_from(k, "capped cone (cc)");
    if (c.r0 < 0 || c.r1 < 0) fail("capped cone radii must be non-negative");
    add(c);
    vec3 axis = c.b - c.a;
    if (!finite3(axis)) axis = vec3(glm::dvec3(c.b) - glm::dvec3(c.a));  // unit_axis needs only the direction
    if (c.r0 > 0) add_disk(c.a, -axis, c.r0);
    if (c.r1 > 0) add_disk(c.b, axis, c.r1);
  }

  void parse_light(const token& k) {
    key = k;
    what = "light (l)";
    words.clear();
    take(3, 3);
    auto three_or_six = [&](size_t got) { return "light (l) needs 3 or 6 numbers, got " + std::to_string(got); };
    // Three more numbers, when a number follows, are the light's colour.
    if (slot_next()) take_or(3, [&] { return three_or_six(words.size()); });
    int line;
    size_t got;
    if (extra_numbers(line, got)) fail(line, three_or_six(got));
    light li;
    li.position = placed(vec(0, "light position"), "light position");
    if (words.size() == 6) {
      li.color = vec(3, "light colour");
      check_colour(li.color, "light colour");
      li.has_color = true;
    }
    s.lights.push_back(li);
  }

  void parse_texture(const token& k) {
    key = k;
    what = "texture";
    words.clear();
    const token kind_tok = in.next();
    if (kind_tok.end() || is_keyword(kind_tok.text)) fail("texture needs a kind: checker, image or none");
    std::string_view kind = kind_tok.text;
    material m = current;
    if (kind == "none") {
      what = "texture none";
      no_more(0);
      m.texture = -1;
      set_material(m);
      return;
    }
    texture t;
    if (kind == "checker") {
      what = "texture checker (two colours, two scales)";
      take(8, 8);
      no_more(8);
      t.kind = texture_kind::checker;
      t.color_a = vec(0, "checker colour");
      t.color_b = vec(3, "checker colour");
      check_colour(t.color_a, "checker colour", max_factor);
      check_colour(t.color_b, "checker colour", max_factor);
      t.scale = {num(6, "texture scale"), num(7, "texture scale")};
    } else if (kind == "image") {
      what = "texture image (a file, two scales)";
      const token file = in.next();
      if (file.end()) fail("texture image needs a file and two scales");
      take(2, 2);
      no_more(2);
      t.kind = texture_kind::image;
      t.file = std::string(file.text);
      t.scale = {num(0, "texture scale"), num(1, "texture scale")};
      load_image(t);
    } else {
      fail(kind_tok.line, "unknown texture kind " + quote_word(kind) + " (checker, image or none)");
    }
    if (!(t.scale.x > 0 && t.scale.y > 0)) fail("texture scales must be positive");
    s.textures.push_back(std::move(t));
    m.texture = int(s.textures.size()) - 1;
    set_material(m);
  }

  // Texels decoded at most: 8192 x 8192 (768 MB as linear floats). A texture is looked up
  // once per shaded point; larger ones add memory, not detail a frame can show.
  static constexpr long long max_texels = 8192LL * 8192LL;
  static constexpr std::size_t max_texture_bytes = std::size_t(512) << 20;

  void load_image(texture& t) {
    std::filesystem::path p(t.file);
    if (p.is_relative() && !base_dir.empty()) p = std::filesystem::path(base_dir) / p;
    const std::string shown = "texture file " + quote_word(t.file);
    std::string bytes;
    try {
      bytes = read_input_file(p.string(), max_texture_bytes);
    } catch (const input_error& e) {
      fail(shown + " cannot be read: " + e.what_is_wrong);
    }
    const auto* data_in = reinterpret_cast<const stbi_uc*>(bytes.data());
    const int len = int(bytes.size());
    int w = 0, h = 0, comp = 0;
    auto reason = [] {  // stb's messages are short C strings; keep them printable
      return quote_word(stbi_failure_reason() ? stbi_failure_reason() : "unknown format");
    };
    if (!stbi_info_from_memory(data_in, len, &w, &h, &comp)) fail(shown + " cannot be read: " + reason());
    if (w <= 0 || h <= 0 || (long long)w * h > max_texels) {
      std::ostringstream m;
      m << shown << " is " << w << "x" << h << ", over the limit of " << max_texels << " texels (8192x8192)";
      fail(m.str());
    }
    unsigned char* data = stbi_load_from_memory(data_in, len, &w, &h, &comp, 3);
    if (!data) fail(shown + " cannot be read: " + reason());
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

  void parse_transform(const token& k, std::string_view name) {
    if (name == "push") {
      begin(k, "push", 0);
      if (stack.size() > 64) fail("transforms nested deeper than 64");
      stack.push_back(top());
    } else if (name == "pop") {
      begin(k, "pop", 0);
      if (stack.size() == 1) fail("pop without a matching push");
      stack.pop_back();
    } else if (name == "translate") {
      begin(k, "translate", 3);
      vec3 o = top().point(vec(0, "translation"));
      if (!finite3(o)) fail("translation is beyond float range once composed with the enclosing transforms");
      stack.back().offset = o;
    } else if (name == "rotate") {
      begin(k, "rotate", 4);
      vec3 axis = vec(0, "rotation axis");
      float deg = num(3, "rotation angle");
      if (axis == vec3(0)) fail("rotation axis is zero");
      glm::mat3 r = rotation(unit_axis(axis), glm::radians(deg));
      stack.back().rot = top().rot * r;
    } else {  // scale
      begin(k, "scale", 1);
      float f = num(0, "scale");
      if (!(f > 0)) fail("scale must be positive (only uniform scaling keeps primitives analytic)");
      float composed = top().scale * f;
      if (!std::isfinite(composed)) fail("scale is beyond float range once composed with the enclosing scales");
      if (!std::isnormal(composed)) fail("scale underflows to zero once composed with the enclosing scales");
      stack.back().scale = composed;
    }
  }

  static glm::mat3 rotation(vec3 a, float rad) {
    float c = std::cos(rad), s = std::sin(rad), t = 1 - c;
    // Rodrigues' formula, column-major for GLM.
    return glm::mat3(t * a.x * a.x + c, t * a.x * a.y + s * a.z, t * a.x * a.z - s * a.y,
                     t * a.x * a.y - s * a.z, t * a.y * a.y + c, t * a.y * a.z + s * a.x,
                     t * a.x * a.z + s * a.y, t * a.y * a.z - s * a.x, t * a.z * a.z + c);
  }

  void parse_view_word(const token& k, std::string_view name) {
    camera_view& v = s.view;
    if (name == "from") begin(k, "from", 3), v.from = vec(0, "from"), saw_from = true;
    else if (name == "at") begin(k, "at", 3), v.at = vec(0, "at"), saw_at = true;
    else if (name == "up") begin(k, "up", 3), v.up = vec(0, "up"), saw_up = true;
    else if (name == "angle") {
      begin(k, "angle", 1);
      v.angle = num(0, "angle");
      if (!(v.angle > 0 && v.angle < 180)) fail("angle must be between 0 and 180 degrees");
      saw_angle = true;
    } else if (name == "hither") {
      begin(k, "hither", 1);
      num(0, "hither");  // checked, then ignored (whitted.md 1)
    } else {  // resolution
      begin(k, "resolution", 2);
      v.width = int(integer(0, "resolution width", 1, 16384));
      v.height = int(integer(1, "resolution height", 2, 16384));
      saw_res = true;
    }
    if (view_line == 0) view_line = k.line;
  }

  void finish() {
    int end = in.last_line() ? in.last_line() : 1;
    if (in.last_line() == 0) in.fail(1, "empty scene file");
    if (s.prims.empty()) in.fail(end, "scene has no primitives");
    if (!(saw_from && saw_at && saw_up && saw_angle && saw_res)) {
      std::string missing_words;
      if (!saw_from) missing_words += " from";
      if (!saw_at) missing_words += " at";
      if (!saw_up) missing_words += " up";
      if (!saw_angle) missing_words += " angle";
      if (!saw_res) missing_words += " resolution";
      in.fail(view_line ? view_line : end, "viewpoint is missing:" + missing_words);
    }
    if (const char* problem = view_problem(s.view)) in.fail(view_line, std::string("viewpoint: ") + problem);
    if (s.materials.empty()) s.materials.push_back(current);
    s.has_view = true;
  }

  void run() {
    while (!in.peek().end()) {
      const token k = in.next();
      std::string_view name = k.text;
      if (name == "v") begin(k, "v", 0), view_line = k.line;
      else if (name == "from" || name == "at" || name == "up" || name == "angle" || name == "hither" ||
               name == "resolution")
        parse_view_word(k, name);
      else if (name == "b") {
        begin(k, "background (b)", 3);
        s.background = vec(0, "background colour");
        check_colour(s.background, "background colour");
      } else if (name == "l") parse_light(k);
      else if (name == "f") parse_material(k);
      else if (name == "s") parse_sphere(k);
      else if (name == "c") { primitive c = cone_from(k, "cone (c)"); add(c); }
      else if (name == "p") parse_polygon(k, false);
      else if (name == "pp") parse_polygon(k, true);
      else if (name == "box") parse_box(k);
      else if (name == "disk") parse_disk(k);
      else if (name == "cc") parse_capped_cone(k);
      else if (name == "texture") parse_texture(k);
      else if (name == "ambient") {
        begin(k, "ambient", 3);
        s.ambient = vec(0, "ambient colour");
        check_colour(s.ambient, "ambient colour");
        s.has_ambient = true;
      } else if (name == "push" || name == "pop" || name == "translate" || name == "rotate" || name == "scale")
        parse_transform(k, name);
      else if (looks_decimal(name)) fail(k.line, "number " + quote_word(name) + " where an entity was expected");
      else fail(k.line, "unknown entity " + quote_word(name));
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
