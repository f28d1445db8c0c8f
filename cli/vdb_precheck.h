// Untrusted .vdb files are read first in a child process. OpenVDB's reader trusts the sizes in
// a file's compressed leaves: a damaged one overruns its buffer and corrupts the heap (the
// process aborts in malloc). The child takes that crash; the command reports the file as
// damaged in one line.
#pragma once

#include <string>

namespace frep::cli {

// Reads `path` with readVdb in `frepcad __read-vdb PATH` and waits for it: returns when the
// child read it; throws FileError with the child's line, or naming the signal that ended it,
// or the time it ran past (30 s and a second for each 20 MB); Cancelled on Ctrl-C.
void readVdbInChild(const std::string& path);

// `frepcad __read-vdb PATH`, the child's side: readVdb in this process, without the check.
int readVdbAlone(const std::string& path);

}  // namespace frep::cli
