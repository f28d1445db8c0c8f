// frepcad reads each .vdb first in a child of its own (volume/vdb_reader_child.h says why).
#pragma once

#include <string>

namespace frep::cli {

// Reads `path` with readVdb in `frepcad __read-vdb PATH` (this executable) and waits for it;
// Cancelled on Ctrl-C.
void readVdbInChild(const std::string& path);

// `frepcad __read-vdb PATH`, the child's side: readVdb in this process, without the check.
int readVdbAlone(const std::string& path);

}  // namespace frep::cli
