// A binary that links LibTorch calls the system's standard library and one OpenMP runtime, whichever
// LibTorch it was built against. PyTorch's wheel exports its own copies of std::filesystem from
// libtorch.so and libtorch_cpu.so and ships its own libgomp: bound to those copies, every file
// operation of romp crashed (the SceneRunner, SweepRunner, law and ROM trainer tests on the H200).
#include <dlfcn.h>
#include <link.h>

#include <gtest/gtest.h>
#include <omp.h>
#include <torch/torch.h>

#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace romp {
namespace {

// The file name of the shared object whose code `function` is, as the loader bound it.
std::string defining_object(const void* function) {
  Dl_info info{};
  if (dladdr(function, &info) == 0 || info.dli_fname == nullptr) return "(unknown)";
  return info.dli_fname;
}

// The loaded shared objects whose path contains `part`.
struct NameSearch {
  std::string part;
  std::vector<std::string> found;
};
std::vector<std::string> loaded_objects_named(const std::string& part) {
  NameSearch search{part, {}};
  dl_iterate_phdr(
      [](dl_phdr_info* info, std::size_t, void* data) {
    NameSearch& s = *static_cast<NameSearch*>(data);
    const std::string name = info->dlpi_name != nullptr ? info->dlpi_name : "";
    if (name.find(s.part) != std::string::npos) s.found.push_back(name);
    return 0;
      },
      &search);
  return search.found;
}

TEST(RuntimeLibraries, StdFilesystemIsTheSystemLibstdcxxs) {
  using RemoveAll = std::uintmax_t (*)(const std::filesystem::path&, std::error_code&);
  using CreateDirectories = bool (*)(const std::filesystem::path&);
  using Rename = void (*)(const std::filesystem::path&, const std::filesystem::path&);
  const RemoveAll remove_all = &std::filesystem::remove_all;
  const CreateDirectories create_directories = &std::filesystem::create_directories;
  const Rename rename = &std::filesystem::rename;
  const std::vector<const void*> functions = {reinterpret_cast<const void*>(remove_all),
                                              reinterpret_cast<const void*>(create_directories),
                                              reinterpret_cast<const void*>(rename)};
  for (const void* function : functions) {
    const std::string object = defining_object(function);
    EXPECT_NE(object.find("libstdc++"), std::string::npos) << "std::filesystem bound to " << object;
  }
  // And it works: a folder made and removed through those calls.
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "romp_runtime_libraries_test";
  std::error_code error;
  std::filesystem::remove_all(folder, error);
  ASSERT_TRUE(std::filesystem::create_directories(folder / "a" / "b"));
  EXPECT_EQ(std::filesystem::remove_all(folder, error), 3u) << error.message();
}

TEST(RuntimeLibraries, OneOpenMpRuntimeServesRompAndLibTorch) {
  // LibTorch's parallel loops and romp's share one libgomp (two would each start a thread pool and
  // spin against each other).
  EXPECT_EQ(loaded_objects_named("libgomp").size(), 1u);
  EXPECT_GE(omp_get_max_threads(), 1);
  EXPECT_GE(torch::get_num_threads(), 1);
}

}  // namespace
}  // namespace romp
