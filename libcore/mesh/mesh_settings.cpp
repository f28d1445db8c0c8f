#include "mesh/mesh_settings.h"

#include <cmath>
#include <sstream>

namespace frep {

namespace {

std::string tableNames(const std::string& text) {
  return spellNames(text, [](const std::string& name) { return name; });
}

std::string choiceList(const std::vector<std::string>& words) {
  std::string out;
  for (std::size_t i = 0; i < words.size(); ++i)
    out += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
  return out;
}

[[noreturn]] void wrongKind(const char* name, SettingKind kind,
                            const std::vector<std::string>& choices, const SettingValue& value) {
  const char* wanted = kind == SettingKind::Switch        ? "true or false"
                       : kind == SettingKind::WholeNumber ? "a whole number"
                       : kind == SettingKind::Distance    ? "a distance (model units) or none"
                                                          : nullptr;
  const std::string allowed = wanted ? wanted : choiceList(choices);
  throw SettingError(
      name, "{" + std::string(name) + "} must be " + allowed + ", got " + settingText(value));
}

// One row of the table for each kind of field: its name, help and accessors.
template <bool MeshSettings::*Field>
MeshSettingInfo switchRow(const char* name, const char* help) {
  return {name,
          SettingKind::Switch,
          {},
          help,
          [](const MeshSettings& s) { return SettingValue(s.*Field); },
          [name](MeshSettings& s, const SettingValue& v) {
            const bool* b = std::get_if<bool>(&v);
            if (!b) wrongKind(name, SettingKind::Switch, {}, v);
            s.*Field = *b;
          }};
}

template <int MeshSettings::*Field>
MeshSettingInfo wholeNumberRow(const char* name, const char* help) {
  return {name,
          SettingKind::WholeNumber,
          {},
          help,
          [](const MeshSettings& s) { return SettingValue(static_cast<long>(s.*Field)); },
          [name](MeshSettings& s, const SettingValue& v) {
            const long* n = std::get_if<long>(&v);
            if (!n) wrongKind(name, SettingKind::WholeNumber, {}, v);
            // (out of int's range stays out of validate()'s)
            s.*Field = *n < -1000 ? -1000 : *n > 1000 ? 1000 : static_cast<int>(*n);
          }};
}

template <std::optional<double> MeshSettings::*Field>
MeshSettingInfo distanceRow(const char* name, const char* help) {
  return {
      name,
      SettingKind::Distance,
      {},
      help,
      [](const MeshSettings& s) { return (s.*Field) ? SettingValue(*(s.*Field)) : SettingValue(); },
      [name](MeshSettings& s, const SettingValue& v) {
        if (std::holds_alternative<std::monostate>(v))
          (s.*Field).reset();
        else if (const double* d = std::get_if<double>(&v))
          s.*Field = *d;
        else if (const long* n = std::get_if<long>(&v))
          s.*Field = static_cast<double>(*n);
        else
          wrongKind(name, SettingKind::Distance, {}, v);
      }};
}

// An enumeration whose values are the words, in order.
template <class Enum, Enum MeshSettings::*Field>
MeshSettingInfo choiceRow(const char* name, std::vector<std::string> words, const char* help) {
  return {name,
          SettingKind::Choice,
          words,
          help,
          [words](const MeshSettings& s) {
            return SettingValue(words[static_cast<std::size_t>(s.*Field)]);
          },
          [name, words](MeshSettings& s, const SettingValue& v) {
            if (const std::string* word = std::get_if<std::string>(&v))
              for (std::size_t i = 0; i < words.size(); ++i)
                if (words[i] == *word) {
                  s.*Field = static_cast<Enum>(i);
                  return;
                }
            wrongKind(name, SettingKind::Choice, words, v);
          }};
}

}  // namespace

SettingError::SettingError(std::string option_, std::string templ_)
    : ModelError(tableNames(templ_)), option(std::move(option_)), templ(std::move(templ_)) {}

const std::vector<MeshSettingInfo>& meshSettingsTable() {
  static const std::vector<MeshSettingInfo> table = {
      choiceRow<Extraction, &MeshSettings::mesher>(
          "mesher", {"cubes", "tetra"},
          "cubes (the default: a fan of straight triangles per crossed cube, creases placed) or "
          "tetra (marching tetrahedra, about three times the triangles: the mesher before 0.3, "
          "kept for one release)"),
      switchRow<&MeshSettings::sharpFeatures>(
          "sharp_features",
          "vertices on the creases and corners (the cubes mesher's, and the simplifier's with a "
          "{tolerance}); off, they are chamfered within a cell"),
      switchRow<&MeshSettings::dropFlatVertices>(
          "drop_flat_vertices",
          "drop the vertices where the surface is flat within a fiftieth of a cell, two "
          "triangles with each: 6 to 15 % fewer triangles, the same accuracy, a little longer "
          "meshing (the cubes mesher)"),
      choiceRow<Refinement, &MeshSettings::refine>(
          "refine", {"off", "thin-parts", "tips"},
          "mesh again at half a cell the cubes where a part thinner than a cell passes between "
          "the grid's points (thin-parts: walls and fins the grid misses come back, slits it "
          "closes open again), and with tips those round the tips of creases and slivers too "
          "(the gyroid's; creases there come out less clean); off by default (docs/mesher.md)"),
      wholeNumberRow<&MeshSettings::refineLevels>(
          "refine_levels",
          "levels of that refinement, 1 to 3: 2 or 3 mesh again at a quarter (an eighth) of a "
          "cell where parts hide between the half cells' points: the gyroid within half a cell, "
          "at several times the time"),
      switchRow<&MeshSettings::straightenCreases>(
          "straighten_creases",
          "merge the vertices either side of a chamfered or zig-zagging crease onto it and flip "
          "its edges along it (within a third of a cell): clean, straight creases at a few times "
          "the meshing's time; needs {sharp_features}"),
      distanceRow<&MeshSettings::tolerance>(
          "tolerance",
          "simplify: far fewer triangles, the surface kept within this distance (model units) "
          "of the exact one, still checked; a tenth of the cell size is a good start"),
  };
  return table;
}

const MeshSettingInfo* findMeshSetting(const std::string& name) {
  for (const MeshSettingInfo& info : meshSettingsTable())
    if (name == info.name) return &info;
  return nullptr;
}

SettingValue getMeshSetting(const MeshSettings& s, const std::string& name) {
  const MeshSettingInfo* info = findMeshSetting(name);
  if (!info) throw SettingError(name, "there is no meshing option '" + name + "'");
  return info->get(s);
}

void setMeshSetting(MeshSettings& s, const std::string& name, const SettingValue& value) {
  const MeshSettingInfo* info = findMeshSetting(name);
  if (!info) throw SettingError(name, "there is no meshing option '" + name + "'");
  info->set(s, value);
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
