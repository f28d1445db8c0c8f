// How a process that does one job (the command-line tool, the benchmarks) takes memory from
// the system: one heap, never trimmed, in transparent huge pages (process_memory.cpp says why).
#pragma once

#include <cstddef>

namespace frep {

// The memory work may take now: MemAvailable from /proc/meminfo (bytes), 0 when unknown (no
// limit then). Exports, previews and repairs refuse work estimated to need more.
std::size_t availableMemory();

// Call first thing in main, before any large allocation. Not for long-running processes
// (FreeCAD, a Python session): freed memory stays with the process until it exits.
void useLargePageHeap();

}  // namespace frep
