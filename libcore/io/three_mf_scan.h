// A look at a 3MF package's models before lib3mf reads them: how many triangles and object
// placements the build expands to once components are followed. lib3mf follows every
// component reference while it parses (a fan of 10 levels of 10 references to one triangle
// is ten billion visits), so the refusal must come first.
#pragma once

#include <string>

namespace frep {

struct ThreeMfExpansion {
  double triangles = 0;   // every build item's triangles, components expanded
  double placements = 0;  // objects placed, each component reference expanded counting once
};

// Reads the package's .model parts as text (zip entries streamed, never whole in memory).
// Throws FileError naming `shown` for a component cycle, nesting deeper than `maxDepth`, a
// vertex coordinate that is not a number or a triangle corner that is not a whole number
// (strictly, as the schema says: lib3mf reads "one" as 0), or a package that cannot be
// opened as a zip.
ThreeMfExpansion scan3mfExpansion(const std::string& file, const std::string& shown,
                                  int maxDepth);

}  // namespace frep
