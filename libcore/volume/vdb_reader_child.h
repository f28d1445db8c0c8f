// Untrusted .vdb files are read first by a helper process. OpenVDB's reader trusts the sizes in
// a file's compressed leaves: a damaged one overruns its buffer and corrupts the heap (the
// process aborts in malloc). The helper takes that crash; the caller reports the file as
// damaged in one line instead of dying with it (frepcad, or FreeCAD through frepcore).
#pragma once

#include <functional>
#include <string>

namespace frep {

// Runs `helper __read-vdb PATH` (frepcad: it reads the file with readVdb and exits) and waits
// for it: returns when the helper read it; throws FileError with the helper's line, or naming
// the signal that ended it, or the time it ran past (30 s and a second for each 20 MB), and
// Cancelled when `cancelled` (may be empty) says so.
void readVdbInHelper(const std::string& helper, const std::string& path,
                     const std::function<bool()>& cancelled);

}  // namespace frep
