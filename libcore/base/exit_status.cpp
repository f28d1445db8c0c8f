#include "base/exit_status.h"

#include <cctype>
#include <new>

#include "base/errors.h"

namespace frep {

std::string shortenedLongWords(const std::string& text) {
  constexpr std::size_t kLongest = 200, kKept = 80;
  std::string out;
  std::size_t i = 0;
  while (i < text.size()) {
    std::size_t end = i;
    while (end < text.size() && !std::isspace(static_cast<unsigned char>(text[end]))) ++end;
    if (end - i > kLongest)
      // (its last characters kept too: the quote and punctuation that close it)
      out += text.substr(i, kKept) + "... (" + std::to_string(end - i) + " characters) ..." +
             text.substr(end - 3, 3);
    else
      out.append(text, i, end - i);
    i = end;
    while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) out += text[i++];
  }
  return out;
}

Outcome outcomeOf(const std::exception_ptr& error, std::string* line) {
  std::string text;
  Outcome outcome = Outcome::InternalError;
  try {
    std::rethrow_exception(error);
  } catch (const Cancelled&) {
    text = "cancelled; nothing written";
    outcome = Outcome::Cancelled;
  } catch (const EmptySolidError& e) {
    text = e.what();
    outcome = Outcome::NotPrintable;
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
  if (line) *line = shortenedLongWords(text);
  return outcome;
}

}  // namespace frep
