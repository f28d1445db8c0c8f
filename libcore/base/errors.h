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

// A file that cannot be read, parsed or written.
struct FileError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Long work stopped on the caller's request.
struct Cancelled : std::runtime_error {
  Cancelled() : std::runtime_error("cancelled") {}
};

}  // namespace frep
