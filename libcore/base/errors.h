// Error types of libcore. Messages are complete sentences meant for the user: they name the
// object (node path or file), the parameter and what is allowed.
#pragma once

#include <stdexcept>
#include <string>

namespace frep {

// Invalid model: unknown node type, bad parameter, wrong number of inputs, bad JSON.
struct ModelError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A mesh estimated too large for the memory there is, refused before any work: a model
// error a caller may answer another way (frepcad points to --bricks).
struct TooLargeError : ModelError {
  using ModelError::ModelError;
};

// A valid model whose solid has no point inside: there is nothing to print. A verdict on the
// result, as a mesh that fails the check is, not a mistake in the input.
struct EmptySolidError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A file that cannot be read, parsed or written.
struct FileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Long work stopped on the caller's request.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace frep
