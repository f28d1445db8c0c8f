// The grids of an OpenVDB file, held without exposing OpenVDB: names, value types, grid
// classes, transforms and metadata, read and written as .vdb files. OpenVDB itself is included
// only by the volume/ sources (openvdb_grids.h), so the rest of libcore compiles without it.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "base/file_names.h"  // isVdbPath
#include "base/vec.h"

namespace frep {

// A .vdb file whose grids would need more memory than this (by the sizes the file declares in
// its metadata) is refused before its grids are read: a small hostile or mistaken file must
// not be able to ask for all of the machine's memory.
constexpr std::uint64_t kMaxVdbGridBytes = 8ull << 30;

struct GridInfo {
  std::string name;
  std::string valueType;  // OpenVDB's name: "float", "double", "int32", "bool", "vec3s", ...
  std::string gridClass;  // "level set", "fog volume", "staggered" or "unknown"
  Vec3 voxelSize{0, 0, 0};
  std::uint64_t activeVoxels = 0;
  Box3 worldBox;                                // of the active voxels; lo > hi when there are none
  std::map<std::string, std::string> metadata;  // every metadata item, as text
};

class GridSet {
 public:
  GridSet();
  std::size_t size() const;
  GridInfo info(std::size_t i) const;
  // The index of the scalar (float or double) grid named `name`, or of the first one when
  // `name` is empty. Throws ModelError saying which grids the set has; `where` names the file.
  std::size_t scalarGrid(const std::string& name, const std::string& where) const;

  struct Impl;  // the OpenVDB grids and the file's own metadata (openvdb_grids.h)
  std::shared_ptr<Impl> impl;
};

// Reads every grid of a .vdb file. Throws FileError naming the file and what is wrong (not an
// OpenVDB file, truncated, unknown value type, grids too large).
GridSet readVdb(const std::string& path);
// A check readVdb runs on each file after its own and before OpenVDB reads it (none by
// default): frepcad and frepcore have a helper read the file first (volume/vdb_reader_child.h),
// since OpenVDB's reader can crash on damaged compressed data. It throws FileError to refuse.
void setVdbPrecheck(std::function<void(const std::string& path)> check);
// Writes every grid (names, types, transforms, metadata) atomically: a failure leaves no file.
void writeVdb(const GridSet& grids, const std::string& path);

// "grid 'density' (float, fog volume, 12,345 active voxels, voxel 0.1)": for listings.
std::string describeGrid(const GridInfo& g);

}  // namespace frep
