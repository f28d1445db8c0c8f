// Vertices snapped onto creases and corners, and edges flipped to run along creases, each
// change proved as a collapse is (simplify/region_simplifier.h).
#include "simplify/region_simplifier.h"

namespace frep {
namespace simplifying {

std::size_t RegionSimplifier::snapToFeatures(RegionOutput& out) {
  std::size_t moved = 0;
  for (std::uint32_t l = 0; l < gid_.size(); ++l) {
    if (fixed_[l] || removedLocal_[l]) continue;
    const std::uint32_t g = gid_[l];
    if (o_.creaseCollapsesOnly && !s_.nearCrease[g]) continue;
    Quadric q = s_.quadric[g];
    ring(l, g, neighboursU_);
    for (std::uint32_t w : neighboursU_) q += s_.quadric[w];
    if (q.count <= 0.0) continue;
    if (o_.creaseCollapsesOnly && !q.mayBeSharp(planeCutoff())) continue;  // (a plane)
    int rank = 0;
    const Vec3 p = q.minimiser(planeCutoff(), &rank), here = toVec3(s_.pos[g]);
    if (rank < 2) continue;  // a plane: nothing sharp to put back
    const Vec3 d = sub(p, here);
    // only a move the own planes allow, by less than two cells (a corner the grid cut off
    // lies up to about a cell from the nearest vertex)
    if (dot(d, d) > 4.0 * o_.cell * o_.cell) continue;
    const Quadric& own = s_.quadric[g];
    if (own.count > 0.0 && own.error(p) > own.error(here) + o_.tolerance * o_.tolerance) continue;
    if (q.error(p) + o_.tolerance * o_.tolerance >= q.error(here)) continue;  // no gain
    if (o_.creaseCollapsesOnly && !onCrease(p)) continue;
    moved += relocate(l, p, out);
  }
  return moved;
}

std::size_t RegionSimplifier::flipTowardsCreases(RegionOutput& out) {
  std::size_t flips = 0;
  for (std::uint32_t f = 0; f < faces_.size(); ++f) {
    if (frozenFace_[f] || deadFace_[f] != kLive) continue;
    if (o_.creaseCollapsesOnly && !touchesCrease(s_, faces_[f])) continue;
    for (int k = 0; k < 3; ++k) {
      const Triangle& t = faces_[f];
      const std::uint32_t u = t[k], v = t[(k + 1) % 3];
      const std::uint32_t g = across(f, u, v);
      // each edge once (from the face with the lower index), both faces free to change
      if (g == kNone || g < f || frozenFace_[g]) continue;
      if (!turnsMoreThan(f, g, kFlipTurnCos)) continue;
      if (tryFlip(f, g, u, v, out)) {
        ++flips;
        break;  // (f changed: its edges are the new ones)
      }
    }
  }
  out.flips += flips;
  return flips;
}

bool RegionSimplifier::tryFlip(std::uint32_t f, std::uint32_t g, std::uint32_t u, std::uint32_t v,
                               RegionOutput& out) {
  auto third = [&](std::uint32_t face) {
    const Triangle& t = faces_[face];
    return t[0] != u && t[0] != v ? t[0] : (t[1] != u && t[1] != v ? t[1] : t[2]);
  };
  const std::uint32_t a = third(f), b = third(g);
  const std::uint32_t lu = local(u), lv = local(v), la = local(a), lb = local(b);
  if (a == b || lu == kNone || lv == kNone || la == kNone || lb == kNone) return false;
  if (incomplete_[lu] || incomplete_[lv] || incomplete_[la] || incomplete_[lb]) return false;
  // u and v keep three faces each
  if (around_[lu].size() <= 3 || around_[lv].size() <= 3) return false;
  // The quad's turning before and after (its four outer edges keep their outer faces).
  const std::uint32_t outer[4] = {across(f, v, a), across(f, a, u), across(g, u, b),
                                  across(g, b, v)};
  for (std::uint32_t h : outer)
    if (h == kNone) return false;
  const Vec3f &pu = s_.pos[u], &pv = s_.pos[v], &pa = s_.pos[a], &pb = s_.pos[b];
  const Vec3 nf = triangleCross(pu, pv, pa), ng = triangleCross(pv, pu, pb);    // old pair
  const Vec3 nf2 = triangleCross(pv, pa, pb), ng2 = triangleCross(pu, pb, pa);  // new pair
  auto angle = [](const Vec3& x, const Vec3& y) {
    const double l = std::sqrt(dot(x, x) * dot(y, y));
    return l > 0.0 ? std::acos(std::clamp(dot(x, y) / l, -1.0, 1.0)) : 3.141592653589793;
  };
  auto length = [](const Vec3f& x, const Vec3f& y) { return norm(sub(toVec3(x), toVec3(y))); };
  Vec3 nh[4];
  for (int i = 0; i < 4; ++i) nh[i] = faceNormal(s_.pos, faces_[outer[i]]);
  const double sides[4] = {length(pv, pa), length(pa, pu), length(pu, pb),
                           length(pb, pv)};  // (v a), (a u), (u b), (b v)
  const double before = length(pu, pv) * angle(nf, ng) + sides[0] * angle(nf, nh[0]) +
                        sides[1] * angle(nf, nh[1]) + sides[2] * angle(ng, nh[2]) +
                        sides[3] * angle(ng, nh[3]);
  const double after = length(pa, pb) * angle(nf2, ng2) + sides[0] * angle(nf2, nh[0]) +
                       sides[1] * angle(ng2, nh[1]) + sides[2] * angle(ng2, nh[2]) +
                       sides[3] * angle(nf2, nh[3]);
  if (!(after < before * (1.0 - kFlipGain))) return false;
  // a and b are not joined already (the edge would double)
  ring(la, a, neighboursU_);
  if (std::find(neighboursU_.begin(), neighboursU_.end(), b) != neighboursU_.end()) return false;
  ring(lb, b, neighboursU_);
  if (std::find(neighboursU_.begin(), neighboursU_.end(), a) != neighboursU_.end()) return false;
  changed_.assign({f, g});
  const double worstBefore = recordBefore(changed_);
  const double allowed = allowedFor(changed_, nullptr, 0);
  const Triangle oldF = faces_[f], oldG = faces_[g];
  faces_[f] = {v, a, b};
  faces_[g] = {u, b, a};
  auto restore = [&] {
    faces_[f] = oldF;
    faces_[g] = oldG;
  };
  // The surface moves most along the two diagonals (centres alone miss a crease or corner
  // cut off): the new one's midpoint stays within reach of F = 0, and the surface point
  // nearest the old one's midpoint stays within reach of the new faces.
  {
    auto midpoint = [&](std::uint32_t x, std::uint32_t y) {
      const Vec3 p = toVec3(s_.pos[x]), q = toVec3(s_.pos[y]);
      return Vec3{0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])};
    };
    double value;
    Vec3 n;
    const Vec3 across = midpoint(a, b), along = midpoint(u, v);
    bool near = region_->plane(across, &value, &n) && std::abs(value) <= allowed &&
                region_->plane(along, &value, &n);
    if (near) {
      const Vec3 foot{along[0] - value * n[0], along[1] - value * n[1], along[2] - value * n[2]};
      double closest = HUGE_VAL;
      for (std::uint32_t face : {f, g}) {
        const Triangle& t = faces_[face];
        closest =
            std::min(closest, pointTriangleDistance(foot, toVec3(s_.pos[t[0]]),
                                                    toVec3(s_.pos[t[1]]), toVec3(s_.pos[t[2]])));
      }
      near = closest <= allowed;
    }
    if (!near) {
      restore();
      return false;
    }
  }
  auto drop = [](std::vector<std::uint32_t>& list, std::uint32_t face) {
    list.erase(std::find(list.begin(), list.end(), face));
  };
  // the stars as they will be: u loses f, v loses g, b gains f, a gains g
  drop(around_[lu], f);
  drop(around_[lv], g);
  around_[lb].push_back(f);
  around_[la].push_back(g);
  vMoves_ = false;
  featureMove_ = true;  // (the faces turn by design: the outward test guards against folds)
  flipCorners_ = {u, v, a, b};
  const bool ok = acceptable(changed_, worstBefore, kNone, kNone, allowed, out);
  if (!ok) {
    around_[lu].push_back(f);
    around_[lv].push_back(g);
    drop(around_[lb], f);
    drop(around_[la], g);
    restore();
    return false;
  }
  keepDeviations(changed_);
  for (std::uint32_t face : changed_) {
    faceBox_[face] = boxOf(faces_[face]);
    insert(face);
  }
  for (std::uint32_t l : {lu, lv, la, lb}) ++stamp_[l];
  // samples handed to another corner: copied there, then dropped here (from the back)
  for (const SampleMove& m : sampleMoves_)
    s_.samples[flipCorners_[m.to]].push_back(s_.samples[flipCorners_[m.from]][m.index]);
  for (auto m = sampleMoves_.rbegin(); m != sampleMoves_.rend(); ++m) {
    std::vector<Vec3f>& from = s_.samples[flipCorners_[m->from]];
    from.erase(from.begin() + m->index);
  }
  return true;
}

}  // namespace simplifying
}  // namespace frep
