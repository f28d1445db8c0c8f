// The check of a mesh held in parts (brick pieces), one part in memory at a time:
// the report checkMesh gives for the whole mesh, but the memory of one part plus the zone
// where parts meet.
//
// Every part declares a box that holds all its vertices. Two triangles of different parts can
// then only meet, and two vertices of different parts only coincide, where their boxes
// overlap: the zone. Each part is judged alone for everything whose faces all lie in it:
// - its vertices outside the zone and their edges;
// - pairs of its own faces;
// - its degenerate faces, area, volume and bounding box;
// - its components.
// The faces that reach into the zone are kept, welded across parts and judged once:
// - their vertices inside the zone and the edges between two of them;
// - the pairs of faces from different parts (all pairs of the zone's faces, less those of
//   each part's own zone faces);
// - the joins of the parts' components.
// Nesting (several components) is decided by the check's rays, counted part by part.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "base/triangle_mesh.h"
#include "base/vec.h"
#include "check/mesh_check.h"

namespace frep {

class PartitionedCheck {
 public:
  // `boxes`: each part's box (closed; every vertex of the part must lie in it, else
  // addPart says so and the caller checks the whole mesh instead).
  explicit PartitionedCheck(std::vector<Box3> boxes);
  ~PartitionedCheck();
  PartitionedCheck(const PartitionedCheck&) = delete;
  PartitionedCheck& operator=(const PartitionedCheck&) = delete;

  // Judges part `index` (each once, any order); false when a vertex lies outside its box.
  bool addPart(std::size_t index, const TriangleMesh& part);
  // The same judgement made where the part is (a brick job's worker), as a summary of a few
  // per cent of the part (its counts, its components' facts, its zone faces), and taken in
  // here. addSummary throws FileError for a summary that is not one.
  static std::vector<char> judgePart(const std::vector<Box3>& boxes, std::size_t index,
                                     const TriangleMesh& part);
  bool addSummary(std::size_t index, const std::vector<char>& summary);
  // Faces made after the parts were judged (the merge's crease flips across brick jobs),
  // judged with the zone: every corner must lie where two boxes overlap (else finish decides
  // nothing). part(i) in finish gives the parts without them.
  void addZoneFaces(const TriangleMesh& faces);

  // The report for the whole mesh. `inputVertices`: the whole mesh's vertex count (the parts
  // repeat their shared vertices). `part(i)` gives part i again (the nesting rays count
  // crossings part by part). Returns nothing where the parts cannot decide what checkMesh
  // would (a non-polygon mesh, whose self-intersections CGAL counts on the whole soup, or a
  // nesting the rays cannot settle): the caller checks the whole mesh then.
  std::optional<CheckReport> finish(std::size_t inputVertices,
                                    const std::function<TriangleMesh(std::size_t)>& part);

 private:
  void absorb(std::size_t index, const void* contribution);
  struct State;
  State* s_;
};

}  // namespace frep
