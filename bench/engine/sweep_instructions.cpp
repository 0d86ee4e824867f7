// Runs S sub-steps (10 sweeps each) of the serial reference or the colored solver on one thread over an N×N cloth
// (cloth_fixture.hpp) and exits: the program scripts/count_instructions runs under callgrind, where instruction
// counts repeat exactly, whatever else the machine is doing. Usage: sweep_instructions serial|colored N S
#include "cloth_fixture.hpp"

#include <oneapi/tbb/task_arena.h>

#include <cstdio>
#include <cstdlib>
#include <string>

int main(int argc, char** argv) {
  using namespace pbd::bench;
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s serial|colored N SUBSTEPS\n", argv[0]);
    return 2;
  }
  const std::string solver = argv[1];
  const int n = std::atoi(argv[2]), substeps = std::atoi(argv[3]);
  if ((solver != "serial" && solver != "colored") || n < 2 || substeps < 0) {
    std::fprintf(stderr, "%s: expected serial|colored, N >= 2, SUBSTEPS >= 0\n", argv[0]);
    return 2;
  }
  ClothFixture f(n, solver == "serial" ? pbd::Solver::serial : pbd::Solver::colored);
  tbb::task_arena(1).execute([&] {
    for (int s = 0; s < substeps; ++s) f.substep();
  });
  std::printf("%zu constraints, %d sweeps per sub-step, first position %.9g\n", f.constraints(), kSweeps,
              double(f.p()(0, f.p().cols() - 1)));
  return 0;
}
