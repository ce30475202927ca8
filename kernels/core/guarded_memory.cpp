// Guarded CPU memory: one reserved arena of pages, protected (PROT_NONE) except while a DeviceAccess
// is alive, so a whole launch opens and closes it with one mprotect each.
#include "kernels/core/guarded_memory.h"

#include <execinfo.h>
#include <signal.h>
#include <sys/mman.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <map>
#include <mutex>

#include "kernels/core/error.h"
#include "kernels/core/memory.h"

namespace romp::memory {
namespace {

// Address space reserved (not memory: untouched pages cost nothing, MAP_NORESERVE commits none).
constexpr std::size_t kArenaBytes = std::size_t(64) << 30;

struct Arena {
  std::mutex mutex;
  char* base = nullptr;
  std::size_t page = 4096;
  std::size_t high_water = 0;              // bytes handed out from base, the extent open() changes
  int open_count = 0;                      // live DeviceAccess objects
  std::map<char*, std::size_t> blocks;     // live blocks and their sizes in bytes (page multiples)
  std::multimap<std::size_t, char*> idle;  // released blocks by size, reused best fit

  void protect(char* begin, std::size_t bytes, bool open) const {
    if (bytes == 0) return;
    ROMP_CHECK(mprotect(begin, bytes, open ? PROT_READ | PROT_WRITE : PROT_NONE) == 0,
               std::string("guarded memory: mprotect failed: ") + std::strerror(errno));
  }
};

Arena& arena() {
  static Arena instance;
  return instance;
}

std::atomic<bool> g_enabled{false};
struct sigaction g_previous_handler {};

// A touch of the arena outside a DeviceAccess: say what it means, then let the fault take its course.
void on_fault(int signal, siginfo_t* info, void* context) {
  const Arena& a = arena();
  const char* address = static_cast<const char*>(info->si_addr);
  if (a.base != nullptr && address >= a.base && address < a.base + kArenaBytes) {
    char message[256];
    const int length = std::snprintf(message, sizeof message,
                                     "\nromp guarded memory: host code touched device memory at %p outside a kernel "
                                     "launch or transfer (on a GPU this read or write would fail). Backtrace:\n",
                                     info->si_addr);
    if (length > 0) (void)!::write(STDERR_FILENO, message, std::size_t(length));
    void* frames[64];
    backtrace_symbols_fd(frames, backtrace(frames, 64), STDERR_FILENO);
  }
  // Returning re-runs the faulting instruction under the handler that was there before (the default
  // one ends the process with SIGSEGV, as ctest expects of a crash).
  if (g_previous_handler.sa_flags & SA_SIGINFO) {
    sigaction(signal, &g_previous_handler, nullptr);
  } else {
    ::signal(signal, g_previous_handler.sa_handler == SIG_IGN ? SIG_DFL : g_previous_handler.sa_handler);
  }
  (void)context;
}

}  // namespace

void enable_guard() {
  Arena& a = arena();
  const std::lock_guard<std::mutex> lock(a.mutex);
  if (g_enabled.load()) return;
  a.page = std::size_t(sysconf(_SC_PAGESIZE));
  void* base = mmap(nullptr, kArenaBytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE, -1, 0);
  ROMP_CHECK(base != MAP_FAILED, std::string("guarded memory: cannot reserve the arena: ") + std::strerror(errno));
  a.base = static_cast<char*>(base);
  struct sigaction handler {};
  handler.sa_sigaction = on_fault;
  handler.sa_flags = SA_SIGINFO;
  sigemptyset(&handler.sa_mask);
  sigaction(SIGSEGV, &handler, &g_previous_handler);
  g_enabled.store(true);
}

bool guard_enabled() { return g_enabled.load(std::memory_order_relaxed); }

DeviceAccess::DeviceAccess() : counted_(guard_enabled()) {
  refuse_in_capture("a host touch of device memory");
  if (!counted_) return;
  Arena& a = arena();
  const std::lock_guard<std::mutex> lock(a.mutex);
  if (a.open_count++ == 0) a.protect(a.base, a.high_water, true);
}

DeviceAccess::~DeviceAccess() {
  if (!counted_) return;
  Arena& a = arena();
  const std::lock_guard<std::mutex> lock(a.mutex);
  if (--a.open_count == 0) a.protect(a.base, a.high_water, false);
}

namespace guarded {

void* allocate(std::size_t bytes) {
  Arena& a = arena();
  const std::lock_guard<std::mutex> lock(a.mutex);
  const std::size_t size = (bytes + a.page - 1) / a.page * a.page;
  // Best fit among released blocks, if it wastes no more than the request itself.
  const auto reuse = a.idle.lower_bound(size);
  if (reuse != a.idle.end() && reuse->first <= 2 * size) {
    char* block = reuse->second;
    a.blocks.emplace(block, reuse->first);
    a.idle.erase(reuse);
    return block;
  }
  if (a.high_water + size > kArenaBytes) return nullptr;
  char* block = a.base + a.high_water;
  a.high_water += size;
  if (a.open_count > 0) a.protect(block, size, true);  // new pages take the arena's current state
  a.blocks.emplace(block, size);
  return block;
}

bool release(void* pointer) noexcept {
  Arena& a = arena();
  char* block = static_cast<char*>(pointer);
  if (a.base == nullptr || block < a.base || block >= a.base + kArenaBytes) return false;
  const std::lock_guard<std::mutex> lock(a.mutex);
  const auto found = a.blocks.find(block);
  if (found == a.blocks.end()) return true;      // not a block start: nothing to free, as free() would crash
  madvise(block, found->second, MADV_DONTNEED);  // give the memory back; the address range stays reserved
  a.idle.emplace(found->second, block);
  a.blocks.erase(found);
  return true;
}

}  // namespace guarded
}  // namespace romp::memory
