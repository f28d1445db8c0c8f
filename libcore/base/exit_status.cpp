#include "base/exit_status.h"

#include <new>

#include "base/errors.h"

namespace frep {

Outcome outcomeOf(const std::exception_ptr& error, std::string* line) {
  std::string text;
  Outcome outcome = Outcome::InternalError;
  try {
    std::rethrow_exception(error);
  } catch (const Cancelled&) {
    text = "cancelled; nothing written";
    outcome = Outcome::Cancelled;
  } catch (const ModelError& e) {
    text = e.what();
    outcome = Outcome::BadInput;
  } catch (const FileError& e) {
    text = e.what();
    outcome = Outcome::BadInput;
  } catch (const std::bad_alloc&) {
    text = "out of memory; ask for less (a larger cell size, fewer cells or a smaller box)";
    outcome = Outcome::BadInput;
  } catch (const std::exception& e) {
    text = std::string("internal error (a bug: please report it): ") + e.what();
  } catch (...) {
    text = "internal error (a bug: please report it): an unknown exception";
  }
  if (line) *line = text;
  return outcome;
}

}  // namespace frep
