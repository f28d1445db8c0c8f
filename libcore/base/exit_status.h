// What a command came to, and the exit status each outcome gives: frepcad's, and its Python
// children's (FreeCAD documents, brick runs), which take the numbers from frepcore's
// EXIT_STATUS (bound from this table) so that every path answers alike.
#pragma once

#include <exception>
#include <string>

namespace frep {

enum class Outcome {
  Done = 0,           // written (or checked) as asked
  NotPrintable = 1,   // the mesh is not printable: nothing written without --force
  BadInput = 2,       // a bad model, option or file: one line naming it and what is allowed
  InternalError = 3,  // a bug: please report it
  Cancelled = 130,    // Ctrl-C or SIGTERM (128 + SIGINT, as shells report it)
};

inline int exitStatus(Outcome outcome) {
  return static_cast<int>(outcome);
}

// `text` with every word (a run without spaces) over 200 characters cut to its first 80, its
// length and its last 3: a message that quotes a value of 100,000 characters stays one readable
// line.
std::string shortenedLongWords(const std::string& text);

// The outcome of the exception `error` and the one line that says it, long words shortened
// (without the program's name): ModelError and FileError are bad input, as is running out of memory
// (the line says to ask for less); an EmptySolidError is not printable; Cancelled is a cancel; any
// other exception is an internal error.
Outcome outcomeOf(const std::exception_ptr& error, std::string* line);

}  // namespace frep
