// Sweep members as child processes: manifest, claims, launching and waiting.
#include "host/run/sweep_runner.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "host/run/interrupt.h"
#include "host/run/process_rank.h"
#include "host/scene/scene_parser.h"
#include "host/scene/sweep.h"
#include "host/scene/toml_reader.h"
#include "nn/io/atomic_file.h"

extern char** environ;

namespace romp::run {
namespace {

namespace fs = std::filesystem;

std::string host_name() {
  char name[256] = {};
  gethostname(name, sizeof name - 1);
  return name;
}

// A member is claimed by creating its lock file exclusively; a lock left by a process of this host
// that no longer exists is stale and taken over. Locks on a shared folder keep two sweeps (or a
// sweep and a restarted one) from running a member twice.
bool claim(const fs::path& lock) {
  const std::string owner = fmt::format("{} {}", host_name(), getpid());
  for (int attempt = 0; attempt < 2; ++attempt) {
    const int fd = open(lock.c_str(), O_CREAT | O_EXCL | O_WRONLY, 0644);
    if (fd >= 0) {
      const bool written = write(fd, owner.data(), owner.size()) == ssize_t(owner.size());
      close(fd);
      if (!written) throw Error(fmt::format("cannot write the claim {}", lock.string()));
      return true;
    }
    if (errno != EEXIST)
      throw Error(fmt::format("cannot create the claim {}: {}", lock.string(), std::strerror(errno)));
    std::ifstream in(lock);
    std::string host;
    long pid = 0;
    in >> host >> pid;
    const bool stale = host == host_name() && pid > 0 && kill(pid_t(pid), 0) != 0 && errno == ESRCH;
    if (!stale) return false;
    spdlog::info("taking over the stale claim {} of process {}", lock.string(), pid);
    fs::remove(lock);
  }
  return false;
}

nlohmann::json manifest(const scene::Scene& base, const std::string& scene_path,
                        const std::vector<scene::SweepMember>& members) {
  const scene::SweepSpec& sweep = *base.sweep;
  nlohmann::json m;
  m["format"] = "romp-sweep";
  m["format_version"] = 1;
  m["scene"] = fs::absolute(scene_path).string();
  m["scene_name"] = base.name;
  m["method"] = sweep.method == scene::SweepMethod::Grid     ? "grid"
                : sweep.method == scene::SweepMethod::Random ? "random"
                                                             : "latin-hypercube";
  m["seed"] = sweep.seed;
  m["test_fraction"] = sweep.test_fraction;
  m["train_every"] = sweep.train_every;
  nlohmann::json names = nlohmann::json::array();
  for (const scene::SweepAxis& axis : sweep.axes) names.push_back(axis.parameter);
  m["parameters"] = names;
  nlohmann::json list = nlohmann::json::array();
  for (const scene::SweepMember& member : members) {
    const std::string stem = member_stem(member.index);
    list.push_back({{"index", member.index},
                    {"values", member.values},
                    {"split", member.test ? "test" : "train"},
                    {"snapshot", stem + ".h5"},
                    {"scene", "members/" + stem + ".toml"},
                    {"log", "logs/" + stem + ".log"}});
  }
  m["members"] = list;
  return m;
}

struct Child {
  std::int64_t index;
  fs::path lock, log;
};

pid_t spawn(const std::string& executable, const std::vector<std::string>& arguments, const fs::path& log) {
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  std::vector<char*> argv;
  for (const std::string& a : arguments) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int error = posix_spawn(&pid, executable.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw Error(fmt::format("cannot start {}: {}", executable, std::strerror(error)));
  return pid;
}

}  // namespace

std::string member_stem(std::int64_t index) { return fmt::format("member_{:06}", index); }

SweepSummary run_sweep(const std::string& scene_path, const SweepOptions& options) {
  const scene::Scene base = scene::load_scene(scene_path, options.overrides, options.laws);
  if (!base.sweep) throw scene::SceneError(fmt::format("{}: has no [sweep] table to run", scene_path));
  const std::vector<scene::SweepMember> members = scene::sweep_members(*base.sweep);
  for (const scene::SweepAxis& axis : base.sweep->axes)
    if (options.overrides.count(axis.parameter))
      throw scene::SceneError(fmt::format("--set {0}: {1} sweeps {0}; set only parameters the sweep leaves alone",
                                          axis.parameter, scene_path));
  const ProcessRank rank = detect_process_rank();
  const fs::path dir = options.output_dir;
  fs::create_directories(dir / "members");
  fs::create_directories(dir / "logs");

  // Every member's scene is resolved before anything runs, so a parameter value that makes a scene
  // invalid (e.g. a negative radius at the end of a range) stops the sweep at once.
  std::map<std::int64_t, std::string> member_scenes;
  for (const scene::SweepMember& member : members) {
    try {
      scene::ParameterValues values = options.overrides;
      values.insert(member.values.begin(), member.values.end());
      member_scenes[member.index] = scene::load_scene(scene_path, values, options.laws).resolved_text;
    } catch (const scene::SceneError& error) {
      throw scene::SceneError(fmt::format("sweep member {}: {}", member.index, error.what()));
    }
  }
  if (rank.rank == 0)
    io::write_file_atomically((dir / "manifest.json").string(), manifest(base, scene_path, members).dump(2) + "\n");

  SweepSummary summary;
  summary.members = std::int64_t(members.size());
  summary.rank = rank.rank;
  summary.ranks = rank.size;
  const std::string executable =
      options.executable.empty() ? fs::read_symlink("/proc/self/exe").string() : options.executable;
  install_interrupt_handler();

  // Progress over this rank's members: how many are done, how many run, and an ETA from this process's
  // throughput so far (members already finished before it started are not timed).
  const std::int64_t rank_members = std::count_if(
      members.begin(), members.end(), [&](const scene::SweepMember& m) { return m.index % rank.size == rank.rank; });
  const auto started = std::chrono::steady_clock::now();
  std::map<pid_t, Child> running;
  auto progress = [&] {
    const std::int64_t completed = summary.ran + std::int64_t(summary.failed.size());
    const std::int64_t done = summary.finished_before + completed;
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const std::int64_t left = rank_members - done - summary.busy_elsewhere;
    const std::string eta =
        completed == 0
            ? std::string("ETA after the first member")
            : fmt::format("ETA {:.0f} s", elapsed / double(completed) * double(std::max<std::int64_t>(left, 0)));
    return fmt::format("{}/{} done, {} running, {}", done, rank_members, running.size(), eta);
  };

  auto wait_one = [&] {
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) {
      if (errno == EINTR) return;
      throw Error(fmt::format("waitpid: {}", std::strerror(errno)));
    }
    const auto found = running.find(pid);
    if (found == running.end()) return;
    const Child child = found->second;
    running.erase(found);
    fs::remove(child.lock);
    const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    if (code == 0) {
      ++summary.ran;
      spdlog::info("member {} finished ({})", child.index, progress());
    } else {
      summary.failed.push_back(fmt::format("member {}: exit code {}, log {}", child.index, code, child.log.string()));
      spdlog::warn("{} ({})", summary.failed.back(), progress());
    }
  };

