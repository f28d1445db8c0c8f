#include <nlohmann/json.hpp>
#include <sstream>

#include "base/file_names.h"
#include "check/mesh_check.h"

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
  os << "  volume               " << r.volume << "\n";
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

std::string reportToJson(const CheckReport& r, const std::string& name) {
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
  j["volume"] = r.volume;
  j["area"] = r.area;
  j["bbox"] = {r.bbox.lo[0], r.bbox.lo[1], r.bbox.lo[2], r.bbox.hi[0], r.bbox.hi[1], r.bbox.hi[2]};
  return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

}  // namespace frep
