#include "mesh/mesh_settings.h"

#include <cmath>
#include <sstream>

namespace frep {

namespace {

std::string tableNames(const std::string& text) {
  return spellNames(text, [](const std::string& name) { return name; });
}

const char* const kMesherWords[] = {"cubes", "tetra"};
const char* const kRefineWords[] = {"off", "thin-parts", "tips"};

std::string choiceList(const std::vector<std::string>& words) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i)
    out += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
  return out;
}

[[noreturn]] void wrongKind(const MeshSettingInfo& info, const SettingValue& value) {
  const char* wanted = info.kind == SettingKind::Switch        ? "true or false"
                       : info.kind == SettingKind::WholeNumber ? "a whole number"
                       : info.kind == SettingKind::Distance    ? "a distance (model units) or none"
                                                               : nullptr;
  const std::string allowed = wanted ? wanted : choiceList(info.choices);
  throw SettingError(info.name, "{" + std::string(info.name) + "} must be " + allowed + ", got " +
                                    settingText(value));
}

int choiceIndex(const MeshSettingInfo& info, const SettingValue& value) {
  if (const std::string* word = std::get_if<std::string>(&value))
    for (std::size_t i = 0; i < info.choices.size(); ++i)
      if (info.choices[i] == *word) return static_cast<int>(i);
  wrongKind(info, value);
}

bool asSwitch(const MeshSettingInfo& info, const SettingValue& value) {
  if (const bool* b = std::get_if<bool>(&value)) return *b;
  wrongKind(info, value);
}

}  // namespace

SettingError::SettingError(std::string option_, std::string templ_)
    : ModelError(tableNames(templ_)), option(std::move(option_)), templ(std::move(templ_)) {}

const std::vector<MeshSettingInfo>& meshSettingsTable() {
  static const std::vector<MeshSettingInfo> table = {
      {"mesher", SettingKind::Choice, {kMesherWords[0], kMesherWords[1]},
       "cubes (the default: a fan of straight triangles per crossed cube, creases placed) or "
       "tetra (marching tetrahedra, about three times the triangles: the mesher before 0.3, "
       "kept for one release)"},
      {"sharp_features", SettingKind::Switch, {},
       "vertices on the creases and corners (the cubes mesher's, and the simplifier's with a "
       "{tolerance}); off, they are chamfered within a cell"},
      {"drop_flat_vertices", SettingKind::Switch, {},
       "drop the vertices where the surface is flat within a fiftieth of a cell, two "
       "triangles with each: 6 to 15 % fewer triangles, the same accuracy, a little longer "
       "meshing (the cubes mesher)"},
      {"refine", SettingKind::Choice, {kRefineWords[0], kRefineWords[1], kRefineWords[2]},
       "mesh again at half a cell the cubes where a part thinner than a cell passes between "
       "the grid's points (thin-parts: walls and fins the grid misses come back, slits it "
       "closes open again), and with tips those round the tips of creases and slivers too "
       "(the gyroid's; creases there come out less clean); off by default (docs/mesher.md)"},
      {"refine_levels", SettingKind::WholeNumber, {},
       "levels of that refinement, 1 to 3: 2 or 3 mesh again at a quarter (an eighth) of a "
       "cell where parts hide between the half cells' points: the gyroid within half a cell, "
       "at several times the time"},
      {"straighten_creases", SettingKind::Switch, {},
       "merge the vertices either side of a chamfered or zig-zagging crease onto it and flip "
       "its edges along it (within a third of a cell): clean, straight creases at a few times "
       "the meshing's time; needs {sharp_features}"},
      {"tolerance", SettingKind::Distance, {},
       "simplify: far fewer triangles, the surface kept within this distance (model units) "
       "of the exact one, still checked; a tenth of the cell size is a good start"},
  };
  return table;
}

const MeshSettingInfo* findMeshSetting(const std::string& name) {
  for (const MeshSettingInfo& info : meshSettingsTable())
    if (name == info.name) return &info;
  return nullptr;
}

SettingValue getMeshSetting(const MeshSettings& s, const std::string& name) {
  if (name == "mesher") return std::string(kMesherWords[static_cast<int>(s.mesher)]);
  if (name == "sharp_features") return s.sharpFeatures;
  if (name == "drop_flat_vertices") return s.dropFlatVertices;
  if (name == "refine") return std::string(kRefineWords[static_cast<int>(s.refine)]);
  if (name == "refine_levels") return static_cast<long>(s.refineLevels);
  if (name == "straighten_creases") return s.straightenCreases;
  if (name == "tolerance") return s.tolerance ? SettingValue(*s.tolerance) : SettingValue();
  throw SettingError(name, "there is no meshing option '" + name + "'");
}

void setMeshSetting(MeshSettings& s, const std::string& name, const SettingValue& value) {
  const MeshSettingInfo* info = findMeshSetting(name);
  if (!info) throw SettingError(name, "there is no meshing option '" + name + "'");
  if (name == "mesher") s.mesher = static_cast<Extraction>(choiceIndex(*info, value));
  else if (name == "sharp_features") s.sharpFeatures = asSwitch(*info, value);
  else if (name == "drop_flat_vertices") s.dropFlatVertices = asSwitch(*info, value);
  else if (name == "refine") s.refine = static_cast<Refinement>(choiceIndex(*info, value));
  else if (name == "refine_levels") {
    const long* n = std::get_if<long>(&value);
    if (!n) wrongKind(*info, value);
    // (out of int's range stays out of validate()'s)
    s.refineLevels = *n < -1000 ? -1000 : *n > 1000 ? 1000 : static_cast<int>(*n);
  } else if (name == "straighten_creases") s.straightenCreases = asSwitch(*info, value);
  else if (name == "tolerance") {
    if (std::holds_alternative<std::monostate>(value)) s.tolerance.reset();
    else if (const double* d = std::get_if<double>(&value)) s.tolerance = *d;
    else if (const long* n = std::get_if<long>(&value)) s.tolerance = static_cast<double>(*n);
    else wrongKind(*info, value);
  }
}

std::string settingText(const SettingValue& value) {
  struct Text {
    std::string operator()(std::monostate) const { return "none"; }
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(long n) const { return std::to_string(n); }
    std::string operator()(double d) const {
      std::ostringstream os;
      os << d;
      return os.str();
    }
    std::string operator()(const std::string& s) const { return "'" + s + "'"; }
  };
  return std::visit(Text{}, value);
}

void MeshSettings::validate() const {
  if (refineLevels < 1 || refineLevels > kMaxRefinementLevels)
    throw SettingError("refine_levels", "{refine_levels} must be a whole number from 1 to " +
                                            std::to_string(kMaxRefinementLevels) + ", got " +
                                            std::to_string(refineLevels));
  if (refineLevels > 1 && !refining())
    throw SettingError("refine_levels",
                       "{refine_levels} " + std::to_string(refineLevels) +
                           " applies to a refinement: set {refine} to thin-parts or tips, or "
                           "{refine_levels} to 1");
  if (straightenCreases && !sharpFeatures)
    throw SettingError("straighten_creases",
                       "{straighten_creases} needs {sharp_features} (they find the creases): "
                       "turn {sharp_features} on or {straighten_creases} off");
  if (tolerance && !(*tolerance > 0.0 && std::isfinite(*tolerance))) {
    std::ostringstream os;
    os << "{tolerance} must be a distance > 0 (model units), got " << *tolerance;
    throw SettingError("tolerance", os.str());
  }
}

}  // namespace frep
