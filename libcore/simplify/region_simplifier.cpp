// A region's simplification (simplify/region_simplifier.h): its set-up, the grid of its
// faces, and the loop that collapses its edges by cost.
#include "simplify/region_simplifier.h"

namespace frep {
namespace simplifying {

void RegionSimplifier::run(const RegionInput& in, RegionOutput& out) {
  key_ = in.key;
  setUp(in);
  // Edges, shortest first (the grid's slivers go first); each is tried in both directions,
  // where v goes found when it is tried. An entry is stale once either end has changed.
  heap_.clear();
  auto push = [&](std::uint32_t a, std::uint32_t b) {
    if (a == kNone || b == kNone || (fixed_[a] && fixed_[b])) return;
    if (o_.creaseCollapsesOnly && !s_.nearCrease[gid_[a]] && !s_.nearCrease[gid_[b]]) return;
    const Vec3 d = sub(toVec3(s_.pos[gid_[a]]), toVec3(s_.pos[gid_[b]]));
    heap_.push_back({dot(d, d), a, b, stamp_[a], stamp_[b]});
    std::push_heap(heap_.begin(), heap_.end(), std::greater<EdgeEntry>());
  };
  for (std::uint32_t f = 0; f < faces_.size(); ++f) {
    if (frozenFace_[f]) continue;
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = local(faces_[f][k]), b = local(faces_[f][(k + 1) % 3]);
      if (a < b) push(a, b);  // each edge once: (a, b) in one face, (b, a) in the other
    }
  }
  while (!heap_.empty()) {
    std::pop_heap(heap_.begin(), heap_.end(), std::greater<EdgeEntry>());
    const EdgeEntry e = heap_.back();
    heap_.pop_back();
    if (removedLocal_[e.a] || removedLocal_[e.b] || stamp_[e.a] != e.stampA ||
        stamp_[e.b] != e.stampB)
      continue;
    std::uint32_t v = kNone;
    for (int direction = 0; direction < 2 && v == kNone; ++direction) {
      Candidate c{direction ? e.b : e.a, direction ? e.a : e.b, Vec3{0, 0, 0}};
      if (fixed_[c.u]) continue;
      // Where v goes: it stays when fixed or without sharp features; else the merged
      // quadric's minimiser. A merged vertex that cannot go there may still stay where v
      // is, with sharp features only where that keeps it near every plane it carries:
      // within tolerance^2 of the quadric's least (else a corner or crease would be
      // rounded off).
      const Vec3 here = toVec3(s_.pos[gid_[c.v]]);
      Quadric q;
      Vec3 best = here;
      double least = 0.0;
      int rank = 0;
      if (o_.sharpFeatures) {
        q = merged(c.u, c.v);
        // (onto creases only: a merge whose planes cannot make a crease is not one)
        if (o_.creaseCollapsesOnly && !q.mayBeSharp(planeCutoff())) continue;
        if (q.count > 0.0) {
          best = q.minimiser(planeCutoff(), &rank);
          least = q.error(best);
        }
      }
      auto admissible = [&](const Vec3& p) {
        return !o_.sharpFeatures || q.count <= 0.0 ||
               q.error(p) <= least + o_.tolerance * o_.tolerance;
      };
      c.at = fixed_[c.v] ? here : best;
      featureMove_ = !fixed_[c.v] && rank >= 2;
      if (o_.creaseCollapsesOnly && !(featureMove_ && onCrease(c.at))) continue;
      bool done = admissible(c.at) && collapse(c, out);
      if (!done && !o_.creaseCollapsesOnly && toVec3f(c.at) != s_.pos[gid_[c.v]]) {
        c.at = here;
        featureMove_ = false;
        done = admissible(here) && collapse(c, out);
      }
      if (done) v = c.v;
    }
    if (v == kNone) continue;
    ++out.collapses;
    if (2 * liveFaces_ < liveAtBuild_) buildGrid();
    ring(v, gid_[v], neighboursU_);
    for (std::uint32_t w : neighboursU_) push(v, local(w));
  }
  // a vertex on a crease lets its neighbours find the crease too: sweep until none moves
  if (o_.sharpFeatures) {
    for (int sweep = 0; sweep < 4 && snapToFeatures(out) > 0; ++sweep) {
    }
    for (int sweep = 0; o_.creaseFlips && in.flipPass && sweep < 4 && flipTowardsCreases(out) > 0;
         ++sweep) {
    }
  }
  for (std::uint32_t f = 0; f < faces_.size(); ++f)
    if (!frozenFace_[f] && deadFace_[f] == kLive) out.faces.push_back(faces_[f]);
}

void RegionSimplifier::setUp(const RegionInput& in) {
  // the global -> local map is kept per thread, all kNone between regions
  if (localOf_.size() != s_.pos.size()) localOf_.assign(s_.pos.size(), kNone);
  for (std::uint32_t g : gid_) localOf_[g] = kNone;
  gid_.clear();
  faces_.clear();
  frozenFace_.clear();
  for (std::size_t i = 0; i < in.innerCount; ++i) {
    faces_.push_back(all_[in.inner[i]]);
    frozenFace_.push_back(0);
  }
  for (std::size_t i = 0; i < in.frozenCount; ++i) {
    faces_.push_back(all_[in.frozen[i]]);
    frozenFace_.push_back(1);
  }
  deadFace_.assign(faces_.size(), kLive);
  deviation_.assign(faces_.size(), std::numeric_limits<float>::quiet_NaN());
  // the region's vertices: those of its faces that lie in it, each listed once (marked in
  // localOf_ as it is met, those outside too), then in order
  constexpr std::uint32_t kSeen = kNone - 1;
  outside_.clear();
  for (const Triangle& t : faces_)
    for (std::uint32_t v : t) {
      if (localOf_[v] != kNone) continue;
      localOf_[v] = kSeen;
      (regions_.of(s_.pos[v]) == key_ ? gid_ : outside_).push_back(v);
    }
  for (std::uint32_t g : outside_) localOf_[g] = kNone;
  std::sort(gid_.begin(), gid_.end());
  const std::size_t n = gid_.size();
  for (std::uint32_t l = 0; l < n; ++l) localOf_[gid_[l]] = l;
  // (the lists are cleared, not freed: the next region reuses them)
  if (around_.size() < n) around_.resize(n);
  for (std::size_t l = 0; l < n; ++l) around_[l].clear();
  fixed_.assign(n, 0);
  incomplete_.assign(n, 0);
  if (!s_.incomplete.empty())
    for (std::uint32_t l = 0; l < n; ++l) fixed_[l] = incomplete_[l] = s_.incomplete[gid_[l]];
  removedLocal_.assign(n, 0);
  stamp_.assign(n, 0);
  for (std::uint32_t f = 0; f < faces_.size(); ++f)
    for (std::uint32_t v : faces_[f]) {
      const std::uint32_t l = local(v);
      if (l == kNone) continue;
      around_[l].push_back(f);
      if (frozenFace_[f]) fixed_[l] = 1;
    }
  for (int a = 0; a < 3; ++a) {
    const std::int64_t i =
        static_cast<std::int64_t>((key_ >> (21 * a)) & ((1u << 21) - 1)) - (std::int64_t(1) << 20);
    regionLo_[a] = regions_.origin[a] + static_cast<double>(i) * regions_.side;
  }
  Box3 box;
  for (int a = 0; a < 3; ++a) {
    box.lo[a] = regionLo_[a];
    box.hi[a] = regionLo_[a] + regions_.side;
  }
  region_.emplace(specialiseInto(field_, box, regionField_), o_.bbox);
  visit_.assign(faces_.size(), 0);
  inCell_.assign(faces_.size(), 0);
  visitStamp_ = cellStamp_ = 0;
  faceBox_.resize(faces_.size());
  for (std::uint32_t f = 0; f < faces_.size(); ++f) faceBox_[f] = boxOf(faces_[f]);
  liveFaces_ = faces_.size();
  buildGrid();
}

void RegionSimplifier::buildGrid() {
  double sum = 0.0;
  std::size_t live = 0;
  for (std::uint32_t f = 0; f < faces_.size(); ++f) {
    if (deadFace_[f] != kLive) continue;
    const FaceBox& b = faceBox_[f];
    sum += std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
    ++live;
  }
  gridCell_ = std::max(o_.cell, live ? sum / static_cast<double>(live) : o_.cell);
  for (int a = 0; a < 3; ++a) gridLo_[a] = regionLo_[a] - o_.cell;
  gridDim_ =
      std::max(1, std::min(o_.regionCells + 2,
                           static_cast<int>(std::ceil((regions_.side + 2 * o_.cell) / gridCell_))));
  grid_.resize(static_cast<std::size_t>(gridDim_) * gridDim_ * gridDim_);
  for (std::vector<std::uint32_t>& cell : grid_) cell.clear();
  for (std::uint32_t f = 0; f < faces_.size(); ++f)
    if (deadFace_[f] == kLive) insert(f);
  liveAtBuild_ = live;
}

void RegionSimplifier::near(const FaceBox& box, std::vector<std::uint32_t>& out) {
  out.clear();
  ++visitStamp_;
  int lo[3], hi[3];
  cellRange(box, lo, hi);
  for (int k = lo[2]; k <= hi[2]; ++k)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int i = lo[0]; i <= hi[0]; ++i) {
        std::vector<std::uint32_t>& cell =
            grid_[(static_cast<std::size_t>(k) * gridDim_ + j) * gridDim_ + i];
        ++cellStamp_;
        std::size_t kept = 0;
        for (std::uint32_t g : cell) {
          // gone for good: dropped; gone only for the collapse under test: kept listed
          if (deadFace_[g] == kGone || inCell_[g] == cellStamp_) continue;
          inCell_[g] = cellStamp_;
          cell[kept++] = g;
          if (deadFace_[g] != kLive) continue;
          if (visit_[g] != visitStamp_) {
            visit_[g] = visitStamp_;
            out.push_back(g);
          }
        }
        cell.resize(kept);
      }
}

}  // namespace simplifying
}  // namespace frep
