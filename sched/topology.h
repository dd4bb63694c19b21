// The machine as hwloc sees it (packages, NUMA nodes, cores, hardware threads, caches),
// for `epsray info`, benchmark output, and pinning worker threads to cores.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace epsray {

struct machine_topology {
  int packages = 0, numa_nodes = 0, cores = 0, pus = 0;
  struct cache {
    int level = 0;
    std::uint64_t bytes = 0;
    int count = 0;  // how many of them
  };
  std::vector<cache> caches;  // data and unified caches, one entry per level
  std::string summary() const;  // one line
};

machine_topology discover_topology();

// Binds each thread that joins an arena to its own core, round-robin over the cores by
// the thread's slot in the arena. Pinning changes where threads run, never what they
// compute: images stay the same.
class core_pinning {
 public:
  core_pinning();
  ~core_pinning();
  core_pinning(const core_pinning&) = delete;
  core_pinning& operator=(const core_pinning&) = delete;
  // Pins the calling thread to core (slot mod cores); false when hwloc cannot bind here.
  bool pin_current_thread(int slot);
  int cores() const;

 private:
  struct impl;
  std::unique_ptr<impl> impl_;
};

}  // namespace epsray
