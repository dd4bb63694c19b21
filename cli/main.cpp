// epsray: the command line of ../shared/spec/contract.md (docs/cli.md describes it).
#include <iostream>

#include "args.h"
#include "common.h"
#include "interrupt.h"
#include "ranks.h"
#include "render.h"
#include "sched/topology.h"
#include "sched/workers.h"
#include "version.h"
#include "viewer/view.h"
#include "walk.h"

using namespace epsray;

namespace {

int run_info() {
  std::cout << "epsray " << epsray_version() << "\nhardware threads: " << hardware_threads() << "\n"
            << "topology (hwloc): " << discover_topology().summary() << "\n"
            << "MPI: " << mpi_library() << "\n";
  return 0;
}

// Under mpirun every rank runs this; only rank 0 prints (the others' output would repeat it).
int run(const std::vector<std::string>& args) {
  const bool speaks = ranks().rank == 0;
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h" || args[0] == "help")) {
    // `epsray help walk` is `epsray walk --help`.
    if (speaks) std::cout << (args[0] == "help" && args.size() == 2 ? usage_text(args[1]) : usage_text());
    return 0;
  }
  if (!args.empty() && (args[0] == "--version" || args[0] == "version")) {
    if (speaks) std::cout << "epsray " << epsray_version() << "\n";
    return 0;
  }
  try {
    cli_options o = parse_args(args);
    if (o.help) {
      if (speaks) std::cout << usage_text(o.command);
      return 0;
    }
    if (ranks().size > 1 && !ranks().mpi)
      throw usage_error("epsray: started by mpirun with " + std::to_string(ranks().size) +
                        " ranks, but built without MPI: run it without mpirun (docs/mpi.md)");
    if (o.command == "info") return speaks ? run_info() : 0;
    if (ranks().size > 1 && o.command != "walk")
      throw usage_error("epsray: only walk runs over mpirun's ranks; run " + o.command +
                        " without mpirun or with -np 1 (docs/mpi.md)");
    if (o.command == "view") return run_view(o);  // the window's own keys end it
    catch_interrupts();
    return o.command == "walk" ? run_walk(o) : run_render(o);
  } catch (...) {
    std::string line;
    const int code = describe_error(std::current_exception(), line);
    if (speaks) std::cerr << line << "\n";
    return code;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Started by mpirun: MPI is initialised here and finalised when run returns.
  rank_session session(&argc, &argv);
  return run(std::vector<std::string>(argv + 1, argv + argc));
}
