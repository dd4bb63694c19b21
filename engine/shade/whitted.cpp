#include "shade/whitted.h"

#include <cmath>
#include <limits>

#include "shade/surface.h"
#include "shade/texture.h"

namespace epsray {

namespace {

// Unit d and nf give a unit reflection (whitted.md 4); no normalize on the hot path.
vec3 reflect_dir(vec3 d, vec3 nf) { return d - 2 * glm::dot(d, nf) * nf; }

int shadow_blocker(const world& w, const ray& r, float dist, size_t light, trace_state& st) {
  const bool cached = !st.tree && light < size_t(shadow_cache_lights);
  if (cached) {
    int last = st.last_blocker[light];
    float t;
    if (last >= 0 && hit_shape(w.shapes[size_t(last)], w.polys, r, dist, t)) return last;
  }
  int b = first_blocker(w, r, dist);
  if (cached) st.last_blocker[light] = b;
  return b;
}

}  // namespace

vec3 radiance(const world& w, const ray& r, int depth, trace_state& st) {
  hit h;
  if (!closest_hit(w, r, std::numeric_limits<float>::infinity(), h)) {
    if (st.tree) st.tree->nodes.emplace_back();  // a miss: prim -1
    return w.background;
  }
  return shade_hit(w, r, h, depth, st);
}

vec3 shade_hit(const world& w, const ray& r, const hit& h, int depth, trace_state& st) {
  ray_tree* tree = st.tree;
  int node = -1;
  if (tree) {
    node = int(tree->nodes.size());
    tree->nodes.emplace_back();
  }

  const surface sf = surface_at(w, h.prim, r, h.t);
  const material& m = w.sc.materials[size_t(w.info[size_t(h.prim)].material)];
  const bool entering = glm::dot(sf.ng, r.d) < 0;
  const vec3 nf = entering ? sf.ns : -sf.ns;
  const vec3 v = -r.d;
  vec3 colour = m.color;
  const bool split = depth == 1 && m.texture >= 0 && st.root_tex_factor;
  vec3 tex_factor{0};
  if (m.texture >= 0) {
    vec2 uv = surface_uv(w, h.prim, sf.p);
    if (split) *st.root_uv = uv, tex_factor = w.ambient * m.kd * m.color;
    colour *= sample_texture(w.sc.textures[size_t(m.texture)], uv);
  }
  const vec3 kd_c = m.kd * colour;

  if (tree) {
    ray_tree_node& n = tree->nodes[size_t(node)];
    n.prim = w.info[size_t(h.prim)].source;
    n.entering = entering;
    n.lights = std::uint32_t(tree->lights.size());
  }

  vec3 L = w.ambient * kd_c;
  const vec3 above = sf.p + w.delta * nf;
  const size_t nl = w.light_pos.size();
  for (size_t j = 0; j < nl; ++j) {
    const vec3 to_light = w.light_pos[j] - sf.p;
    const vec3 lj = glm::normalize(to_light);
    const float ndl = glm::dot(nf, lj);
    std::int32_t status = light_behind;
    if (ndl > 0) {
      ++st.counts.shadow;
      vec3 so = w.light_pos[j] - above;
      float dist = glm::length(so);
      int blocker = dist > 0 ? shadow_blocker(w, make_ray(above, so / dist), dist, j, st) : -1;
      status = blocker >= 0 ? w.info[size_t(blocker)].source : light_lit;
      if (blocker < 0) {
        float spec = 0;
        if (m.shine > 0) {
          vec3 hj = glm::normalize(lj + v);
          spec = std::pow(std::max(0.0f, glm::dot(nf, hj)), m.shine);
        }
        L += w.light_power[j] * (kd_c * ndl + m.ks * spec);
        if (split) tex_factor += w.light_power[j] * (m.kd * m.color * ndl);
      }
    }
    if (tree) tree->lights.push_back(status);
  }
  if (split) *st.root_tex_factor = tex_factor;

  if (depth < max_depth && m.ks > 0) {
    ++st.counts.reflect;
    if (tree) tree->nodes[size_t(node)].reflect = std::int16_t(tree->nodes.size());
    L += m.ks * radiance(w, make_ray(above, reflect_dir(r.d, nf)), depth + 1, st);
  }
  if (depth < max_depth && m.t > 0) {
    ++st.counts.refract;
    const float eta = entering ? 1 / m.ior : m.ior;
    const float ci = glm::dot(v, nf);
    const float k = 1 - eta * eta * (1 - ci * ci);
    if (tree) {
      ray_tree_node& n = tree->nodes[size_t(node)];
      n.refract = std::int16_t(tree->nodes.size());
      n.tir = k < 0;
    }
    if (k < 0) {
      L += m.t * radiance(w, make_ray(above, reflect_dir(r.d, nf)), depth + 1, st);
    } else {
      vec3 td = glm::normalize(eta * r.d + (eta * ci - std::sqrt(k)) * nf);
      L += m.t * radiance(w, make_ray(sf.p - w.delta * nf, td), depth + 1, st);
    }
  }
  return L;
}

vec3 trace_eye(const world& w, const ray& r, trace_state& st) {
  ++st.counts.eye;
  if (st.tree) st.tree->clear();
  return radiance(w, r, 1, st);
}

}  // namespace epsray
