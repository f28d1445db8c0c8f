// Welding brick jobs' pieces (base/mesh_piece.h) into one mesh, streaming: pieces
// come in any order, each vertex off the jobs' seams is numbered at once, a seam vertex by its
// key (the one table kept: memory bounded by the seams, not the mesh), and every triangle goes
// to the sink as soon as it is final; a crease flip across two jobs waits for the second
// job's piece. The result is the mesh polygonize makes, up to the order of vertices and
// triangles.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "base/mesh_piece.h"
#include "base/triangle_mesh.h"

namespace frep {

class PieceMerger {
 public:
  struct Sink {
    virtual ~Sink() = default;
    // vertices are numbered in the order they are given here
    virtual void vertex(const Vec3f& position) = 0;
    virtual void triangle(const Triangle& vertices, const Vec3f& a, const Vec3f& b,
                          const Vec3f& c) = 0;
  };

  // The sink that keeps the merged mesh in memory.
  struct MeshCollector : Sink {
    TriangleMesh mesh;
    void vertex(const Vec3f& p) override { mesh.positions.push_back(p); }
    void triangle(const Triangle& t, const Vec3f&, const Vec3f&, const Vec3f&) override {
      mesh.triangles.push_back(t);
    }
  };

  explicit PieceMerger(Sink& sink) : sink_(sink) {}
  // Throws ModelError for a piece of another run or grid, a job given twice, or a piece whose
  // triangles name vertices it does not have.
  void add(const MeshPiece& piece);
  // The triangles still waiting for a partner, as they are; throws ModelError naming the
  // jobs that never came.
  void finish();

  std::size_t vertices() const { return vertices_; }
  // The fan triangles pieces left to the merge (pendingFlips), as the merged mesh has them
  // (flipped or not): by (job << 32 | the piece's triangle number), their corners. A check of
  // the mesh piece by piece takes these with the zone where pieces meet.
  const std::unordered_map<std::uint64_t, std::array<Vec3f, 3>>& settled() const {
    return settled_;
  }

 private:
  struct SeamVertex {
    std::uint32_t id;
    Vec3f position;
  };
  struct Waiting {
    Triangle ids;
    Vec3f corners[3];
    std::uint32_t job, triangle;  // where it came from
  };
  void emit(const Triangle& t, const Vec3f& a, const Vec3f& b, const Vec3f& c);

  Sink& sink_;
  bool started_ = false;
  MeshPiece shape_;  // the first piece's run, job count and grid (no arrays)
  std::vector<bool> seen_;
  std::unordered_map<std::uint64_t, SeamVertex> seam_;
  std::unordered_map<std::uint64_t, Waiting> waiting_;  // by directed edge (a << 32 | b)
  std::unordered_map<std::uint64_t, std::array<Vec3f, 3>> settled_;
  std::size_t vertices_ = 0, triangles_ = 0;
};

// All pieces of a run merged in memory (PieceMerger into a TriangleMesh).
TriangleMesh mergePieces(const std::vector<MeshPiece>& pieces);

}  // namespace frep
