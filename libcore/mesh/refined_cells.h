// The local refinement's cells (mesh/local_refinement.h): a half cube, or an eighth of one,
// with the lines its neighbours draw on its faces, meshed so that its triangles meet its
// faces only along those lines (docs/mesher.md, "Local refinement"). Internal to the mesh
// layer: the refinement's region, seam and half cubes are in local_refinement.cpp.
#pragma once

#include <cstdint>
#include <map>
#include <stdexcept>
#include <tuple>
#include <unordered_map>
#include <vector>

#include "base/triangle_mesh.h"
#include "frep/field.h"
#include "mesh/edge_roots.h"
#include "mesh/local_refinement.h"
#include "mesh/sampling_grid.h"

namespace frep::refinement {

// Where a vertex goes on an edge whose ends the field does not put on two sides (an end's side
// is the seam's): off the middle, where a split cell samples.
constexpr double kNoRoot = 0.4375;

inline std::uint64_t dirKey(std::uint32_t a, std::uint32_t b) {
  return (std::uint64_t(a) << 32) | b;
}

// A case the refinement does not handle where it met it.
struct Abort : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A directed line of the seam or of a cell's face, by mesh vertex.
struct Seg {
  std::uint32_t from, to;
};

// A cell (a half cube, or an eighth of one) with the lines its neighbours draw on its faces,
// as it runs them, and its corners' sides (corner d at lo + (d & 1, d & 2, d & 4) of the way).
struct Cell {
  double lo[3], hi[3];
  std::vector<Seg> face[6];  // face 2a + side
  bool inside[8];
};

// A face's walk round its rim, counterclockwise seen from outside: corners and crossings.
struct WalkStep {
  bool corner;
  bool inside;      // corners
  std::uint32_t v;  // crossings
};

// A face's lines cut at its midlines: the pieces per quarter (qb + 2 qc, b and c the face's
// axes after its normal) and the cuts per half midline (0, 1: the midline across b, lower and
// upper half along c; 2, 3: across c, halves along b), sorted along it.
struct FaceCut {
  std::vector<Seg> quarter[4];
  std::vector<std::pair<float, std::uint32_t>> halfMid[4];
};

class CellMesher {
 public:
  CellMesher(const Field& field, const Grid& g, TriangleMesh& mesh, LocalRefinementStats& stats)
      : field_(field), g_(g), mesh_(mesh), stats_(stats) {}

  // One loop: a fan from a point inside (the feature point, else the loop's mean). Several:
  // the cell is split in eight with its faces' lines kept, down to a depth, then meshed by
  // a cone of tetrahedra. Triangles go to added().
  void meshCell(const Cell& cell, int depth);
  // Crease flips between neighbouring feature half cubes, where no cut split their line.
  void flipCreases();
  // Cuts face a's lines at its midlines midF (recorded for the triangles sharing them).
  void cutFace(int a, const std::vector<Seg>& segs, const float midF[3], FaceCut* out);
  // The lines across a face from its walk, by one rule both cells sharing it apply alike.
  void pairCrossings(const std::vector<WalkStep>& walk, const double centre[3],
                     std::vector<Seg>* out);
  // The cuts on line u-w, in order from u (every level of them).
  std::vector<std::uint32_t> between(std::uint32_t u, std::uint32_t w) const;
  const std::unordered_map<std::uint64_t, std::vector<std::uint32_t>>& cuts() const {
    return cuts_;
  }
  std::vector<Triangle>& added() { return added_; }
  std::uint32_t newVertex(const Vec3f& p) {
    mesh_.positions.push_back(p);
    return static_cast<std::uint32_t>(mesh_.positions.size() - 1);
  }
  void clear() {
    added_.clear();
    cuts_.clear();
    cutVertex_.clear();
    flippable_.clear();
    normal_.clear();  // (keyed by vertex: new vertices are numbered again)
  }

 private:
  Vec3f clampInto(const Cell& cell, const double x[3]) const;
  const Vec3f& unitNormal(std::uint32_t v);
  bool featureApex(const Cell& cell, const std::vector<std::uint32_t>& loop, Vec3f* apex);
  void coneCell(const Cell& cell);
  void emitFacing(std::uint32_t a, std::uint32_t b, std::uint32_t c, const double o[3], int so,
                  const Vec3f& toward);
  Vec3f rootAlong(const double a[3], double fa, const double b[3]);
  Vec3f rootOnSegment(const double a[3], double fa, const double b[3], int axis);
  std::uint32_t cutVertex(std::uint32_t p, std::uint32_t q, int m, float at, int a);
  void recordCuts(std::uint32_t p, std::uint32_t q, std::vector<std::uint32_t> chain);
  static std::uint64_t undirected(std::uint32_t a, std::uint32_t b);
  void splitCell(const Cell& cell, int depth);
  double sampleAt(double x, double y, double z);

  const Field& field_;
  const Grid& g_;
  TriangleMesh& mesh_;
  LocalRefinementStats& stats_;
  std::vector<Triangle> added_;
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cuts_;  // line -> its cuts
  std::map<std::tuple<std::uint32_t, std::uint32_t, int>, std::uint32_t> cutVertex_;
  std::unordered_map<std::uint64_t, std::uint32_t> flippable_;  // half cube fan edge -> triangle
  std::unordered_map<std::uint32_t, Vec3f> normal_;
};

}  // namespace frep::refinement
