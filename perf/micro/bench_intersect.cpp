// Ray-primitive intersection throughput, one benchmark per shape kind: the inline hit_*
// routines of geom/shapes.h called directly ("intersect/<kind>") and through the tag switch
// of hit_shape ("intersect_dispatch/<kind>", plus "mixed": every kind interleaved at random).
//
// Each case holds 64 shapes of its kind (random size, place and orientation, built from NFF
// primitives by make_shape like a real scene) and 4096 rays, each paired with one shape.
// Exactly half the rays hit their shape, in a shuffled order, so the hit/miss branch cannot be
// predicted; the misses are whatever a ray aimed near the shape's box gives (early outs and
// near misses alike). One item is one intersection test.
#include <array>
#include <limits>
#include <memory>
#include <stdexcept>

#include "bench_common.h"
#include "geom/shape_build.h"
#include "geom/shapes.h"

namespace epsray::micro {
namespace {

constexpr int shapes_per_case = 64;
constexpr int rays_per_case = 4096;
constexpr float no_limit = std::numeric_limits<float>::infinity();

enum class test_kind { sphere, triangle, polygon, cone, cylinder, disk, box };

struct shape_case {
  const char* name;
  test_kind kind;
  int vertices;  // polygons only
};

constexpr std::array<shape_case, 9> cases{{
    {"sphere", test_kind::sphere, 0},
    {"triangle", test_kind::triangle, 3},
    {"polygon4", test_kind::polygon, 4},
    {"polygon32", test_kind::polygon, 32},
    {"polygon128", test_kind::polygon, 128},
    {"cone", test_kind::cone, 0},
    {"cylinder", test_kind::cylinder, 0},
    {"disk", test_kind::disk, 0},
    {"box", test_kind::box, 0},
}};

struct frame3 {
  vec3 u, v, n;
};

frame3 random_frame(rng& g) {
  vec3 n = g.direction();
  vec3 t = std::fabs(n.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0);
  vec3 u = glm::normalize(glm::cross(n, t));
  return {u, glm::cross(n, u), n};
}

// One NFF primitive of the case, about unit size near the origin; polygon vertices go to s.
primitive random_primitive(const shape_case& c, rng& g, scene& s) {
  primitive p;
  const vec3 centre = g.in_box(vec3(-0.5f), vec3(0.5f));
  const frame3 f = random_frame(g);
  switch (c.kind) {
    case test_kind::sphere:
      p.kind = prim_kind::sphere;
      p.a = centre;
      p.r0 = g.uniform(0.5f, 1.0f);
      break;
    case test_kind::triangle:
    case test_kind::polygon: {
      // Triangles: three random points on a sphere. n-gons (n > 4): a star, alternating
      // radii, so the even-odd walk meets a concave outline as SPD's gears do.
      p.kind = prim_kind::polygon;
      p.first = int(s.vertices.size());
      p.count = c.vertices;
      const float phase = g.uniform(0, 6.2831853f);
      for (int i = 0; i < c.vertices; ++i) {
        if (c.kind == test_kind::triangle) {
          s.vertices.push_back(centre + 0.9f * g.direction());
          continue;
        }
        float a = phase + 6.2831853f * float(i) / float(c.vertices);
        float r = (c.vertices > 4 && (i & 1)) ? 0.65f : 0.9f;
        s.vertices.push_back(centre + r * (std::cos(a) * f.u + std::sin(a) * f.v));
      }
      break;
    }
    case test_kind::cone:
    case test_kind::cylinder: {
      p.kind = prim_kind::cone;
      const float h = g.uniform(1.0f, 1.6f);
      p.a = centre - 0.5f * h * f.n;
      p.b = centre + 0.5f * h * f.n;
      p.r0 = c.kind == test_kind::cone ? 0.7f : 0.5f;
      p.r1 = c.kind == test_kind::cone ? 0.2f : 0.5f;
      break;
    }
    case test_kind::disk:
      p.kind = prim_kind::disk;
      p.a = centre;
      p.b = f.n;
      p.r0 = g.uniform(0.6f, 1.0f);
      break;
    case test_kind::box:
      p.kind = prim_kind::box;
      p.a = centre;
      p.b = g.in_box(vec3(0.3f), vec3(0.8f));
      p.frame = glm::mat3(f.u, f.v, f.n);
      break;
  }
  return p;
}

struct intersect_set {
  std::vector<shape> shapes;
  polygon_data polys;
  std::vector<ray> rays;
  std::vector<std::uint16_t> target;  // rays[i] is tested against shapes[target[i]]
};

// Fills `set` from the primitives of `s`: rays paired with random shapes, half of them hits.
void aim_rays(const scene& s, rng& g, intersect_set& set) {
  for (const primitive& p : s.prims) set.shapes.push_back(make_shape(s, p, set.polys));
  std::vector<char> wanted(rays_per_case);
  for (int i = 0; i < rays_per_case; ++i) wanted[size_t(i)] = i < rays_per_case / 2;
  for (int i = rays_per_case - 1; i > 0; --i) std::swap(wanted[size_t(i)], wanted[g.next() % std::uint32_t(i + 1)]);
  for (int i = 0; i < rays_per_case; ++i) {
    const std::uint16_t j = std::uint16_t(g.next() % std::uint32_t(set.shapes.size()));
    const bounds b = primitive_bounds(s, s.prims[j]);
    const vec3 c = b.centre(), half = 0.6f * b.extent() + vec3(0.15f);  // flat shapes get depth
    for (int attempt = 0;; ++attempt) {
      if (attempt == 100000) throw std::runtime_error("cannot aim a ray at a benchmark shape");
      const vec3 o = c + 4.0f * g.direction();
      const ray r = make_ray(o, glm::normalize(g.in_box(c - half, c + half) - o));
      float t;
      if (hit_shape(set.shapes[j], set.polys, r, no_limit, t) == bool(wanted[size_t(i)])) {
        set.rays.push_back(r);
        set.target.push_back(j);
        break;
      }
    }
  }
}

std::shared_ptr<intersect_set> make_case(const shape_case& c) {
  rng g(seed, std::uint64_t(&c - cases.data()) + 1);
  scene s;
  for (int i = 0; i < shapes_per_case; ++i) s.prims.push_back(random_primitive(c, g, s));
  auto set = std::make_shared<intersect_set>();
  aim_rays(s, g, *set);
  return set;
}

std::shared_ptr<intersect_set> make_mixed() {
  rng g(seed, 100);
  scene s;
  for (const shape_case& c : cases)
    for (int i = 0; i < shapes_per_case; ++i) s.prims.push_back(random_primitive(c, g, s));
  auto set = std::make_shared<intersect_set>();
  aim_rays(s, g, *set);
  return set;
}

template <class Hit>
void run_intersect(benchmark::State& state, const intersect_set& set, Hit&& hit) {
  const shape* shapes = set.shapes.data();
  for (auto _ : state) {
    for (std::size_t i = 0; i < set.rays.size(); ++i) {
      float t = 0;
      bool h = hit(shapes[set.target[i]], set.rays[i], t);
      benchmark::DoNotOptimize(h);
      benchmark::DoNotOptimize(t);
    }
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(set.rays.size()));
}

// The routine the BVH leaf would reach after the switch, called without it.
void bm_direct(benchmark::State& state, std::shared_ptr<intersect_set> set, test_kind kind) {
  const polygon_data& polys = set->polys;
  switch (kind) {
    case test_kind::sphere:
      return run_intersect(state, *set, [](const shape& s, const ray& r, float& t) {
        return hit_sphere(s.sphere, r, no_limit, t);
      });
    case test_kind::triangle:
      return run_intersect(state, *set, [](const shape& s, const ray& r, float& t) {
        return hit_triangle(s.tri, r, no_limit, t);
      });
    case test_kind::polygon:
      return run_intersect(state, *set, [&polys](const shape& s, const ray& r, float& t) {
        return hit_polygon(s.poly, polys, r, no_limit, t);
      });
    case test_kind::cone:
    case test_kind::cylinder:
      return run_intersect(state, *set, [](const shape& s, const ray& r, float& t) {
        return hit_cone(s.cone, r, no_limit, t);
      });
    case test_kind::disk:
      return run_intersect(state, *set, [](const shape& s, const ray& r, float& t) {
        return hit_disk(s.disk, r, no_limit, t);
      });
    case test_kind::box:
      return run_intersect(state, *set, [](const shape& s, const ray& r, float& t) {
        return hit_box(s.box, r, no_limit, t);
      });
  }
}

void bm_dispatch(benchmark::State& state, std::shared_ptr<intersect_set> set) {
  const polygon_data& polys = set->polys;
  run_intersect(state, *set, [&polys](const shape& s, const ray& r, float& t) {
    return hit_shape(s, polys, r, no_limit, t);
  });
}

}  // namespace

void register_intersect_benchmarks() {
  for (const shape_case& c : cases) {
    auto set = make_case(c);
    benchmark::RegisterBenchmark((std::string("intersect/") + c.name).c_str(), bm_direct, set, c.kind);
  }
  for (const shape_case& c : cases)
    benchmark::RegisterBenchmark((std::string("intersect_dispatch/") + c.name).c_str(), bm_dispatch, make_case(c));
  benchmark::RegisterBenchmark("intersect_dispatch/mixed", bm_dispatch, make_mixed());
}

}  // namespace epsray::micro
