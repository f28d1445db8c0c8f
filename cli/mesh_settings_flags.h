// frepcad's flags for the meshing options, spelled from the one table (mesh/mesh_settings.h):
// `--NAME VALUE` for a number or a choice, `--NAME` and `--no-NAME` for a switch, with the
// table name's underscores as dashes.
#pragma once

#include <cstddef>
#include <set>
#include <string>

#include "cli/commands.h"
#include "mesh/mesh_settings.h"

namespace frep::cli {

// "--refine-levels" for "refine_levels".
std::string settingFlag(const std::string& option);

// Takes args[i] (and its value) when it is a meshing flag or an older spelling of one: sets
// it in `settings`, adds its table name to `given` and returns true (i at the last argument
// taken). A bad value is a UsageError naming the flag and what is allowed.
bool takeMeshSettingFlag(const Args& args, std::size_t& i, MeshSettings& settings,
                         std::set<std::string>& given);

// A SettingError as a UsageError that names the flags.
UsageError flagError(const SettingError& error);

// MeshSettings::validate, its error as a UsageError that names the flags.
void validateMeshFlags(const MeshSettings& settings);

// The settings named in `only` (all when it is empty) as a JSON object of table names and
// values (none: null), for the Python children (documents, brick runs).
std::string meshSettingsJson(const MeshSettings& settings, const std::set<std::string>& only);

// The flags' lines for `frepcad export --help`, from the table.
std::string meshSettingsHelp();

}  // namespace frep::cli
