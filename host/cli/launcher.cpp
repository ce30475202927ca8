// The `romp` and `romp-bench` executables: launchers that start the program proper (ROMP_PROGRAM, beside
// the launcher) with OMP_WAIT_POLICY=passive where the user left it unset, so that idle OpenMP threads
// sleep rather than spin (host/backend_selection.h says why). libgomp reads the variable before main()
// runs, so it must be in the environment the program starts with; a program that set it and executed
// itself again would load LibTorch twice (0.3–0.6 s), where this launcher loads only libc.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#ifndef ROMP_PROGRAM
#error "ROMP_PROGRAM: the file name of the program this launcher starts"
#endif

int main(int, char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") == nullptr) {
    setenv("OMP_WAIT_POLICY", "passive", 1);
    setenv("ROMP_OPENMP_WAITS", "passive", 1);  // so that reports can tell romp's choice from the user's
  } else {
    unsetenv("ROMP_OPENMP_WAITS");  // a marker inherited from a parent romp no longer says who chose
  }
  // The program lives beside the launcher's own file (links resolved), wherever it is started from.
  std::string self(4096, '\0');
  const ssize_t length = readlink("/proc/self/exe", self.data(), self.size());
  if (length <= 0 || std::size_t(length) >= self.size()) {
    std::fprintf(stderr, "%s: cannot find its own executable: %s\n", argv[0], std::strerror(errno));
    return 1;
  }
  self.resize(std::size_t(length));
  const std::string program = self.substr(0, self.rfind('/') + 1) + ROMP_PROGRAM;
  execv(program.c_str(), argv);
  std::fprintf(stderr, "%s: cannot start %s: %s\n", argv[0], program.c_str(), std::strerror(errno));
  return 1;
}
