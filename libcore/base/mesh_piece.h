// A piece of a mesh made by one brick job: the mesher's mesh of a box of its
// bricks, with every vertex keyed by the grid edge (or cube) it lies on. Pieces of one grid
// weld by key alone: a vertex on the face two jobs share is computed bit-identically by both,
// so merging pieces is a merge of keys, never a search by position.
#pragma once

#include <cstdint>
#include <vector>

#include "base/triangle_mesh.h"

namespace frep {

struct MeshPiece {
  // Which run the piece belongs to (a fingerprint of the model and the meshing options):
  // pieces of different runs are never merged.
  std::uint64_t runId = 0;
  std::uint32_t job = 0, jobs = 1;        // this piece's job, of how many
  std::int64_t gridCells[3] = {0, 0, 0};  // the grid's cells per axis (its points: one more)
  std::int64_t cellLo[3] = {0, 0, 0}, cellHi[3] = {0, 0, 0};  // the job's cells [lo, hi)
  // Per vertex: the lower grid point's linear index (x + points_x (y + points_y z)) times 7
  // plus the direction (offset bit mask - 1; 6: a vertex inside a cube); after all those, a
  // vertex on the edge from a cube's centre to its corner c: 7 x points + the cube's lowest
  // point's index x 8 + c. Sorted, unique.
  std::vector<std::uint64_t> keys;
  std::vector<Vec3f> positions;
  std::vector<Triangle> triangles;
  // Fan triangles (apex, a, b) whose crease flip (mesh/crease_flips.h) pairs them with a
  // triangle of a neighbouring job: the merge decides them.
  std::vector<std::uint32_t> pendingFlips;
};

// Whether the vertex with this key may also belong to a neighbouring job's piece: its edge
// lies on a face the job shares with another (a cell next to the edge is outside the job).
inline bool onJobSeam(const MeshPiece& p, std::uint64_t key) {
  const std::uint64_t direction = key % 7 + 1;
  std::uint64_t point = key / 7;
  // keys past every grid edge's are on a cube centre's edges (inside one cube): never shared
  if (point >= static_cast<std::uint64_t>((p.gridCells[0] + 1) * (p.gridCells[1] + 1) *
                                          (p.gridCells[2] + 1)))
    return false;
  for (int a = 0; a < 3; ++a) {
    const auto points = static_cast<std::uint64_t>(p.gridCells[a] + 1);
    const auto at = static_cast<std::int64_t>(point % points);
    point /= points;
    if ((direction >> a) & 1) continue;  // the edge runs along a: only cell `at` holds it
    // the cells at - 1 and at hold it; a cell outside the job but inside the grid: shared
    if ((at == p.cellLo[a] && at > 0) || (at == p.cellHi[a] && at < p.gridCells[a])) return true;
  }
  return false;
}

}  // namespace frep
