// BVH build and traversal, and full Whitted rays, in one thread:
//   bvh_build/{spheres,triangles}/N    build_bvh over N random primitive boxes (items: primitives)
//   soup_{closest_hit,first_blocker}/N random rays through N random spheres (items: rays)
//   spd_{closest_hit,first_blocker}/<scene>/{eye,random,shadow}
//                                      the SPD scenes with their own camera (items: rays)
//   spd_light_cache/<scene>/shadow     the same shadow rays by the light cache's lists
//   whitted/<scene>                    trace_eye per eye ray (items: eye rays; rays/s counts all)
// Scenes, soups and ray sets are made on first use and kept, outside the timed loops.
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <tuple>

#include "accel/bvh.h"
#include "accel/light_cache.h"
#include "bench_common.h"
#include "scene/nff.h"
#include "shade/surface.h"
#include "shade/whitted.h"

#ifndef EPSRAY_SPD_DIR
#define EPSRAY_SPD_DIR ""
#endif

namespace epsray::micro {

constexpr float no_limit = std::numeric_limits<float>::infinity();

ray_set eye_rays(const camera_view& view, int width, int height) {
  constexpr int stride = 16;  // 16 rows of 256 pixels: one chunk
  const camera cam = make_camera(view, width, height);
  ray_set set;
  for (int k = 0; k < stride; ++k)
    for (int y = k; y < height; y += stride)
      for (int x = 0; x < width; ++x) {
        set.rays.push_back(make_ray(cam.origin, eye_direction(cam, float(x), float(y))));
        set.tmax.push_back(no_limit);
      }
  return set;
}

ray_set random_rays(const bounds& box, std::size_t n, std::uint64_t s) {
  rng g(seed, s);
  ray_set set;
  for (std::size_t i = 0; i < n; ++i) {
    vec3 o = g.in_box(box.lo, box.hi);
    set.rays.push_back(make_ray(o, g.direction()));
    set.tmax.push_back(no_limit);
  }
  return set;
}

namespace {

constexpr std::size_t random_ray_count = 65536;

// Spheres in the unit cube, radius 0.25 N^(-1/3): the covered volume fraction stays the same
// (about 6.5 %, before overlaps) for every N.
scene sphere_soup(int n) {
  rng g(seed, 7);
  scene s;
  s.materials.emplace_back();
  const float r = 0.25f * std::pow(float(n), -1.0f / 3.0f);
  for (int i = 0; i < n; ++i) {
    primitive p;
    p.kind = prim_kind::sphere;
    p.a = g.in_box(vec3(0), vec3(1));
    p.r0 = r;
    s.prims.push_back(p);
  }
  return s;
}

// Bounds of N random spheres, or of N random triangles of the same size.
const std::vector<bounds>& build_input(bool triangles, int n) {
  static std::map<std::pair<bool, int>, std::vector<bounds>> cache;
  auto [it, fresh] = cache.try_emplace({triangles, n});
  if (!fresh) return it->second;
  rng g(seed, triangles ? 11 : 7);
  const float r = 0.25f * std::pow(float(n), -1.0f / 3.0f);
  for (int i = 0; i < n; ++i) {
    vec3 c = g.in_box(vec3(0), vec3(1));
    bounds b;
    if (triangles) {
      for (int k = 0; k < 3; ++k) b.grow(c + 2 * r * g.direction());
    } else {
      b = bounds{c - r, c + r};
    }
    it->second.push_back(b);
  }
  return it->second;
}

void bm_build(benchmark::State& state, bool triangles) {
  const std::vector<bounds>& boxes = build_input(triangles, int(state.range(0)));
  std::size_t nodes = 0;
  for (auto _ : state) {
    bvh b = build_bvh(boxes);
    nodes = b.nodes.size();
    benchmark::DoNotOptimize(b.nodes.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * state.range(0));
  state.counters["nodes"] = double(nodes);
}

struct soup {
  world w;
  ray_set rays;
};

const soup& sphere_soup_world(int n) {
  static std::map<int, std::unique_ptr<soup>> cache;
  std::unique_ptr<soup>& s = cache[n];
  if (!s) {
    s = std::make_unique<soup>();
    s->w = make_world(sphere_soup(n));
    s->rays = random_rays(bounds{vec3(0), vec3(1)}, random_ray_count, 13);
  }
  return *s;
}

struct walk_stats {
  double leaves = 0, tests = 0;  // per ray
};

// Leaves visited and primitive tests per ray, by the same walk as closest_hit/first_blocker
// with counting leaves; computed once per (world, ray set, query) and kept.
const walk_stats& count_walk(const world& w, const ray_set& set, bool closest) {
  static std::map<std::tuple<const world*, const ray_set*, bool>, walk_stats> cache;
  auto [it, fresh] = cache.try_emplace({&w, &set, closest});
  if (!fresh) return it->second;
  double leaves = 0, tests = 0;
  for (std::size_t i = 0; i < set.rays.size(); ++i) {
    const ray& r = set.rays[i];
    float tmax = set.tmax[i];
    auto leaf = [&](std::uint32_t first, std::uint32_t count, float& tm) {
      bool any = false;
      ++leaves;
      for (std::uint32_t k = first; k < first + count; ++k) {
        float t;
        ++tests;
        // Leaves hold slots: a primitive split into pieces has several (world::slot_prim).
        if (hit_shape(w.shapes[w.slot_prim[k]], w.polys, r, tm, t)) {
          if (!closest) return true;
          tm = t, any = true;
        }
      }
      return any;
    };
    if (closest) traverse_bvh<false>(w.tree, r, tmax, leaf);
    else traverse_bvh<true>(w.tree, r, tmax, leaf);
  }
  const double n = double(std::max<std::size_t>(1, set.rays.size()));
  it->second = {leaves / n, tests / n};
  return it->second;
}

// closest_hit or first_blocker over a ray set; reports rays as items, the hit rate, and the
// leaves and primitive tests per ray (untimed: from a separate counting walk).
void run_query(benchmark::State& state, const world& w, const ray_set& set, bool closest) {
  const walk_stats& ws = count_walk(w, set, closest);
  std::size_t hits = 0;
  if (closest) {
    run_ray_set(state, set, [&](const ray& r, float tmax) {
      hit h;
      bool found = closest_hit(w, r, tmax, h);
      benchmark::DoNotOptimize(h);
      hits += found;
    });
  } else {
    run_ray_set(state, set, [&](const ray& r, float tmax) {
      int b = first_blocker(w, r, tmax);
      benchmark::DoNotOptimize(b);
      hits += b >= 0;
    });
  }
  const double done = double(state.iterations()) * double(chunk);
  state.counters["hit%"] = done > 0 ? 100.0 * double(hits) / done : 0.0;
  state.counters["prims"] = double(w.shapes.size());
  state.counters["leaves/ray"] = ws.leaves;
  state.counters["tests/ray"] = ws.tests;
}

void bm_soup(benchmark::State& state, bool closest) {
  const soup& s = sphere_soup_world(int(state.range(0)));
  run_query(state, s.w, s.rays, closest);
}

// The shadow rays of radiance() for every eye ray's first hit: from just above the surface
// to each light on its front side, tmax the distance to the light; each one's light in
// `light`, and in `self` the flat primitive it leaves, which the light cache skips.
ray_set shadow_rays(const world& w, const ray_set& eye, std::vector<std::uint32_t>& light, std::vector<int>& self) {
  ray_set set;
  for (const ray& r : eye.rays) {
    hit h;
    if (!closest_hit(w, r, no_limit, h)) continue;
    const surface sf = surface_at(w, h.prim, r, h.t);
    const vec3 nf = glm::dot(sf.ng, r.d) < 0 ? sf.ns : -sf.ns;
    const vec3 above = sf.p + w.delta * nf;
    for (size_t j = 0; j < w.light_pos.size(); ++j) {
      const vec3 lp = w.light_pos[j];
      if (glm::dot(nf, glm::normalize(lp - sf.p)) <= 0) continue;
      const vec3 so = lp - above;
      const float dist = glm::length(so);
      if (dist <= 0) continue;
      set.rays.push_back(make_ray(above, so / dist));
      set.tmax.push_back(dist);
      light.push_back(std::uint32_t(j));
      self.push_back(shadow_self(w, h.prim));
    }
  }
  return set;
}

enum class spd_rays { eye, random, shadow };

// The scene's data, or null after marking the benchmark skipped (no ../shared, bad file).
const spd_data* spd_or_skip(benchmark::State& state, const std::string& name) {
  try {
    if (const spd_data* d = spd_scene(name)) return d;
    state.SkipWithError("no ../shared");
  } catch (const std::exception& e) {
    state.SkipWithError(e.what());
  }
  return nullptr;
}

void bm_spd(benchmark::State& state, std::string name, bool closest, spd_rays which) {
  const spd_data* d = spd_or_skip(state, name);
  if (!d) return;
  const ray_set& set = which == spd_rays::eye ? d->eye : which == spd_rays::random ? d->random : d->shadow;
  if (set.rays.empty()) {
    state.SkipWithError("no rays of this kind in the scene");
    return;
  }
  run_query(state, d->w, set, closest);
}

// The same shadow rays answered by interp and full modes' light cache (accel/light_cache.h),
// the BVH walking those its crowded cells leave; `listed%`: the share its lists answered.
void bm_light_cache(benchmark::State& state, std::string name) {
  const spd_data* d = spd_or_skip(state, name);
  if (!d) return;
  const light_cache lc(d->w);
  const ray_set& set = d->shadow;
  std::size_t hits = 0, listed = 0, at = 0;
  run_ray_set(state, set, [&](const ray& r, float tmax) {
    // run_ray_set walks the set in order, chunk after chunk: `at` follows it.
    const std::size_t i = at++ % set.rays.size();
    int b = lc.blocker(d->shadow_light[i], r, tmax, d->shadow_self[i]);
    if (b == light_cache::not_listed) b = first_blocker(d->w, r, tmax);
    else ++listed;
    benchmark::DoNotOptimize(b);
    hits += b >= 0;
  });
  const double done = double(state.iterations()) * double(chunk);
  state.counters["hit%"] = done > 0 ? 100.0 * double(hits) / done : 0.0;
  state.counters["listed%"] = done > 0 ? 100.0 * double(listed) / done : 0.0;
  state.counters["KB"] = double(lc.bytes()) / 1024;
}

void bm_whitted(benchmark::State& state, std::string name) {
  const spd_data* d = spd_or_skip(state, name);
  if (!d) return;
  trace_state st;
  run_ray_set(state, d->eye, [&](const ray& r, float) {
    vec3 c = trace_eye(d->w, r, st);
    benchmark::DoNotOptimize(c);
  });
  const ray_counts& n = st.counts;
  const double all = double(n.eye + n.reflect + n.refract + n.shadow);
  state.counters["rays/s"] = benchmark::Counter(all, benchmark::Counter::kIsRate);
  state.counters["rays/eye"] = n.eye ? all / double(n.eye) : 0.0;
  state.counters["prims"] = double(d->w.shapes.size());
}

std::vector<std::string> spd_names() {
  std::vector<std::string> names;
  const std::string dir = spd_dir();
  if (dir.empty()) return names;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == ".nff") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace

std::string spd_dir() {
  const char* env = std::getenv("EPSRAY_SPD_DIR");
  std::string dir = env && *env ? env : EPSRAY_SPD_DIR;
  std::error_code ec;
  return !dir.empty() && std::filesystem::is_directory(dir, ec) ? dir : std::string();
}

const spd_data* spd_scene(const std::string& name) {
  static std::map<std::string, std::unique_ptr<spd_data>> cache;
  auto it = cache.find(name);
  if (it != cache.end()) return it->second.get();
  const std::string dir = spd_dir();
  const std::filesystem::path file = std::filesystem::path(dir) / (name + ".nff");
  std::error_code ec;
  if (dir.empty() || !std::filesystem::is_regular_file(file, ec)) return nullptr;
  auto d = std::make_unique<spd_data>();
  d->w = make_world(load_scene(file.string()));
  d->eye = eye_rays(d->w.sc.view, 256, 256);
  d->random = random_rays(d->w.box, random_ray_count, 17);
  d->shadow = shadow_rays(d->w, d->eye, d->shadow_light, d->shadow_self);
  return (cache[name] = std::move(d)).get();
}

void register_bvh_benchmarks() {
  benchmark::RegisterBenchmark("bvh_build/spheres", bm_build, false)
      ->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("bvh_build/triangles", bm_build, true)
      ->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark("soup_closest_hit", bm_soup, true)
      ->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("soup_first_blocker", bm_soup, false)
      ->RangeMultiplier(10)->Range(100, 100000)->Unit(benchmark::kMicrosecond);

  std::vector<std::string> names = spd_names();
  if (names.empty()) names.push_back("none");  // registered anyway, to say why they are skipped
  for (const std::string& n : names) {
    auto add = [&](const char* query, const char* rays, bool closest, spd_rays which) {
      std::string full = std::string("spd_") + query + "/" + n + "/" + rays;
      benchmark::RegisterBenchmark(full.c_str(), bm_spd, n, closest, which)->Unit(benchmark::kMicrosecond);
    };
    add("closest_hit", "eye", true, spd_rays::eye);
    add("closest_hit", "random", true, spd_rays::random);
    add("first_blocker", "eye", false, spd_rays::eye);
    add("first_blocker", "random", false, spd_rays::random);
    add("first_blocker", "shadow", false, spd_rays::shadow);
    benchmark::RegisterBenchmark(("spd_light_cache/" + n + "/shadow").c_str(), bm_light_cache, n)
        ->Unit(benchmark::kMicrosecond);
  }
  for (const char* n : {"balls-s3", "teapot-s6"})
    benchmark::RegisterBenchmark((std::string("whitted/") + n).c_str(), bm_whitted, std::string(n))
        ->Unit(benchmark::kMillisecond);
}

}  // namespace epsray::micro
