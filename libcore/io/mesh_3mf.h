// 3MF files (the 3D Manufacturing Format's core specification) through lib3mf: one or more
// named mesh objects, each a build item, with the length unit and metadata. lib3mf itself is
// only in mesh_3mf.cpp (its headers define Windows types that must not leak).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "base/triangle_mesh.h"
#include "io/mesh_io.h"

namespace frep {

enum class LengthUnit { Micrometer, Millimeter, Centimeter, Inch, Foot, Meter };

// "micron", "mm", "cm", "inch", "ft", "m": the 3MF unit names; parseLengthUnit throws
// ModelError naming the allowed values.
const char* lengthUnitName(LengthUnit u);
LengthUnit parseLengthUnit(const std::string& name);

struct NamedMesh {
  std::string name;
  TriangleMesh mesh;
};

struct ThreeMfOptions {
  LengthUnit unit = LengthUnit::Millimeter;
  // (name, value) pairs, names from the core specification's list (Title, Designer,
  // Description, Copyright, LicenseTerms, Rating, CreationDate, ModificationDate, Application).
  std::vector<std::pair<std::string, std::string>> metadata;
  // Refuse an object that is not manifold and consistently oriented, as the core
  // specification requires, judged by lib3mf itself before anything is written. Off only for
  // a write the user forced after the check refused the mesh.
  bool validate = true;
};

// lib3mf 1.8 writes coordinates with at most six decimals through its own float-to-text
// conversion (truncating, and off by an ulp for large values), so a 3MF does not hold a
// mesh's float coordinates exactly. A package is therefore made in memory first and read
// back: `objects` are the meshes exactly as the file holds them, and that is what a caller
// checks before it writes the bytes.
struct ThreeMfPackage {
  std::vector<unsigned char> bytes;
  std::vector<NamedMesh> objects;
};

// Builds the package (an object and a build item per mesh). Throws FileError naming an object
// that breaks a rule of the specification (with options.validate), Cancelled.
ThreeMfPackage pack3mf(const std::vector<NamedMesh>& objects, const ThreeMfOptions& options = {},
                       const WriteProgress& progress = {});
// Writes a package's bytes to `path` atomically.
void writePackage(const ThreeMfPackage& package, const std::string& path);
// pack3mf, then writePackage.
void write3mf(const std::vector<NamedMesh>& objects, const std::string& path,
              const ThreeMfOptions& options = {}, const WriteProgress& progress = {});

struct ThreeMfContents {
  std::vector<NamedMesh> objects;  // one per build item, its transforms applied
  LengthUnit unit = LengthUnit::Millimeter;
  std::vector<std::pair<std::string, std::string>> metadata;
};

// Packages larger than this once unpacked are refused before lib3mf reads them: a zip bomb
// costs nothing but the look at the archive's directory.
constexpr unsigned long long kMax3mfUnpackedBytes = 4ull << 30;
// Component references nested deeper than this are refused (a hostile file can nest them to
// blow the stack or multiply the triangles).
constexpr int kMax3mfComponentDepth = 16;
// Triangles all build items may add up to (components instancing one mesh many times).
constexpr std::size_t kMax3mfTriangles = std::size_t(1) << 26;

// Reads every build item of a 3MF (mesh objects, and components objects flattened with their
// transforms). Throws FileError naming the file and the problem.
ThreeMfContents read3mf(const std::string& path);

// The sum of the declared unpacked sizes of a zip archive's entries, read from its central
// directory alone (exposed for the tests). Throws FileError for a file that is no zip archive.
unsigned long long zipUnpackedBytes(const std::string& path);

}  // namespace frep
