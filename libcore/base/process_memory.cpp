// A one-job process's memory policy (the command-line tool, the benchmarks). On the virtual
// machines FRepCAD runs on (and is benchmarked on), the first touch of each fresh 4 KiB page costs
// about 11 microseconds: a 64 MiB buffer takes 0.19 s to fault in, as long as meshing a model at
// 256 cells. An export allocates and frees hundreds of MiB (the mesher's bricks, the check's
// tables), and glibc hands large blocks back to the system on free, so each phase faults its memory
// in again. Three settings, made once before any work:
//  - one heap, grown by brk, for every block and every thread (no mmap per large block,
//    no per-thread arenas): freed memory is reused by the next phase without new faults;
//  - the heap is never trimmed (the tool exits when its one job is done);
//  - a reserve at the top of the heap is marked for transparent huge pages (madvise; the
//    system's default is "madvise"), so memory comes in 2 MiB pages: 512 times fewer
//    faults.
// The Python module does not do this: FreeCAD is a long-running process whose memory must
// go back to the system.
#include "base/process_memory.h"

#include <malloc.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <string>

namespace frep {

std::size_t availableMemory() {
  std::ifstream in("/proc/meminfo");
  std::string key;
  std::size_t kib = 0;
  while (in >> key) {
    if (key == "MemAvailable:") {
      in >> kib;
      return kib * 1024;
    }
    in.ignore(1 << 12, '\n');
  }
  return 0;
}

void useLargePageHeap() {
  const long pages = sysconf(_SC_PHYS_PAGES), pageSize = sysconf(_SC_PAGESIZE);
  if (pages <= 0 || pageSize <= 0) return;
  // The reserve: a quarter of the machine's memory, at most 2 GiB (M_TOP_PAD is an int).
  const std::uint64_t physical =
      static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(pageSize);
  const std::uint64_t reserve = std::min<std::uint64_t>(physical / 4, 2047ull << 20);
  mallopt(M_ARENA_MAX, 1);
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, -1);  // (-1: never trim)
  mallopt(M_TOP_PAD, static_cast<int>(reserve));
  // Grow the heap once (by the reserve), mark the new part for huge pages, and go back to
  // glibc's usual padding for any growth beyond it (in 4 KiB pages: a job past the reserve
  // is large enough that the faults are a small share of it).
  char* const before = static_cast<char*>(sbrk(0));
  // (more than the heap has free, so it grows; volatile, or the compiler drops the pair)
  void* volatile probe = std::malloc(64 << 20);
  char* const after = static_cast<char*>(sbrk(0));
  mallopt(M_TOP_PAD, 128 << 10);
  const std::uintptr_t huge = 2u << 20;
  const std::uintptr_t from = (reinterpret_cast<std::uintptr_t>(before) + huge - 1) & ~(huge - 1);
  const std::uintptr_t to = reinterpret_cast<std::uintptr_t>(after) & ~(huge - 1);
  if (to > from) madvise(reinterpret_cast<void*>(from), to - from, MADV_HUGEPAGE);
  std::free(probe);
}

}  // namespace frep
