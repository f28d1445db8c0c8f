#include <nlohmann/json.hpp>
#include <sstream>

#include "base/file_names.h"
#include "check/mesh_check.h"
#include "check/printability.h"

namespace frep {

std::string reportToText(const CheckReport& r, const std::string& name) {
  std::ostringstream os;
  os.precision(8);
  os << "check " << displayName(name) << "\n";
  os << "  triangles            " << r.faces << "\n";
  os << "  vertices             " << r.vertices << " (" << r.inputVertices << " before welding)\n";
  os << "  closed               " << (r.closed ? "yes" : "no") << " (" << r.borderEdges
     << " border edges)\n";
  os << "  non-manifold         " << r.nonManifoldEdges << " edges, " << r.nonManifoldVertices
     << " vertices\n";
  os << "  orientation          " << (r.outward ? "outward" : "not outward") << " ("
     << r.misorientedEdges << " inconsistent edges)\n";
  os << "  self-intersections   " << (r.selfIntersectionsAtLeast ? "at least " : "")
     << r.selfIntersections << " triangle pairs\n";
  os << "  degenerate triangles " << r.degenerateFaces << "\n";
  os << "  components           " << r.components << "\n";
  // an open surface encloses nothing: its signed "volume" depends on where the hole is
  if (r.closed)
    os << "  volume               " << r.volume << "\n";
  else
    os << "  volume               none (the surface is open)\n";
  os << "  area                 " << r.area << "\n";
  os << "  bounding box         [" << r.bbox.lo[0] << ", " << r.bbox.lo[1] << ", " << r.bbox.lo[2]
     << "] - [" << r.bbox.hi[0] << ", " << r.bbox.hi[1] << ", " << r.bbox.hi[2] << "]\n";
  if (r.printable()) {
    os << "verdict: printable\n";
  } else {
    os << "verdict: NOT printable\n";
    for (const auto& reason : r.reasons) os << "  - " << reason << "\n";
  }
  return os.str();
}

namespace {

// The largest cavities the text lists and the JSON lists (a foam may hold millions).
constexpr std::size_t kCavitiesListed = 5;
constexpr std::size_t kCavitiesInJson = 1000;

nlohmann::json checkJson(const CheckReport& r, const std::string& name) {
  nlohmann::json j;
  j["file"] = displayName(name);  // valid UTF-8 whatever the file name's bytes
  j["printable"] = r.printable();
  j["reasons"] = r.reasons;
  j["triangles"] = r.faces;
  j["vertices"] = r.vertices;
  j["input_vertices"] = r.inputVertices;
  j["closed"] = r.closed;
  j["border_edges"] = r.borderEdges;
  j["non_manifold_edges"] = r.nonManifoldEdges;
  j["non_manifold_vertices"] = r.nonManifoldVertices;
  j["misoriented_edges"] = r.misorientedEdges;
  j["outward"] = r.outward;
  j["self_intersections"] = r.selfIntersections;
  j["self_intersections_at_least"] = r.selfIntersectionsAtLeast;
  j["degenerate_triangles"] = r.degenerateFaces;
  j["non_finite_vertices"] = r.nonFiniteVertices;
  j["components"] = r.components;
  j["volume"] = r.closed ? nlohmann::json(r.volume) : nlohmann::json(nullptr);
  j["area"] = r.area;
  j["bbox"] = {r.bbox.lo[0], r.bbox.lo[1], r.bbox.lo[2], r.bbox.hi[0], r.bbox.hi[1], r.bbox.hi[2]};
  return j;
}

std::string dump(const nlohmann::json& j) {
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace

std::string reportToJson(const CheckReport& r, const std::string& name) {
  return dump(checkJson(r, name));
}

void addPrintabilityReasons(CheckReport& check, const PrintabilityReport& r,
                            const PrintabilityOptions& o) {
  if (!o.minWall || r.thinTriangles == 0) return;
  std::ostringstream why;
  why << r.thinTriangles << " triangles where the wall is thinner than " << *o.minWall
      << " (thinnest " << r.minWall << ")";
  check.reasons.push_back(why.str());
}

std::string printabilityToText(const PrintabilityReport& r, const PrintabilityOptions& o) {
  std::ostringstream os;
  os.precision(6);
  os << "printability (build direction [" << o.up[0] << ", " << o.up[1] << ", " << o.up[2]
     << "])\n";
  if (r.minWall >= 0)
    os << "  thinnest wall        " << r.minWall << " at [" << r.minWallAt[0] << ", "
       << r.minWallAt[1] << ", " << r.minWallAt[2] << "]\n";
  else
    os << "  thinnest wall        not measured ("
       << (o.thickness ? "no ray met the surface again: an open mesh?"
                       : "the mesh is not printable, so it has no walls to measure")
       << ")\n";
  if (o.minWall)
    os << "  thinner than " << *o.minWall << "    " << r.thinTriangles << " triangles, area "
       << r.thinArea << "\n";
  os << "  overhang             area " << r.overhangArea << " (" << r.overhangTriangles
     << " triangles facing down more than " << o.overhangDeg << " degrees from vertical)\n";
  os << "  height               " << r.height << "\n";
  if (r.cavities > 0) {
    os << "  cavities             " << r.cavities << " enclosed, volume " << r.cavityVolume
       << " (resin and powder printers cannot empty them: add drain holes)\n";
    // The largest few, with where a drain hole would empty each.
    const std::size_t shown = std::min<std::size_t>(r.cavityList.size(), kCavitiesListed);
    for (std::size_t k = 0; k < shown; ++k) {
      const PrintabilityReport::Cavity& c = r.cavityList[k];
      const std::string label = "    cavity " + std::to_string(k + 1);
      os << label << std::string(label.size() < 23 ? 23 - label.size() : 1, ' ') << "volume "
         << c.volume << ", drain at [" << c.drainAt[0] << ", " << c.drainAt[1] << ", "
         << c.drainAt[2] << "]\n";
    }
    if (shown < r.cavityList.size())
      os << "    ... and " << r.cavityList.size() - shown << " smaller (--json lists the largest "
         << kCavitiesInJson << ")\n";
  } else if (r.cavities == 0)
    os << "  cavities             none\n";
  if (o.density > 0)
    os << "  mass                 " << r.mass << " g (density " << o.density
       << " g/cm3, units taken as mm)\n";
  return os.str();
}

std::string printabilityToJson(const CheckReport& check, const PrintabilityReport& r,
                               const PrintabilityOptions& o, const std::string& name) {
  nlohmann::json j = checkJson(check, name);
  nlohmann::json p;
  p["up"] = {o.up[0], o.up[1], o.up[2]};
  p["min_wall"] = r.minWall >= 0 ? nlohmann::json(r.minWall) : nlohmann::json(nullptr);
  p["min_wall_at"] = {r.minWallAt[0], r.minWallAt[1], r.minWallAt[2]};
  if (o.minWall) {
    p["min_wall_required"] = *o.minWall;
    p["thin_triangles"] = r.thinTriangles;
    p["thin_area"] = r.thinArea;
  }
  p["overhang_angle_deg"] = o.overhangDeg;
  p["overhang_area"] = r.overhangArea;
  p["overhang_triangles"] = r.overhangTriangles;
  p["height"] = r.height;
  p["cavities"] = r.cavities >= 0 ? nlohmann::json(r.cavities) : nlohmann::json(nullptr);
  p["cavity_volume"] = r.cavities >= 0 ? nlohmann::json(r.cavityVolume) : nlohmann::json(nullptr);
  nlohmann::json list = nlohmann::json::array();
  for (std::size_t k = 0; k < r.cavityList.size() && k < kCavitiesInJson; ++k) {
    const PrintabilityReport::Cavity& c = r.cavityList[k];
    list.push_back(
        {{"volume", c.volume}, {"drain_at", {c.drainAt[0], c.drainAt[1], c.drainAt[2]}}});
  }
  p["cavity_list"] = list;
  if (o.density > 0) {
    p["density"] = o.density;
    p["mass_g"] = r.mass;
  }
  j["print"] = p;
  return dump(j);
}

}  // namespace frep
