// The frepcad subcommands. Each returns the process exit code: 0 success, 1 the mesh is not
// printable (export refused, check failed), 2 bad input (usage, unreadable or invalid file).
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace frep::cli {

using Args = std::vector<std::string>;

int exportCommand(const Args& args);
int checkCommand(const Args& args);
int infoCommand(const Args& args);
// `export DOC.FCStd ...`: runs the export inside FreeCAD, headless (document_export.cpp).
bool isDocumentPath(const std::string& path);
int exportDocument(const Args& args);

// Thrown for a usage error: main prints it as one line and exits 2.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double parseNumber(const std::string& text, const std::string& option);

}  // namespace frep::cli
