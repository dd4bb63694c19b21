// epsray: the command line of ../shared/spec/contract.md (docs/cli.md describes it).
#include <iostream>

#include "args.h"
#include "interrupt.h"
#include "render.h"
#include "scene/input_error.h"
#include "sched/topology.h"
#include "sched/workers.h"
#include "version.h"
#include "viewer/view.h"
#include "walk.h"

using namespace epsray;

namespace {

int run_info() {
  std::cout << "epsray " << epsray_version() << "\nhardware threads: " << hardware_threads() << "\n"
            << "topology (hwloc): " << discover_topology().summary() << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h" || args[0] == "help")) {
    // `epsray help walk` is `epsray walk --help`.
    std::cout << (args[0] == "help" && args.size() == 2 ? usage_text(args[1]) : usage_text());
    return 0;
  }
  if (!args.empty() && (args[0] == "--version" || args[0] == "version")) {
    std::cout << "epsray " << epsray_version() << "\n";
    return 0;
  }
  // Every message is one line: control characters in what the user gave (a file name
  // with a newline) are printed as C escapes.
  try {
    cli_options o = parse_args(args);
    if (o.help) {
      std::cout << usage_text(o.command);
      return 0;
    }
    if (o.command == "info") return run_info();
    if (o.command == "view") return run_view(o);  // the window's own keys end it
    catch_interrupts();
    return o.command == "walk" ? run_walk(o) : run_render(o);
  } catch (const input_error& e) {
    std::cerr << one_line(e) << "\n";
    return 2;
  } catch (const usage_error& e) {
    std::cerr << escape_controls(e.what()) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "epsray: " << escape_controls(e.what()) << "\n";
    return 1;
  }
}
