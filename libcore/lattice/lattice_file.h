// Lattice files (.json): a lattice's rest box, divisions and deformed control points, for
// `frepcad deform --lattice` and for exchange (docs/file-formats.md, "Lattice files"):
//
//   {"format": "frepcad-lattice", "version": 1,
//    "rest_min": [x, y, z], "rest_max": [x, y, z], "divisions": [l, m, n],
//    "points": [[x, y, z], ...]}      // (l+1)(m+1)(n+1), i slowest, k fastest; optional
//
// the same fields as the ffd node's parameters. Malformed input gets a ModelError naming the
// file and the field; files over 64 MiB or nested deeper than a lattice can be are refused
// before they are parsed.
#pragma once

#include <string>

#include "lattice/ffd_lattice.h"

namespace frep {

constexpr std::size_t kMaxLatticeFileBytes = std::size_t(64) << 20;

FfdLattice parseLattice(const std::string& text, const std::string& source);
FfdLattice readLatticeFile(const std::string& path);
std::string latticeToJson(const FfdLattice& lattice);
// Atomic: a failure leaves no file.
void writeLatticeFile(const FfdLattice& lattice, const std::string& path);

}  // namespace frep
