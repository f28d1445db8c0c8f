// Lattice files: nlohmann::json with a depth guard, every field checked with its name.
#include "lattice/lattice_file.h"


#include <iomanip>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "base/atomic_file.h"
#include "base/errors.h"
#include "base/file_names.h"

namespace frep {

using nlohmann::json;

namespace {

Vec3 vec3Field(const json& j, const char* name, const std::string& source) {
  if (!j.contains(name))
    throw ModelError(source + ": \"" + name + "\" is missing (an array of three numbers)");
  const json& v = j[name];
  if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
    throw ModelError(source + ": \"" + name + "\" must be an array of three numbers");
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

}  // namespace

FfdLattice parseLattice(const std::string& text, const std::string& source) {
  json j;
  try {
    // A lattice is two levels deep; a deeper file is refused as it is read, before its
    // nesting can cost memory or stack.
    j = json::parse(text, [&](int depth, json::parse_event_t, json&) {
      if (depth > 4) throw ModelError(source + ": nested deeper than a lattice file can be");
      return true;
    });
  } catch (const json::exception& e) {
    throw ModelError(source + ": not valid JSON (" + std::string(e.what()) + ")");
  }
  if (!j.is_object()) throw ModelError(source + ": a lattice file holds one JSON object");
  if (!j.contains("format") || j["format"] != "frepcad-lattice")
    throw ModelError(source + ": \"format\" must be \"frepcad-lattice\"");
  if (!j.contains("version") || !j["version"].is_number_integer() || j["version"].get<int>() != 1)
    throw ModelError(source + ": \"version\" must be 1 (this frepcad reads version 1)");
  for (auto it = j.begin(); it != j.end(); ++it)
    if (it.key() != "format" && it.key() != "version" && it.key() != "rest_min" &&
        it.key() != "rest_max" && it.key() != "divisions" && it.key() != "points")
      throw ModelError(source + ": unknown key \"" + it.key() +
                       "\"; a lattice has format, version, rest_min, rest_max, divisions, points");
  const Vec3 lo = vec3Field(j, "rest_min", source), hi = vec3Field(j, "rest_max", source);
  if (!j.contains("divisions") || !j["divisions"].is_array() || j["divisions"].size() != 3)
    throw ModelError(source + ": \"divisions\" must be an array of three integers from 1 to " +
                     std::to_string(kMaxLatticeDivisions));
  int d[3];
  for (int a = 0; a < 3; ++a) {
    const json& v = j["divisions"][a];
    if (!v.is_number_integer() || v.get<long long>() < 1 ||
        v.get<long long>() > kMaxLatticeDivisions)
      throw ModelError(source + ": \"divisions\" must be three integers from 1 to " +
                       std::to_string(kMaxLatticeDivisions) + ", got " + v.dump());
    d[a] = v.get<int>();
  }
  FfdLattice lattice = [&] {
    try {
      return FfdLattice({lo, hi}, d[0], d[1], d[2]);
    } catch (const ModelError& e) {
      throw ModelError(source + ": " + e.what());
    }
  }();
  if (j.contains("points")) {
    const json& p = j["points"];
    if (!p.is_array() || p.size() != lattice.pointCount())
      throw ModelError(source + ": \"points\" must hold " + std::to_string(lattice.pointCount()) +
                       " points for a " + std::to_string(d[0]) + " x " + std::to_string(d[1]) +
                       " x " + std::to_string(d[2]) + " lattice (i slowest, k fastest), got " +
                       (p.is_array() ? std::to_string(p.size()) : std::string("no array")));
    std::vector<Vec3> points;
    points.reserve(p.size());
    for (std::size_t at = 0; at < p.size(); ++at) {
      const json& q = p[at];
      if (!q.is_array() || q.size() != 3 || !q[0].is_number() || !q[1].is_number() ||
          !q[2].is_number())
        throw ModelError(source + ": point " + std::to_string(at) +
                         " must be an array of three numbers");
      points.push_back({q[0].get<double>(), q[1].get<double>(), q[2].get<double>()});
    }
    try {
      lattice.setPoints(points);
    } catch (const ModelError& e) {
      throw ModelError(source + ": " + e.what());
    }
  }
  return lattice;
}

FfdLattice readLatticeFile(const std::string& path) {
  return parseLattice(readSmallFile(path, "lattice file", kMaxLatticeFileBytes), displayName(path));
}

std::string latticeToJson(const FfdLattice& lattice) {
  std::ostringstream o;
  o << std::setprecision(17);
  auto vec = [&](const Vec3& v) { o << "[" << v[0] << ", " << v[1] << ", " << v[2] << "]"; };
  o << "{\n  \"format\": \"frepcad-lattice\",\n  \"version\": 1,\n  \"rest_min\": ";
  vec(lattice.rest().lo);
  o << ",\n  \"rest_max\": ";
  vec(lattice.rest().hi);
  o << ",\n  \"divisions\": [" << lattice.divisions(0) << ", " << lattice.divisions(1) << ", "
    << lattice.divisions(2) << "],\n  \"points\": [";
  bool first = true;
  for (const Vec3& p : lattice.points()) {
    o << (first ? "\n    " : ",\n    ");
    first = false;
    vec(p);
  }
  o << "\n  ]\n}\n";
  return o.str();
}

void writeLatticeFile(const FfdLattice& lattice, const std::string& path) {
  const std::string text = latticeToJson(lattice);
  AtomicFile f(path);
  f.write(text.data(), text.size());
  f.commit();
}

}  // namespace frep
