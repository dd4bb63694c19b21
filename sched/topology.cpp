#include "topology.h"

#include <hwloc.h>

#include <cstdio>

namespace epsray {

namespace {

// A loaded hwloc topology, destroyed with its owner.
struct topo_handle {
  hwloc_topology_t t = nullptr;
  topo_handle() {
    if (hwloc_topology_init(&t) != 0 || hwloc_topology_load(t) != 0) {
      if (t) hwloc_topology_destroy(t);
      t = nullptr;
    }
  }
  ~topo_handle() {
    if (t) hwloc_topology_destroy(t);
  }
  int count(hwloc_obj_type_t type) const { return t ? std::max(0, hwloc_get_nbobjs_by_type(t, type)) : 0; }
};

std::string bytes_text(std::uint64_t b) {
  char s[32];
  if (b >= (1u << 20)) std::snprintf(s, sizeof s, "%.3g MiB", double(b) / (1 << 20));
  else std::snprintf(s, sizeof s, "%.3g KiB", double(b) / 1024);
  return s;
}

}  // namespace

machine_topology discover_topology() {
  topo_handle h;
  machine_topology m;
  if (!h.t) return m;
  m.packages = h.count(HWLOC_OBJ_PACKAGE);
  m.numa_nodes = h.count(HWLOC_OBJ_NUMANODE);
  m.cores = h.count(HWLOC_OBJ_CORE);
  m.pus = h.count(HWLOC_OBJ_PU);
  const hwloc_obj_type_t levels[] = {HWLOC_OBJ_L1CACHE, HWLOC_OBJ_L2CACHE, HWLOC_OBJ_L3CACHE};
  for (int i = 0; i < 3; ++i) {
    const int n = h.count(levels[i]);
    if (n <= 0) continue;
    hwloc_obj_t o = hwloc_get_obj_by_type(h.t, levels[i], 0);
    m.caches.push_back({i + 1, o && o->attr ? o->attr->cache.size : 0, n});
  }
  return m;
}

std::string machine_topology::summary() const {
  if (pus == 0) return "topology unknown (hwloc could not load it)";
  char s[160];
  std::snprintf(s, sizeof s, "%d package%s, %d NUMA node%s, %d core%s, %d hardware thread%s", packages,
                packages == 1 ? "" : "s", numa_nodes, numa_nodes == 1 ? "" : "s", cores, cores == 1 ? "" : "s", pus,
                pus == 1 ? "" : "s");
  std::string out = s;
  for (const cache& c : caches)
    out += "; L" + std::to_string(c.level) + " " + std::to_string(c.count) + " x " + bytes_text(c.bytes);
  return out;
}

struct core_pinning::impl {
  topo_handle h;
};

core_pinning::core_pinning() : impl_(std::make_unique<impl>()) {}
core_pinning::~core_pinning() = default;

int core_pinning::cores() const { return impl_->h.count(HWLOC_OBJ_CORE); }

bool core_pinning::pin_current_thread(int slot) {
  const int n = cores();
  if (n <= 0 || slot < 0) return false;
  hwloc_obj_t core = hwloc_get_obj_by_type(impl_->h.t, HWLOC_OBJ_CORE, unsigned(slot % n));
  if (!core || !core->cpuset) return false;
  return hwloc_set_cpubind(impl_->h.t, core->cpuset, HWLOC_CPUBIND_THREAD) == 0;
}

}  // namespace epsray
