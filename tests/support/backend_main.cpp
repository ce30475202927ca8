// main() for test binaries whose tests run on either backend: --backend=cpu|cuda picks the Exec;
// --backend=guarded is the CPU with device memory guarded (kernels/core/guarded_memory.h), so host
// code that touches it crashes here as it would on a GPU.
#include <gtest/gtest.h>

#include <iostream>
#include <string>

#include "kernels/core/device.h"
#include "kernels/core/guarded_memory.h"
#include "tests/support/test_exec.h"

namespace romp::test {
namespace {

Exec g_exec = Exec::cpu();

// ctest's SKIP_RETURN_CODE for the `gpu`-labelled entries: a --backend=cuda run on a machine where
// no CUDA device answers reports "skipped", never a vacuous pass.
constexpr int kSkipReturnCode = 77;

}  // namespace

const Exec& exec() { return g_exec; }

Exec exec_with_threads(int threads) {
  Exec exec = g_exec;
  exec.threads = threads;
  return exec;
}

}  // namespace romp::test

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  bool cuda = false;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (argument == "--backend=cuda") {
      cuda = true;
    } else if (argument == "--backend=guarded") {
      romp::memory::enable_guard();
    } else if (argument != "--backend=cpu") {
      std::cerr << "unknown argument '" << argument
                << "'; expected --backend=cpu, --backend=guarded or --backend=cuda\n";
      return 2;
    }
  }
  if (cuda && !::testing::GTEST_FLAG(list_tests)) {
    const romp::CudaProbe probe = romp::probe_cuda();
    if (probe.devices.empty()) {
      std::cout << "skipped: --backend=cuda but no CUDA device (" << probe.status << ")\n";
      return romp::test::kSkipReturnCode;
    }
    romp::test::g_exec = romp::Exec::cuda(probe.devices.front().ordinal);
    romp::set_cuda_device(romp::test::g_exec.device);
  }
  return RUN_ALL_TESTS();
}
