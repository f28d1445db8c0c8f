#include "cli/mesh_settings_flags.h"

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <utility>

namespace frep::cli {

namespace {

// Older spellings, still accepted: (flag, option, value).
struct OlderFlag {
  const char* flag;
  const char* option;
  SettingValue value;
};
const OlderFlag kOlderFlags[] = {
    {"--no-sharp", "sharp_features", false},
    {"--keep-flat-vertices", "drop_flat_vertices", false},
    {"--fewer-triangles", "drop_flat_vertices", true},
    {"--refine-thin-parts", "refine", std::string("thin-parts")},
    {"--refine-tips", "refine", std::string("tips")},
};

std::string dashes(std::string name) {
  for (char& c : name)
    if (c == '_') c = '-';
  return name;
}

std::string spellFlags(const std::string& text) {
  return spellNames(text, [](const std::string& name) { return settingFlag(name); });
}

void set(MeshSettings& settings, const std::string& option, const SettingValue& value,
         std::set<std::string>& given) {
  try {
    setMeshSetting(settings, option, value);
  } catch (const SettingError& e) {
    throw flagError(e);
  }
  given.insert(option);
}

SettingValue parseValue(const MeshSettingInfo& info, const std::string& flag,
                        const std::string& text) {
  switch (info.kind) {
    case SettingKind::WholeNumber: {
      const double n = parseNumber(text, flag);
      if (n != std::floor(n) || std::fabs(n) > 1e6)
        throw UsageError(flag + " must be a whole number, got '" + text + "'");
      return static_cast<long>(n);
    }
    case SettingKind::Distance:
      if (text == "none") return std::monostate();
      return parseNumber(text, flag);
    case SettingKind::Choice:
    case SettingKind::Switch:
      break;
  }
  return text;
}

// Wraps `text` to the help's second column.
std::string wrapped(const std::string& head, const std::string& text) {
  constexpr std::size_t kColumn = 26, kWidth = 94;
  std::string out = "  " + head;
  std::size_t line = out.size();
  if (line + 1 > kColumn) {
    out += "\n";
    line = 0;
  }
  out += std::string(kColumn - line, ' ');
  line = kColumn;
  std::istringstream words(text);
  std::string word;
  bool first = true;
  while (words >> word) {
    if (!first && line + 1 + word.size() > kWidth) {
      out += "\n" + std::string(kColumn, ' ');
      line = kColumn;
      first = true;
    }
    out += (first ? "" : " ") + word;
    line += (first ? 0 : 1) + word.size();
    first = false;
  }
  return out + "\n";
}

}  // namespace

std::string settingFlag(const std::string& option) {
  return "--" + dashes(option);
}

bool takeMeshSettingFlag(const Args& args, std::size_t& i, MeshSettings& settings,
                         std::set<std::string>& given) {
  const std::string& a = args[i];
  for (const OlderFlag& older : kOlderFlags)
    if (a == older.flag) {
      // (--refine-thin-parts after --refine-tips kept the tips)
      if (std::string(older.option) == "refine" && settings.refine == Refinement::Tips) return true;
      set(settings, older.option, older.value, given);
      return true;
    }
  for (const MeshSettingInfo& info : meshSettingsTable()) {
    const std::string flag = settingFlag(info.name);
    if (info.kind == SettingKind::Switch) {
      if (a != flag && a != "--no-" + flag.substr(2)) continue;
      set(settings, info.name, a == flag, given);
      return true;
    }
    if (a != flag) continue;
    if (i + 1 >= args.size()) {
      const char* what = info.kind == SettingKind::WholeNumber ? "a whole number"
                         : info.kind == SettingKind::Distance  ? "a distance"
                                                               : "a choice";
      throw UsageError(flag + " expects " + what);
    }
    set(settings, info.name, parseValue(info, flag, args[++i]), given);
    return true;
  }
  return false;
}

UsageError flagError(const SettingError& error) {
  return UsageError(spellFlags(error.templ));
}

void validateMeshFlags(const MeshSettings& settings) {
  try {
    settings.validate();
  } catch (const SettingError& e) {
    throw flagError(e);
  }
}

std::string meshSettingsJson(const MeshSettings& settings, const std::set<std::string>& only) {
  struct ToJson {
    nlohmann::json operator()(std::monostate) const { return nullptr; }
    nlohmann::json operator()(bool b) const { return b; }
    nlohmann::json operator()(long n) const { return n; }
    nlohmann::json operator()(double d) const { return d; }
    nlohmann::json operator()(const std::string& s) const { return s; }
  };
  nlohmann::json out = nlohmann::json::object();
  for (const MeshSettingInfo& info : meshSettingsTable())
    if (only.empty() || only.count(info.name))
      out[info.name] = std::visit(ToJson{}, getMeshSetting(settings, info.name));
  return out.dump();
}

std::string meshSettingsHelp() {
  const MeshSettings defaults;
  std::string out;
  for (const MeshSettingInfo& info : meshSettingsTable()) {
    const std::string flag = settingFlag(info.name);
    const SettingValue value = getMeshSetting(defaults, info.name);
    std::string head, text = spellFlags(info.help);
    switch (info.kind) {
      case SettingKind::Switch:
        head = std::get<bool>(value) ? "--[no-]" + flag.substr(2) : flag;
        if (std::get<bool>(value)) text += " (on by default)";
        break;
      case SettingKind::WholeNumber:
        head = flag + " N";
        break;
      case SettingKind::Distance:
        head = flag + " D";
        break;
      case SettingKind::Choice: {
        head = flag + " ";
        for (std::size_t k = 0; k < info.choices.size(); ++k)
          head += (k ? "|" : "") + info.choices[k];
        break;
      }
    }
    out += wrapped(head, text);
  }
  std::string older;
  for (const OlderFlag& f : kOlderFlags)
    older += std::string(older.empty() ? "" : ", ") + f.flag + " (" +
             (!std::holds_alternative<bool>(f.value)
                  ? settingFlag(f.option) + " " + std::get<std::string>(f.value)
              : std::get<bool>(f.value) ? settingFlag(f.option)
                                        : "--no-" + settingFlag(f.option).substr(2)) +
             ")";
  return out + wrapped("", "older spellings, still accepted: " + older);
}

}  // namespace frep::cli
