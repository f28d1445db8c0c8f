// frepcore.MeshSettings: the one meshing-settings type (mesh/mesh_settings.h), bound once with
// a property per row of its table; Shape.mesh, Shape.export and the brick jobs take it.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "mesh/mesh_settings.h"
#include "python/bindings.h"

namespace py = pybind11;

namespace frep {

namespace {

SettingValue toSettingValue(const py::handle& v) {
  if (v.is_none()) return std::monostate();
  if (py::isinstance<py::bool_>(v)) return v.cast<bool>();
  if (py::isinstance<py::int_>(v)) return v.cast<long>();
  if (py::isinstance<py::float_>(v)) return v.cast<double>();
  if (py::isinstance<py::str>(v)) return v.cast<std::string>();
  throw SettingError("", "a meshing option's value must be a bool, a number, a word or None, got " +
                             py::repr(v).cast<std::string>());
}

py::object fromSettingValue(const SettingValue& v) {
  struct ToPython {
    py::object operator()(std::monostate) const { return py::none(); }
    py::object operator()(bool b) const { return py::bool_(b); }
    py::object operator()(long n) const { return py::int_(n); }
    py::object operator()(double d) const { return py::float_(d); }
    py::object operator()(const std::string& s) const { return py::str(s); }
  };
  return std::visit(ToPython{}, v);
}

const char* kindName(SettingKind kind) {
  switch (kind) {
    case SettingKind::Switch:
      return "switch";
    case SettingKind::WholeNumber:
      return "whole number";
    case SettingKind::Distance:
      return "distance";
    case SettingKind::Choice:
      return "choice";
  }
  return "?";
}

MeshSettings meshSettingsFrom(const py::kwargs& options) {
  MeshSettings s;
  for (const auto& item : options)
    setMeshSetting(s, item.first.cast<std::string>(), toSettingValue(item.second));
  return s;
}

}  // namespace

void bindMeshSettings(py::module_& m) {
  py::class_<MeshSettings> cls(m, "MeshSettings",
                               "The meshing options (one per row of mesh_settings_table()): "
                               "MeshSettings(sharp_features=False, refine='tips', ...).");
  cls.def(py::init([](const py::kwargs& options) { return meshSettingsFrom(options); }));
  for (const MeshSettingInfo& info : meshSettingsTable()) {
    const std::string name = info.name;
    cls.def_property(
        info.name,
        [name](const MeshSettings& s) { return fromSettingValue(getMeshSetting(s, name)); },
        [name](MeshSettings& s, const py::object& v) {
          setMeshSetting(s, name, toSettingValue(v));
        },
        spellNames(info.help, [](const std::string& n) { return n; }).c_str());
  }
  cls.def(
      "problem",
      [](const MeshSettings& s) -> py::object {
        try {
          s.validate();
        } catch (const SettingError& e) {
          return py::make_tuple(e.option, e.templ);
        }
        return py::none();
      },
      "None, or (option, text) for the first setting validate() refuses; the text names "
      "options as {name}, for a front end to spell its own way.");
  cls.def("validate", &MeshSettings::validate, "Raises ValueError naming a bad setting.");
  cls.def("to_dict", [](const MeshSettings& s) {
    py::dict d;
    for (const MeshSettingInfo& info : meshSettingsTable())
      d[info.name] = fromSettingValue(getMeshSetting(s, info.name));
    return d;
  });
  cls.def("__repr__", [](const MeshSettings& s) {
    std::string out = "MeshSettings(";
    bool first = true;
    const MeshSettings defaults;
    for (const MeshSettingInfo& info : meshSettingsTable()) {
      const SettingValue v = getMeshSetting(s, info.name);
      if (v == getMeshSetting(defaults, info.name)) continue;
      out += (first ? "" : ", ") + std::string(info.name) + "=" +
             py::repr(fromSettingValue(v)).cast<std::string>();
      first = false;
    }
    return out + ")";
  });
  cls.def("__eq__", [](const MeshSettings& a, const MeshSettings& b) {
    for (const MeshSettingInfo& info : meshSettingsTable())
      if (getMeshSetting(a, info.name) != getMeshSetting(b, info.name)) return false;
    return true;
  });
  m.def(
      "mesh_settings_table",
      [] {
        py::list rows;
        const MeshSettings defaults;
        for (const MeshSettingInfo& info : meshSettingsTable()) {
          py::dict row;
          row["name"] = info.name;
          row["kind"] = kindName(info.kind);
          row["choices"] = info.choices;
          row["default"] = fromSettingValue(getMeshSetting(defaults, info.name));
          row["help"] = info.help;
          rows.append(row);
        }
        return rows;
      },
      "The meshing options, in order: dicts of name, kind, choices, default and help (which "
      "names other options as {name}).");
}

}  // namespace frep
