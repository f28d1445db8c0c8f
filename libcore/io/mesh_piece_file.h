// The file a brick job writes and the merge reads (docs/file-formats.md, "Brick pieces"):
// little-endian binary, a fixed header then the arrays, so reading is one pass with every
// count checked against the file's size before anything is allocated.
#pragma once

#include <string>

#include "base/mesh_piece.h"

namespace frep {

// Written atomically (temporary name, then rename). Throws FileError.
void writePieceFile(const MeshPiece& piece, const std::string& path);
// Throws FileError for a file that is not a piece, is truncated or inconsistent (counts
// beyond the file, a triangle naming a missing vertex, keys out of order).
MeshPiece readPieceFile(const std::string& path);

}  // namespace frep
