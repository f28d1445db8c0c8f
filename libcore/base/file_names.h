// File names in messages. A name is bytes, not necessarily UTF-8 text: messages (and the JSON
// reports that carry them) show invalid bytes as \xNN so they stay valid UTF-8.
#pragma once

#include <string>

namespace frep {

std::string displayName(const std::string& path);

// Whether `path` names something that can be read as a file: a regular file, not a folder,
// FIFO (which would block the reader), socket or device. Throws FileError naming the path
// and what it is; `what` names the expected file ("the model file", "the mesh file").
void requireRegularFile(const std::string& path, const std::string& what);

}  // namespace frep
