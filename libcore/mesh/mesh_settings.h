// The options a user chooses for a mesh: one type, one validation and one table of names for
// every front end. The C++ pipeline embeds MeshSettings (MeshingOptions, ExportRequest,
// BrickJobPlan, MeshingStats); frepcad's export flags, frepcore's keywords and the Polygonize
// feature's properties are all spelled from the table below, so an option has one name:
//
//   table name          C++ field            Python keyword        frepcad flag            property
//   sharp_features      sharpFeatures        sharp_features=       --[no-]sharp-features
//   SharpFeatures
//
// A new option is a field here, a row in meshSettingsTable() (mesh_settings.cpp, its name,
// kind, help and field) and a row in the Polygonize feature's property table
// (Mod/FRep/FRepPolygonize.py); the rest follows from the table.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "base/errors.h"

namespace frep {

// How a crossed cube becomes triangles (docs/mesher.md).
enum class Extraction {
  // Each cube whose surface meets its faces in one loop caps that loop with a fan of
  // straight triangles (as many as marching cubes makes); the rare cube with several loops
  // keeps its tetrahedra's triangles. The default.
  Cubes,
  // Marching tetrahedra in every cube: about three times the triangles (`--mesher tetra`,
  // kept for one release).
  Tetrahedra,
};

// Which cubes are meshed again at half a cell (mesh/local_refinement.h).
enum class Refinement {
  Off,
  // The cubes round parts thinner than a cell seen nowhere near the mesh: solid left out,
  // gaps closed.
  ThinParts,
  // ... and those round the tips of creases and slivers (the gyroid's); creases there come
  // out less clean.
  Tips,
};

// The most levels of local refinement (MeshSettings::refineLevels): half, quarter and eighth
// cells.
constexpr int kMaxRefinementLevels = 3;

struct MeshSettings {
  Extraction mesher = Extraction::Cubes;
  // Cubes only: a cube a crease or corner crosses gets a vertex on it (from the normals'
  // tangent planes) instead of a chamfer across it; the simplifier keeps them too.
  bool sharpFeatures = true;
  // Cubes only: where the surface is flat to within a fiftieth of a cell, a vertex on a grid
  // edge goes and its neighbours are fanned again, two triangles fewer each time
  // (docs/mesher.md, "Flat vertices"): 6 to 15 % fewer triangles on the reference models at
  // the same accuracy, at a cost in meshing time. Needs an even MeshingOptions::brickCells.
  bool dropFlatVertices = true;
  Refinement refine = Refinement::Off;
  // Levels of that refinement (1 to kMaxRefinementLevels): 2 meshes the half cubes inside
  // the refined region again at a quarter cell where their own half cells show what their
  // corners miss (docs/mesher.md, "Deeper levels"), 3 at an eighth.
  int refineLevels = 1;
  // The mesher's creases straightened (simplify/straighten_creases.h), before any
  // simplification; needs sharpFeatures.
  bool straightenCreases = false;
  // Given: the mesh is simplified (simplify/simplify.h), kept within this distance of F = 0
  // (model units, > 0).
  std::optional<double> tolerance;

  bool refining() const { return refine != Refinement::Off; }

  // Throws SettingError for a value out of range or options that contradict each other.
  void validate() const;
};

// `text` with every {name} replaced by spell(name): the table's texts and SettingError's
// name options this way, so that each front end spells them its own way.
template <class Spell>
std::string spellNames(const std::string& text, Spell&& spell) {
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t open = text.find('{', i);
    const std::size_t close = open == std::string::npos ? open : text.find('}', open);
    if (close == std::string::npos) {
      out += text.substr(i);
      break;
    }
    out += text.substr(i, open - i) + spell(text.substr(open + 1, close - open - 1));
    i = close + 1;
  }
  return out;
}

// A bad setting: `option` is the table name of the option at fault, `templ` says what is
// wrong and what is allowed, naming options as {name}; what() has the table names.
struct SettingError : ModelError {
  SettingError(std::string option, std::string templ);
  std::string option, templ;
};

// A setting's value as the front ends hold it: a switch, a whole number, a distance (none:
// std::monostate, for an optional distance left out) or one of a choice's words.
using SettingValue = std::variant<std::monostate, bool, long, double, std::string>;

enum class SettingKind { Switch, WholeNumber, Distance, Choice };

struct MeshSettingInfo {
  const char* name;  // snake_case: Python keyword; dashes for frepcad's flag
  SettingKind kind;
  std::vector<std::string> choices;  // a Choice's words, in order
  const char* help;                  // one paragraph for every front end's help
  // The option's value in a MeshSettings, and setting it (a value of the wrong kind or a
  // word the choice does not have: SettingError naming the option).
  std::function<SettingValue(const MeshSettings&)> get;
  std::function<void(MeshSettings&, const SettingValue&)> set;
};

// Every option, in the order the front ends list them.
const std::vector<MeshSettingInfo>& meshSettingsTable();
// The row of `name`, or nullptr.
const MeshSettingInfo* findMeshSetting(const std::string& name);
// `name`'s value in `settings` (MeshSettings{} gives the defaults).
SettingValue getMeshSetting(const MeshSettings& settings, const std::string& name);
// Sets `name` from `value`; a value of the wrong kind or a word the choice does not have is
// a SettingError naming the option (ranges are validate()'s). A whole number is taken for a
// distance.
void setMeshSetting(MeshSettings& settings, const std::string& name, const SettingValue& value);
// The value as text: "true", "3", "0.05", "none", "cubes".
std::string settingText(const SettingValue& value);

}  // namespace frep
