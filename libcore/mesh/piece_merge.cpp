#include "mesh/piece_merge.h"

#include <sstream>
#include <string>

#include "base/errors.h"
#include "mesh/crease_flips.h"

namespace frep {

void PieceMerger::emit(const Triangle& t, const Vec3f& a, const Vec3f& b, const Vec3f& c) {
  sink_.triangle(t, a, b, c);
  ++triangles_;
}

void PieceMerger::add(const MeshPiece& p) {
  auto refuse = [&](const std::string& why) {
    throw ModelError("brick merge: piece of job " + std::to_string(p.job) + ": " + why);
  };
  if (!started_) {
    if (p.jobs == 0) refuse("a run of 0 jobs");
    shape_.runId = p.runId;
    shape_.jobs = p.jobs;
    for (int a = 0; a < 3; ++a) shape_.gridCells[a] = p.gridCells[a];
    seen_.assign(p.jobs, false);
    started_ = true;
  }
  if (p.runId != shape_.runId || p.jobs != shape_.jobs)
    refuse("it belongs to another run (another model, options or job count)");
  for (int a = 0; a < 3; ++a)
    if (p.gridCells[a] != shape_.gridCells[a]) refuse("its grid differs from the other pieces'");
  if (p.job >= p.jobs) refuse("the job number is out of range");
  if (seen_[p.job]) refuse("the job came twice");
  if (p.positions.size() != p.keys.size())
    refuse("it has a key for every vertex but not a position");
  seen_[p.job] = true;

  // the piece's vertices: seam vertices by key, the others numbered now
  std::vector<std::uint32_t> id(p.keys.size());
  for (std::size_t v = 0; v < p.keys.size(); ++v) {
    if (onJobSeam(p, p.keys[v])) {
      const auto [at, isNew] = seam_.try_emplace(
          p.keys[v], SeamVertex{static_cast<std::uint32_t>(vertices_), p.positions[v]});
      if (isNew) {
        sink_.vertex(p.positions[v]);
        ++vertices_;
      }
      id[v] = at->second.id;
    } else {
      id[v] = static_cast<std::uint32_t>(vertices_++);
      sink_.vertex(p.positions[v]);
    }
  }

  std::vector<bool> pending(p.triangles.size(), false);
  for (std::uint32_t t : p.pendingFlips) {
    if (t >= p.triangles.size()) refuse("a pending flip names a triangle it does not have");
    pending[t] = true;
  }
  for (std::size_t t = 0; t < p.triangles.size(); ++t) {
    const Triangle& local = p.triangles[t];
    for (std::uint32_t v : local)
      if (v >= p.keys.size()) refuse("a triangle names a vertex it does not have");
    const Triangle ids = {id[local[0]], id[local[1]], id[local[2]]};
    const Vec3f& a = p.positions[local[0]];
    const Vec3f& b = p.positions[local[1]];
    const Vec3f& c = p.positions[local[2]];
    if (!pending[t]) {
      emit(ids, a, b, c);
      continue;
    }
    // (apex, a, b): its partner is (apex2, b, a), from another job
    const auto partner = waiting_.find((std::uint64_t(ids[2]) << 32) | ids[1]);
    if (partner == waiting_.end()) {
      waiting_.emplace((std::uint64_t(ids[1]) << 32) | ids[2],
                       Waiting{ids, {a, b, c}, p.job, static_cast<std::uint32_t>(t)});
      continue;
    }
    // the pair's four corners, numbered locally for the flip's decision
    const Waiting& w = partner->second;
    const std::vector<Vec3f> corners = {a, b, c, w.corners[0]};
    const Triangle mine = {0, 1, 2}, theirs = {3, 2, 1};
    Triangle f1 = mine, f2 = theirs;
    flipCrease(mine, theirs, corners, &f1, &f2);  // (or f1, f2 stay as they were)
    const std::uint32_t global[4] = {ids[0], ids[1], ids[2], w.ids[0]};
    for (const Triangle& f : {f1, f2})
      emit({global[f[0]], global[f[1]], global[f[2]]}, corners[f[0]], corners[f[1]], corners[f[2]]);
    settled_[(std::uint64_t(p.job) << 32) | t] = {corners[f1[0]], corners[f1[1]], corners[f1[2]]};
    settled_[(std::uint64_t(w.job) << 32) | w.triangle] = {corners[f2[0]], corners[f2[1]],
                                                           corners[f2[2]]};
    waiting_.erase(partner);
  }
}

void PieceMerger::finish() {
  std::ostringstream missing;
  std::size_t count = 0;
  for (std::size_t j = 0; j < seen_.size(); ++j)
    if (!seen_[j]) {
      if (count < 8) missing << (count ? ", " : "") << j;
      ++count;
    }
  if (!started_) throw ModelError("brick merge: no pieces");
  if (count > 0)
    throw ModelError("brick merge: " + std::to_string(count) + " of " +
                     std::to_string(seen_.size()) + " jobs have no piece (jobs " + missing.str() +
                     (count > 8 ? ", ..." : "") + ")");
  for (const auto& [edge, w] : waiting_) {
    emit(w.ids, w.corners[0], w.corners[1], w.corners[2]);
    settled_[(std::uint64_t(w.job) << 32) | w.triangle] = {w.corners[0], w.corners[1],
                                                           w.corners[2]};
  }
  waiting_.clear();
}

TriangleMesh mergePieces(const std::vector<MeshPiece>& pieces) {
  PieceMerger::MeshCollector sink;
  std::size_t vertices = 0, triangles = 0;
  for (const MeshPiece& p : pieces) {
    vertices += p.positions.size();
    triangles += p.triangles.size();
  }
  sink.mesh.positions.reserve(vertices);
  sink.mesh.triangles.reserve(triangles);
  PieceMerger merger(sink);
  for (const MeshPiece& p : pieces) merger.add(p);
  merger.finish();
  return std::move(sink.mesh);
}

}  // namespace frep
