// File names in messages. A name is bytes, not necessarily UTF-8 text: messages (and the JSON
// reports that carry them) show invalid bytes as \xNN so they stay valid UTF-8.
#pragma once

#include <cstdint>
#include <string>

namespace frep {

std::string displayName(const std::string& path);

// The extension of the file name (the last part of the path), lower case and without the dot;
// "" when the name has none. "a.b/c" has none: a folder's dot is not the file's.
std::string fileExtension(const std::string& path);

// Whether `path` names an OpenVDB file (.vdb, in any case).
bool isVdbPath(const std::string& path);

// Whether `path` names something that can be read as a file: a regular file, not a folder,
// FIFO (which would block the reader), socket or device. Throws FileError naming the path
// and what it is; `what` names the expected file ("the model file", "the mesh file").
void requireRegularFile(const std::string& path, const std::string& what);

// The whole of a small text file (a model, a lattice), refused with a FileError naming it when
// it is not a regular file, larger than maxBytes (before anything is read) or unreadable.
// `kind` names it in messages: "model file" gives "the model file", "a model file".
std::string readSmallFile(const std::string& path, const std::string& kind, std::uint64_t maxBytes);

}  // namespace frep
