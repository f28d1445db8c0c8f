// One collapse: the merged vertex placed, the faces round it changed, and the change accepted
// only when proved free of intersections and within the tolerance (simplify/region_simplifier.h).
#include "simplify/region_simplifier.h"

namespace frep {
namespace simplifying {

bool RegionSimplifier::relocate(std::uint32_t l, const Vec3& p, RegionOutput& out) {
  const std::uint32_t g = gid_[l];
  const Vec3f at = toVec3f(p);
  if (!std::isfinite(at[0]) || !std::isfinite(at[1]) || !std::isfinite(at[2]) ||
      regions_.of(at) != key_ || at == s_.pos[g])
    return false;
  changed_ = around_[l];
  const double worstBefore = recordBefore(changed_);
  const double allowed = allowedFor(changed_, nullptr, 0);
  const Vec3f old = s_.pos[g];
  s_.pos[g] = at;
  vMoves_ = true;
  featureMove_ = true;
  if (!acceptable(changed_, worstBefore, g, kNone, allowed, out)) {
    s_.pos[g] = old;
    return false;
  }
  keepDeviations(changed_);
  s_.moved[g] = 1;
  for (std::uint32_t f : changed_) {
    faceBox_[f] = boxOf(faces_[f]);
    insert(f);
  }
  return true;
}

bool RegionSimplifier::collapse(const Candidate& c, RegionOutput& out) {
  const std::uint32_t u = c.u, v = c.v, gu = gid_[u], gv = gid_[v];
  if (incomplete_[u] || incomplete_[v]) return false;  // (their rings are not all known)
  // the two faces on the edge, and their third vertices
  std::uint32_t edgeFaces[2], third[2], m = 0;
  for (std::uint32_t f : around_[u])
    if (holds(faces_[f], gv)) {
      if (m == 2) return false;
      edgeFaces[m] = f;
      for (std::uint32_t w : faces_[f])
        if (w != gu && w != gv) third[m] = w;
      ++m;
    }
  if (m != 2 || third[0] == third[1]) return false;
  // link condition: u's and v's neighbours in common are the two third vertices only
  // (closed manifold fans: each face (w, a, b) gives w's ring the vertex after w)
  ring(u, gu, neighboursU_);
  ring(v, gv, neighboursV_);
  std::size_t common = 0;
  for (std::uint32_t w : neighboursU_)
    if (std::find(neighboursV_.begin(), neighboursV_.end(), w) != neighboursV_.end()) {
      if (w != third[0] && w != third[1]) return false;
      ++common;
    }
  if (common != 2) return false;
  // no pillow: the third vertices and v keep at least three faces each
  for (std::uint32_t w : third) {
    const std::uint32_t l = local(w);
    if (l == kNone || around_[l].size() <= 3) return false;
  }
  if (around_[u].size() + around_[v].size() < 7) return false;

  // where v goes: inside this region, as a float
  const Vec3f at = toVec3f(c.at);
  if (!std::isfinite(at[0]) || !std::isfinite(at[1]) || !std::isfinite(at[2]) ||
      regions_.of(at) != key_)
    return false;
  const Vec3f oldV = s_.pos[gv];
  const bool moves = at != oldV;
  if (moves && fixed_[v]) return false;
  vMoves_ = moves;

  // the changed faces: u's (u becomes v) and, when v moves, v's; the edge's two go
  changed_.clear();
  for (std::uint32_t f : around_[u])
    if (f != edgeFaces[0] && f != edgeFaces[1]) changed_.push_back(f);
  if (moves)
    for (std::uint32_t f : around_[v])
      if (f != edgeFaces[0] && f != edgeFaces[1]) changed_.push_back(f);
  double worstBefore = recordBefore(changed_);
  for (int e = 0; e < 2; ++e) {
    const Triangle& t = faces_[edgeFaces[e]];
    worstBefore = std::min(worstBefore, quality(s_.pos[t[0]], s_.pos[t[1]], s_.pos[t[2]]));
  }

  const double allowed = allowedFor(changed_, edgeFaces, 2);
  // apply, test, and undo on failure
  saved_.clear();
  for (std::uint32_t f : changed_) saved_.push_back(faces_[f]);
  for (std::uint32_t f : changed_)
    for (std::uint32_t& w : faces_[f])
      if (w == gu) w = gv;
  s_.pos[gv] = at;
  deadFace_[edgeFaces[0]] = deadFace_[edgeFaces[1]] = kGoingUnderTest;
  const bool ok = acceptable(changed_, worstBefore, gv, gu, allowed, out);
  if (!ok) {
    for (std::size_t i = 0; i < changed_.size(); ++i) faces_[changed_[i]] = saved_[i];
    s_.pos[gv] = oldV;
    deadFace_[edgeFaces[0]] = deadFace_[edgeFaces[1]] = kLive;
    return false;
  }
  deadFace_[edgeFaces[0]] = deadFace_[edgeFaces[1]] = kGone;
  keepDeviations(changed_);
  liveFaces_ -= 2;

  // commit: u is gone, its faces are v's; the edge's faces leave every list
  removedLocal_[u] = 1;
  s_.removed[gu] = 1;
  if (moves) s_.moved[gv] = 1;
  // (a merged vertex sits on the crease now: its new neighbours are near it)
  if (!s_.nearCrease.empty()) s_.nearCrease[gv] = 1;
  s_.quadric[gv] += s_.quadric[gu];
  s_.samples[gv].insert(s_.samples[gv].end(), s_.samples[gu].begin(), s_.samples[gu].end());
  std::vector<Vec3f>().swap(s_.samples[gu]);
  auto drop = [&](std::uint32_t l) {
    std::vector<std::uint32_t>& a = around_[l];
    a.erase(std::remove_if(a.begin(), a.end(),
                           [&](std::uint32_t f) { return f == edgeFaces[0] || f == edgeFaces[1]; }),
            a.end());
  };
  drop(v);
  for (std::uint32_t w : third) drop(local(w));
  for (std::uint32_t f : around_[u])
    if (f != edgeFaces[0] && f != edgeFaces[1]) around_[v].push_back(f);
  around_[u].clear();
  for (std::uint32_t f : changed_) {
    faceBox_[f] = boxOf(faces_[f]);
    insert(f);
  }
  ++stamp_[v];
  for (std::uint32_t w : neighboursU_) {
    const std::uint32_t l = local(w);
    if (l != kNone) ++stamp_[l];
  }
  for (std::uint32_t w : neighboursV_) {
    const std::uint32_t l = local(w);
    if (l != kNone) ++stamp_[l];
  }
  return true;
}

bool RegionSimplifier::linkProved(std::uint32_t w) {
  for (const auto& [vertex, proved] : linkProofs_)
    if (vertex == w) return proved;
  const std::uint32_t l = local(w);
  bool proved = false;
  // (a vertex outside the region, or with faces left out: not all its faces are listed here)
  if (l != kNone && !incomplete_[l]) {
    sectors_.clear();
    for (std::uint32_t f : around_[l]) {
      if (deadFace_[f] != kLive) continue;
      const Triangle& t = faces_[f];
      const int k = t[0] == w ? 0 : (t[1] == w ? 1 : 2);
      sectors_.emplace_back(t[(k + 1) % 3], t[(k + 2) % 3]);
    }
    proved = fanProvedEmbedded(s_.pos, w, sectors_.data(), sectors_.size());
  }
  linkProofs_.emplace_back(w, proved);
  return proved;
}

bool RegionSimplifier::acceptable(const std::vector<std::uint32_t>& changed, double worstBefore,
                                  std::uint32_t gv, std::uint32_t gu, double allowed,
                                  RegionOutput& out) {
  if (changed.empty()) return false;
  if (s_.zone) {  // (a face of the pass's work zone: none left out can meet it)
    FaceBox zone = boxOf(faces_[changed[0]]);
    for (std::uint32_t f : changed) zone.grow(boxOf(faces_[f]));
    if (!s_.zone->covers(zone.lo, zone.hi)) return false;
  }
  const double floorQuality = std::min(featureMove_ ? kFeatureQuality : kQuality, worstBefore);
  for (std::size_t i = 0; i < changed.size(); ++i) {
    const Triangle& t = faces_[changed[i]];
    if (quality(s_.pos[t[0]], s_.pos[t[1]], s_.pos[t[2]]) < floorQuality) return false;
    // (a vertex put on a corner may turn its faces further: the outward test below, against
    // the field's gradient, is their guard against folding)
    const Vec3 n = faceNormal(s_.pos, t), before = normalsBefore_[i];
    if (!featureMove_ && dot(n, before) < kTurn * std::sqrt(dot(n, n) * dot(before, before)))
      return false;
    if (o_.maxEdge > 0.0)
      for (int k = 0; k < 3; ++k) {
        const Vec3 d = sub(toVec3(s_.pos[t[k]]), toVec3(s_.pos[t[(k + 1) % 3]]));
        if (dot(d, d) > o_.maxEdge * o_.maxEdge) return false;
      }
    if (collinear(s_.pos[t[0]], s_.pos[t[1]], s_.pos[t[2]])) return false;
  }
  // the surface stays near F = 0: at v and at each changed face's centre
  double largest = 0.0;
  if (vMoves_) {
    largest = region_->distance(toVec3(s_.pos[gv]));
    if (!(largest <= allowed)) return false;
  }
  newDeviation_.clear();
  // and each changed face faces out: against the gradient at its centre (a small part
  // collapsed into itself, turned inside out, fails here); the centres in one batch
  const std::size_t m = changed.size();
  centres_.resize(m);
  values_.resize(m);
  gradients_.resize(m);
  planeOk_.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    const Triangle& t = faces_[changed[i]];
    centres_[i] = {0, 0, 0};
    for (std::uint32_t w : t)
      for (int a = 0; a < 3; ++a) centres_[i][a] += s_.pos[w][a] / 3.0;
  }
  region_->planes(centres_.data(), m, values_.data(), gradients_.data(), planeOk_.data());
  for (std::size_t i = 0; i < m; ++i) {
    if (!planeOk_[i]) return false;
    const double d = std::abs(values_[i]);
    if (!(d <= allowed)) return false;
    if (!(dot(faceNormal(s_.pos, faces_[changed[i]]), gradients_[i]) < 0.0)) return false;
    largest = std::max(largest, d);
    newDeviation_.push_back(static_cast<float>(d));
  }
  // every surface point v now stands for (u's and v's) stays within the tolerance of v's
  // faces as they will be
  if (gv == kNone ? !quadSamplesCovered() : !samplesCovered(gv, gu)) return false;
  // no changed face meets another face (the changed ones among themselves too: the grid
  // still lists them where they were)
  // (only pairs whose boxes meet can intersect: the check tests no others either)
  // One search for the whole fan (its faces share most of their cells), then each
  // candidate against each changed face whose box it meets.
  // Two faces of v's fan cannot meet where the fan is proved embedded (the check's own proof,
  // check/face_pair_test.h): every changed face is one of them, so then only the faces off
  // the fan are tested. (A flip has no such vertex: its faces are tested pair by pair.)
  bool fanProved = false;
  if (gv != kNone) {
    sectors_.clear();
    for (std::uint32_t l : {local(gv), gu == kNone ? kNone : local(gu)}) {
      if (l == kNone) continue;
      for (std::uint32_t f : around_[l]) {  // (u's faces hold v now)
        if (deadFace_[f] != kLive) continue;
        const Triangle& t = faces_[f];
        const int k = t[0] == gv ? 0 : (t[1] == gv ? 1 : 2);
        sectors_.emplace_back(t[(k + 1) % 3], t[(k + 2) % 3]);
      }
    }
    fanProved = fanProvedEmbedded(s_.pos, gv, sectors_.data(), sectors_.size());
  }
  boxes_.resize(changed.size());
  FaceBox all = boxOf(faces_[changed[0]]);
  for (std::size_t i = 0; i < changed.size(); ++i) {
    boxes_[i] = boxOf(faces_[changed[i]]);
    all.grow(boxes_[i]);
  }
  near(all, nearby_);  // (sets visit_ of every face found to visitStamp_)
  ++visitStamp_;
  for (std::uint32_t f : changed) visit_[f] = visitStamp_;  // the changed ones: below
  linkProofs_.clear();
  for (std::uint32_t g : nearby_) {
    if (visit_[g] == visitStamp_) continue;
    const FaceBox& bg = faceBox_[g];
    if (!all.meets(bg) || (fanProved && holds(faces_[g], gv))) continue;
    for (std::size_t i = 0; i < changed.size(); ++i)
      if (boxes_[i].meets(bg) && !inProvedFan(faces_[changed[i]], faces_[g], gv) &&
          facesIntersect(s_.pos, faces_[changed[i]], faces_[g]))
        return false;
  }
  for (std::size_t i = 0; i < changed.size() && !fanProved; ++i)
    for (std::size_t j = i + 1; j < changed.size(); ++j)
      if (boxes_[i].meets(boxes_[j]) && !inProvedFan(faces_[changed[i]], faces_[changed[j]], gv) &&
          facesIntersect(s_.pos, faces_[changed[i]], faces_[changed[j]]))
        return false;
  out.largestDistance = std::max(out.largestDistance, largest);
  return true;
}

}  // namespace simplifying
}  // namespace frep
