// .hs files: FRepCAD's text format for an hspline's hierarchy (docs/file-formats.md, ".hs").
// Version 1:
//
//   hspline 1
//   axis u periodic 8 8.0        axis <u|v> <open|periodic> <CVs> [period]
//   knots 0 1 2 3 4 5 6 7        CVs + 4 knots (open) or CVs knots in one period (periodic)
//   axis v open 6
//   knots 0 0 0 0 1 2 3 3 3 3
//   level 0 48                   level <index> <CVs>, levels in order from 0
//   cv 0 0 1.5 0 0.25            cv <i> <j> <x y z>: level 0 positions, finer levels offsets
//   ...                          (along the parent's u tangent, v tangent, normal)
//   end
//
// '#' starts a comment. Numbers are written with 17 significant digits, so a round trip is
// exact. Every malformed input gets a FileError naming the source and line; counts are checked
// against the limits before anything is allocated for them.
#pragma once

#include <string>

#include "hspline/hspline.h"

namespace frep {

// The file's text; `optimised` writes the hierarchy unrefined (CVs with zero offsets that no
// detail needs left out, as seed 003's Dragon saved), which describes the same surface.
std::string hsText(const HSpline& h, bool optimised = false);
HSpline parseHs(const std::string& text, const std::string& source = "<text>");

void writeHsFile(const HSpline& h, const std::string& path, bool optimised = false);  // atomic
HSpline readHsFile(const std::string& path);

}  // namespace frep
