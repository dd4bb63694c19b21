#include "reproject/face_raster.h"

#include <dlfcn.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <type_traits>

namespace epsray {

// The OSMesa and GL entry points, fetched at run time. No GL header is included, so no gl*
// function can be called directly by mistake (it would bind to the viewer's libOpenGL).
struct face_raster::gl {
  using GLenum = unsigned;
  void* (*CreateContextExt)(GLenum format, int depth, int stencil, int accum, void* share) = nullptr;
  unsigned char (*MakeCurrent)(void* ctx, void* buffer, GLenum type, int width, int height) = nullptr;
  void (*DestroyContext)(void* ctx) = nullptr;
  void (*(*GetProcAddress)(const char*))() = nullptr;
  void (*Viewport)(int, int, int, int) = nullptr;
  void (*MatrixMode)(GLenum) = nullptr;
  void (*LoadIdentity)() = nullptr;
  void (*Ortho)(double, double, double, double, double, double) = nullptr;
  void (*Disable)(GLenum) = nullptr;
  void (*ShadeModel)(GLenum) = nullptr;
  void (*ClearColor)(float, float, float, float) = nullptr;
  void (*Clear)(unsigned) = nullptr;
  void (*EnableClientState)(GLenum) = nullptr;
  void (*VertexPointer)(int, GLenum, int, const void*) = nullptr;
  void (*ColorPointer)(int, GLenum, int, const void*) = nullptr;
  void (*DrawArrays)(GLenum, int, int) = nullptr;
  void (*Finish)() = nullptr;
};

namespace {

constexpr unsigned gl_rgba = 0x1908, gl_unsigned_byte = 0x1401, gl_float = 0x1406;
constexpr unsigned gl_projection = 0x1701, gl_modelview = 0x1700, gl_flat = 0x1D00;
constexpr unsigned gl_dither = 0x0BD0, gl_blend = 0x0BE2, gl_depth_test = 0x0B71, gl_cull_face = 0x0B44;
constexpr unsigned gl_color_buffer_bit = 0x4000, gl_triangles = 0x0004;
constexpr unsigned gl_vertex_array = 0x8074, gl_color_array = 0x8076;
constexpr std::uint32_t max_cells = (1u << 24) - 1;  // indices + 1 in 24 bits of colour

constexpr int max_vertices = 48;
struct poly3 {
  int n = 0;
  glm::dvec3 v[max_vertices];
};
struct poly2 {
  int n = 0;
  glm::dvec2 v[max_vertices];
};

// Sutherland-Hodgman: the part of a convex polygon where f >= 0 (f affine).
template <class P, class F>
P clip(const P& in, F&& f) {
  P out;
  for (int i = 0; i < in.n; ++i) {
    const auto& a = in.v[i];
    const auto& b = in.v[(i + 1) % in.n];
    const double fa = f(a), fb = f(b);
    if (fa >= 0 && out.n < max_vertices) out.v[out.n++] = a;
    if (((fa >= 0) != (fb >= 0)) && out.n < max_vertices) out.v[out.n++] = a + (b - a) * (fa / (fa - fb));
  }
  return out;
}

double area(const poly2& p) {
  double s = 0;
  for (int i = 0; i < p.n; ++i) {
    const glm::dvec2& a = p.v[i];
    const glm::dvec2& b = p.v[(i + 1) % p.n];
    s += a.x * b.y - a.y * b.x;
  }
  return 0.5 * s;
}

// The face's eye lines within the view, as at most two convex polygons in window
// coordinates: the part of the face in front of the eye, and the part behind it mirrored
// through the eye (a line meets a plane behind the eye too, and the lookup takes it).
int face_parts(const camera& cam, const glm::dvec3 corner[4], poly2 out[2], bool front_only = false) {
  const glm::dvec3 r(cam.r), u(cam.u), w(cam.w), o(cam.origin);
  const double step = double(cam.step);
  // The view's frustum, two pixels wider on each side than the pixel centres need.
  const double X = (0.5 * double(cam.width) + 2) * step, Y = (0.5 * double(cam.height) + 2) * step;
  double scale = 0;
  for (int k = 0; k < 4; ++k) scale = std::max(scale, glm::length(corner[k] - o));
  int parts = 0;
  for (double s : {1.0, -1.0}) {
    if (front_only && s < 0) break;
    poly3 p;
    p.n = 4;
    for (int k = 0; k < 4; ++k) p.v[k] = s * (corner[k] - o);
    p = clip(p, [&](const glm::dvec3& q) { return glm::dot(q, w) - 1e-9 * scale; });
    p = clip(p, [&](const glm::dvec3& q) { return X * glm::dot(q, w) - glm::dot(q, r); });
    p = clip(p, [&](const glm::dvec3& q) { return X * glm::dot(q, w) + glm::dot(q, r); });
    p = clip(p, [&](const glm::dvec3& q) { return Y * glm::dot(q, w) - glm::dot(q, u); });
    p = clip(p, [&](const glm::dvec3& q) { return Y * glm::dot(q, w) + glm::dot(q, u); });
    if (p.n < 3) continue;
    poly2& f = out[parts];
    f.n = p.n;
    for (int k = 0; k < p.n; ++k) {
      const double z = glm::dot(p.v[k], w) * step;
      f.v[k] = {0.5 * double(cam.width) + glm::dot(p.v[k], r) / z, 0.5 * double(cam.height) + glm::dot(p.v[k], u) / z};
    }
    const double a = area(f);
    if (!(std::abs(a) > 1e-12)) continue;
    if (a < 0) std::reverse(f.v, f.v + f.n);  // counter-clockwise: inside is on the left
    ++parts;
  }
  return parts;
}

// The overlap of two counter-clockwise convex polygons.
poly2 overlap(const poly2& a, const poly2& b) {
  poly2 p = a;
  for (int i = 0; i < b.n && p.n >= 3; ++i) {
    const glm::dvec2 e0 = b.v[i], e = b.v[(i + 1) % b.n] - e0;
    p = clip(p, [&](const glm::dvec2& q) { return e.x * (q.y - e0.y) - e.y * (q.x - e0.x); });
  }
  return p;
}

}  // namespace

void cell_regions(const camera& cam, const facepair& fp, const lt_node& n, std::vector<int>& counts,
                  std::vector<float>& xy, const cell_trust* trust) {
  glm::dvec3 front[4], back[4], face[4];
  const int order[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};  // corners around the rectangle
  for (int k = 0; k < 4; ++k) {
    const int i = order[k][0], j = order[k][1];
    front[k] = glm::dvec3(front_point(fp, i ? n.hi[0] : n.lo[0], j ? n.hi[1] : n.lo[1]));
    back[k] = glm::dvec3(back_point(fp, i ? n.hi[2] : n.lo[2], j ? n.hi[3] : n.lo[3]));
    if (trust && trust->face_check)
      face[k] = glm::dvec3(plane_point(fp, trust->face_at, i ? trust->face_hi[0] : trust->face_lo[0],
                                       j ? trust->face_hi[1] : trust->face_lo[1]));
  }
  poly2 f[2], b[2], fc[2];
  const int nf = face_parts(cam, front, f), nb = face_parts(cam, back, b);
  const bool on_face = trust && trust->face_check;
  if (on_face && face_parts(cam, face, fc, true) == 0) return;  // the face is out of view
  for (int i = 0; i < nf; ++i)
    for (int j = 0; j < nb; ++j) {
      poly2 p = overlap(f[i], b[j]);
      if (on_face && p.n >= 3) p = overlap(p, fc[0]);
      if (p.n < 3) continue;
      counts.push_back(p.n);
      for (int k = 0; k < p.n; ++k) xy.push_back(float(p.v[k].x)), xy.push_back(float(p.v[k].y));
    }
}

std::unique_ptr<face_raster> face_raster::open(std::string& why) {
  std::unique_ptr<face_raster> fr(new face_raster);
  // llvmpipe's own threads would compete with the TBB workers (2.7x slower measured):
  // rasterize in the calling thread unless the user chose otherwise.
  setenv("LP_NUM_THREADS", "0", 0);
  for (const char* name : {"libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"})
    if ((fr->lib_ = dlopen(name, RTLD_NOW | RTLD_LOCAL))) break;
  if (!fr->lib_) {
    const char* e = dlerror();
    why = std::string("OSMesa cannot be loaded: ") + (e ? e : "libOSMesa.so.8 not found");
    return nullptr;
  }
  fr->gl_ = std::make_unique<gl>();
  gl& g = *fr->gl_;
  auto sym = [&](auto& fn, const char* name) {
    fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(dlsym(fr->lib_, name));
    return fn != nullptr;
  };
  if (!sym(g.CreateContextExt, "OSMesaCreateContextExt") || !sym(g.MakeCurrent, "OSMesaMakeCurrent") ||
      !sym(g.DestroyContext, "OSMesaDestroyContext") || !sym(g.GetProcAddress, "OSMesaGetProcAddress")) {
    why = "OSMesa lacks its context functions";
    return nullptr;
  }
  auto proc = [&](auto& fn, const char* name) {
    fn = reinterpret_cast<std::remove_reference_t<decltype(fn)>>(g.GetProcAddress(name));
    return fn != nullptr;
  };
  if (!proc(g.Viewport, "glViewport") || !proc(g.MatrixMode, "glMatrixMode") ||
      !proc(g.LoadIdentity, "glLoadIdentity") || !proc(g.Ortho, "glOrtho") || !proc(g.Disable, "glDisable") ||
      !proc(g.ShadeModel, "glShadeModel") || !proc(g.ClearColor, "glClearColor") || !proc(g.Clear, "glClear") ||
      !proc(g.EnableClientState, "glEnableClientState") || !proc(g.VertexPointer, "glVertexPointer") ||
      !proc(g.ColorPointer, "glColorPointer") || !proc(g.DrawArrays, "glDrawArrays") || !proc(g.Finish, "glFinish")) {
    why = "OSMesa lacks a GL 1.1 entry point";
    return nullptr;
  }
  fr->ctx_ = g.CreateContextExt(gl_rgba, 0, 0, 0, nullptr);
  if (!fr->ctx_) {
    why = "OSMesa gives no RGBA context";
    return nullptr;
  }
  return fr;
}

face_raster::~face_raster() {
  if (ctx_ && gl_) gl_->DestroyContext(ctx_);  // never current here: draw releases it
  // The library stays loaded: Mesa keeps threads and atexit handlers that outlive a context.
}

void cell_triangles(const camera& cam, const std::vector<cell_ref>& cells, const std::vector<cell_trust>& trusted,
                    std::size_t first, std::size_t last, std::vector<float>& xy, std::vector<std::uint32_t>& rgba) {
  std::vector<int> counts;
  std::vector<float> poly;
  last = std::min<std::size_t>(last, max_cells);
  for (std::size_t i = last; i-- > first;) {
    if (!trusted[i].ok) continue;
    counts.clear(), poly.clear();
    cell_regions(cam, cells[i].lt->fp, *cells[i].node, counts, poly, &trusted[i]);
    const std::uint32_t colour = std::uint32_t(i + 1) | 0xff000000u;  // R, G, B, A in memory
    std::size_t at = 0;
    for (int c : counts) {
      for (int k = 1; k + 1 < c; ++k)  // a fan: the regions are convex
        for (int v : {0, k, k + 1}) {
          xy.push_back(poly[2 * (at + std::size_t(v))]), xy.push_back(poly[2 * (at + std::size_t(v)) + 1]);
          rgba.push_back(colour);
        }
      at += std::size_t(c);
    }
  }
}

std::size_t face_raster::owners(const camera& cam, const std::vector<cell_ref>& cells,
                                const std::vector<cell_trust>& trusted, std::int32_t* owner) {
  std::vector<float> xy;
  std::vector<std::uint32_t> rgba;
  cell_triangles(cam, cells, trusted, 0, cells.size(), xy, rgba);
  draw(cam, xy, rgba, owner);
  return rgba.size() / 3;
}

void face_raster::draw(const camera& cam, const std::vector<float>& xy, const std::vector<std::uint32_t>& rgba,
                       std::int32_t* owner) {
  const int W = cam.width, H = cam.height;
  const std::size_t pixels = std::size_t(W) * std::size_t(H);
  buffer_.assign(pixels, 0);
  const gl& g = *gl_;
  if (!g.MakeCurrent(ctx_, buffer_.data(), gl_unsigned_byte, W, H)) {
    std::fill(owner, owner + pixels, -1);  // nothing reprojected: every pixel takes the interpolate path
    return;
  }
  g.Viewport(0, 0, W, H);
  g.MatrixMode(gl_projection), g.LoadIdentity(), g.Ortho(0, W, 0, H, -1, 1);
  g.MatrixMode(gl_modelview), g.LoadIdentity();
  g.Disable(gl_dither), g.Disable(gl_blend), g.Disable(gl_depth_test), g.Disable(gl_cull_face);
  g.ShadeModel(gl_flat);  // the provoking vertex's colour, exactly
  g.ClearColor(0, 0, 0, 0), g.Clear(gl_color_buffer_bit);
  if (!rgba.empty()) {
    g.EnableClientState(gl_vertex_array), g.EnableClientState(gl_color_array);
    g.VertexPointer(2, gl_float, 0, xy.data()), g.ColorPointer(4, gl_unsigned_byte, 0, rgba.data());
    g.DrawArrays(gl_triangles, 0, int(rgba.size()));
  }
  g.Finish();
  // Released, so that the next frame may draw from another thread (--pipeline's).
  g.MakeCurrent(nullptr, nullptr, 0, 0, 0);
  for (int y = 0; y < H; ++y) {
    const std::uint32_t* row = buffer_.data() + std::size_t(H - 1 - y) * std::size_t(W);  // bottom row first
    std::int32_t* out = owner + std::size_t(y) * std::size_t(W);
    for (int x = 0; x < W; ++x) out[x] = std::int32_t(row[x] & 0xffffffu) - 1;
  }
}

}  // namespace epsray
