// The entry point of libfrepcad_heavy.so: the commands and steps that need OpenVDB or
// OpenCASCADE (heavy_module.h).
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/heavy_module.h"
#include "cli/terminal_progress.h"
#include "cli/vdb_precheck.h"
#include "frep/program.h"
#include "pipeline/export_pipeline.h"
#include "volume/field_sources.h"
#include "volume/grid_set.h"
#include "volume/level_sets.h"

namespace frep::cli {

namespace {

// `frepcad info FILE.vdb`: the file's grids, to pick one for a vdb_grid node.
int vdbInfo(const std::string& path, bool json) {
  const GridSet grids = readVdb(path);
  if (!json) {
    std::cout << path << ": " << grids.size() << " grid" << (grids.size() == 1 ? "" : "s") << "\n";
    for (std::size_t i = 0; i < grids.size(); ++i) {
      const GridInfo g = grids.info(i);
      std::cout << "  " << describeGrid(g) << "\n";
      if (g.worldBox.lo[0] <= g.worldBox.hi[0])
        std::cout << "    box [" << g.worldBox.lo[0] << ", " << g.worldBox.lo[1] << ", "
                  << g.worldBox.lo[2] << "] - [" << g.worldBox.hi[0] << ", " << g.worldBox.hi[1]
                  << ", " << g.worldBox.hi[2] << "]\n";
    }
    return 0;
  }
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i < grids.size(); ++i) {
    const GridInfo g = grids.info(i);
    out.push_back({{"name", g.name},
                   {"value_type", g.valueType},
                   {"grid_class", g.gridClass},
                   {"voxel_size", {g.voxelSize[0], g.voxelSize[1], g.voxelSize[2]}},
                   {"active_voxels", g.activeVoxels},
                   {"metadata", g.metadata}});
  }
  std::cout << out.dump(2) << "\n";
  return 0;
}

int exportLevelSet(const ExportOptions& opt, const Program& program, const MeshingBox& box) {
  if (!opt.format.empty() || opt.stats)
    throw UsageError("--format and --stats apply to meshes, not to a .vdb level set");
  LevelSetOptions o;
  o.voxel = box.resolution;
  o.fog = opt.fog;
  installInterruptHandlers();
  o.progress = [](double) { return !interrupted(); };
  const GridSet grids = sampleLevelSet(program, box.box, o);
  writeVdb(grids, opt.output);
  if (!opt.quiet)
    std::cout << "wrote " << opt.output << ": " << describeGrid(grids.info(0)) << "\n";
  return 0;
}

const HeavyModule kModule = {kHeavyModuleVersion, deformCommand,         repairCommand,
                             compareCommand,      hsplineCommand,        vdbInfo,
                             exportLevelSet,      registerVolumeSources, readVdbAlone};

}  // namespace

}  // namespace frep::cli

extern "C" __attribute__((visibility("default"))) const frep::cli::HeavyModule*
frepcad_heavy_module() {
  // Every .vdb this process reads is read by a child first (cli/vdb_precheck.h); the child
  // itself turns that off.
  frep::setVdbPrecheck(frep::cli::readVdbInChild);
  return &frep::cli::kModule;
}
