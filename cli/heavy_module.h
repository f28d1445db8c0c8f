// The commands and steps that need OpenVDB or OpenCASCADE live in a module that frepcad loads
// only when one of them is asked for (libfrepcad_heavy.so, beside the executable or in
// ../lib/frepcad): loading those two libraries and their dependencies takes 0.1 s and 35 MiB
// before any work, more than meshing and checking a model at 256 cells. The module is built
// from the same sources and resolves the rest of libcore against the executable (which
// exports it), so there is one registry and one set of interrupt handlers.
#pragma once

#include <string>

#include "cli/commands.h"

namespace frep {
class Program;
struct MeshingBox;
}  // namespace frep

namespace frep::cli {

// What the module offers; it returns one of these from frepcad_heavy_module().
struct HeavyModule {
  int version;  // kHeavyModuleVersion: a module from another build is refused
  int (*deform)(const Args& args);
  int (*repair)(const Args& args);
  int (*compare)(const Args& args);
  int (*hspline)(const Args& args);
  int (*vdbInfo)(const std::string& path, bool json);
  // `export MODEL -o OUT.vdb`: the solid as an OpenVDB level set, a voxel per cell.
  int (*exportLevelSet)(const ExportOptions& options, const Program& program,
                        const MeshingBox& box);
  // The loaders of the mesh_sdf and vdb_grid nodes (volume/field_sources.h).
  void (*registerVolumeSources)();
  // `frepcad __read-vdb PATH`: reads the file for a parent frepcad (cli/vdb_precheck.h).
  int (*readVdbAlone)(const std::string& path);
};
constexpr int kHeavyModuleVersion = 2;

// The module, loaded on first use. Throws std::runtime_error naming the file and the reason
// when it cannot be found or loaded (main reports it in one line).
const HeavyModule& heavyModule();

// Stand-ins for the loaders of the node types whose field is read from a file: the first
// model that uses one loads the module, which puts the real loaders in their place.
void registerLazyVolumeSources();

}  // namespace frep::cli
