// Shared pieces of the micro-benchmarks: a fixed-seed generator, random geometry, and the
// ray sets that every traversal benchmark walks in fixed-size chunks.
#pragma once
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "accel/world.h"
#include "geom/ray.h"
#include "scene/camera.h"
#include "scene/scene.h"

namespace epsray::micro {

// PCG32 (O'Neill): the same numbers on every platform, unlike std::uniform_*_distribution.
struct rng {
  std::uint64_t state, inc;
  explicit rng(std::uint64_t seed, std::uint64_t stream = 54) : state(0), inc((stream << 1) | 1) {
    next();
    state += seed;
    next();
  }
  std::uint32_t next() {
    std::uint64_t old = state;
    state = old * 6364136223846793005ULL + inc;
    std::uint32_t x = std::uint32_t(((old >> 18) ^ old) >> 27), rot = std::uint32_t(old >> 59);
    return (x >> rot) | (x << ((32 - rot) & 31));
  }
  float uniform() { return float(next() >> 8) * 0x1p-24f; }  // [0, 1)
  float uniform(float lo, float hi) { return lo + (hi - lo) * uniform(); }
  vec3 in_box(vec3 lo, vec3 hi) { return {uniform(lo.x, hi.x), uniform(lo.y, hi.y), uniform(lo.z, hi.z)}; }
  vec3 direction() {  // uniform on the unit sphere
    float z = uniform(-1, 1), phi = uniform(0, 6.2831853f), s = std::sqrt(std::max(0.0f, 1 - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
  }
};

constexpr std::uint64_t seed = 20240611;

// A traversal workload: rays with their tmax, walked `chunk` rays per benchmark iteration so
// that an iteration stays short even on the heaviest scene. Every chunk is a fair sample of
// the whole set (eye rays are stored as interleaved rows, see eye_rays).
struct ray_set {
  std::vector<ray> rays;
  std::vector<float> tmax;
};
constexpr std::size_t chunk = 4096;

// Eye rays of the scene's own camera at width x height, one row at a time (coherent), with
// the rows interleaved: chunk k holds rows k, k + 16, k + 32, ... when width * 16 = chunk.
ray_set eye_rays(const camera_view& view, int width, int height);
// Origins uniform in `box`, directions uniform on the sphere, tmax infinite (incoherent).
ray_set random_rays(const bounds& box, std::size_t n, std::uint64_t s);

// Runs `body(ray, tmax)` over the set, `chunk` rays per iteration, and reports rays as items.
template <class Body>
void run_ray_set(benchmark::State& state, const ray_set& set, Body&& body) {
  const std::size_t n = set.rays.size();
  std::size_t at = 0, done = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < chunk; ++i) {
      body(set.rays[at], set.tmax[at]);
      if (++at == n) at = 0;
    }
    done += chunk;
  }
  state.SetItemsProcessed(std::int64_t(done));
}

// Where the SPD scenes live: $EPSRAY_SPD_DIR, else the compile-time default; "" when absent.
std::string spd_dir();

// An SPD scene with its ray sets, loaded on first use and kept for the whole run.
struct spd_data {
  world w;
  ray_set eye;     // 256x256 eye rays of the scene's camera, tmax infinite
  ray_set random;  // 65536 random rays from inside the scene's box, tmax infinite
  ray_set shadow;  // the shadow rays trace_eye casts from the eye rays' first hits
  std::vector<std::uint32_t> shadow_light;  // each shadow ray's light
  std::vector<int> shadow_self;  // the flat primitive it leaves (-1: none), as whitted.cpp passes it
};
// Null when the scene file is absent.
const spd_data* spd_scene(const std::string& name);

// Registered from main: the intersection cases and the SPD list are built at run time.
void register_intersect_benchmarks();
void register_bvh_benchmarks();

}  // namespace epsray::micro
