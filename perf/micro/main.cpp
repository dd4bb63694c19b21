// epsray_micro: registers the intersection and BVH benchmarks and runs Google Benchmark.
// Without --benchmark_min_time, each benchmark runs for at least 0.1 s, which keeps a run of
// the whole binary near half a minute (about 150 benchmarks, most of them over the SPD scenes).
// Per-benchmark MinTime is not used so that the command-line flag always wins.
#include <cstring>
#include <vector>

#include "bench_common.h"

int main(int argc, char** argv) {
  static char default_min_time[] = "--benchmark_min_time=0.1";
  std::vector<char*> args(argv, argv + argc);
  bool has_min_time = false;
  for (int i = 1; i < argc; ++i) has_min_time |= std::strncmp(argv[i], "--benchmark_min_time", 20) == 0;
  if (!has_min_time) args.insert(args.begin() + 1, default_min_time);
  int n = int(args.size());
  args.push_back(nullptr);

  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;

  const std::string dir = epsray::micro::spd_dir();
  benchmark::AddCustomContext("spd_dir", dir.empty() ? "(absent: spd_* and whitted/* skipped)" : dir);
  epsray::micro::register_intersect_benchmarks();
  epsray::micro::register_bvh_benchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