  for (const scene::SweepMember& member : members) {
    if (member.index % rank.size != rank.rank) continue;
    ++summary.assigned;
    const std::string stem = member_stem(member.index);
    const fs::path snapshot = dir / (stem + ".h5");
    if (fs::exists(snapshot)) {
      ++summary.finished_before;
      continue;
    }
    if (interrupt_requested()) break;
    while (int(running.size()) >= options.jobs) wait_one();
    const fs::path scene_file = dir / "members" / (stem + ".toml");
    io::write_file_atomically(scene_file.string(), member_scenes[member.index]);
    const fs::path lock = dir / (stem + ".lock");
    if (!claim(lock)) {
      ++summary.busy_elsewhere;
      continue;
    }
    std::vector<std::string> arguments{executable};
    arguments.insert(arguments.end(), options.run_arguments.begin(), options.run_arguments.end());
    for (const char* a : {"run", "--resume", "--no-progress", "-o"}) arguments.emplace_back(a);
    arguments.push_back(snapshot.string());
    arguments.push_back(scene_file.string());
    const fs::path log = dir / "logs" / (stem + ".log");
    try {
      running[spawn(executable, arguments, log)] = Child{member.index, lock, log};
    } catch (...) {
      fs::remove(lock);
      throw;
    }
    spdlog::info("member {} started ({})", member.index, progress());
  }
  while (!running.empty()) wait_one();
  return summary;
}

}  // namespace romp::run
