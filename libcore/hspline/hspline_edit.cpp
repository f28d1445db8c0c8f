// The editing operations of an hspline: refine, move, zero offsets, unrefine (seed 003, 2.3.1).
#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_set>

#include "base/errors.h"
#include "hspline/hspline.h"

namespace frep {

namespace {

std::int64_t key(int i, int j) {
  return (static_cast<std::int64_t>(i) << 32) | static_cast<std::uint32_t>(j);
}

// For each fine index, the coarse vertices whose child block (centre +- 3) holds it.
std::vector<std::vector<int>> blockSources(const SplineAxis& fine,
                                           const std::vector<int>& childCentres) {
  std::vector<std::vector<int>> sources(static_cast<std::size_t>(fine.count()));
  for (std::size_t i = 0; i < childCentres.size(); ++i)
    for (int d = -3; d <= 3; ++d) {
      const int f = fine.wrap(long(childCentres[i]) + d);
      if (f >= 0) sources[static_cast<std::size_t>(f)].push_back(static_cast<int>(i));
    }
  return sources;
}

}  // namespace

void HSpline::refine(int level, const std::vector<std::pair<int, int>>& cvs) {
  checkLevelIndex(level);
  if (cvs.empty())
    throw ModelError("hspline refine: no CVs of level " + std::to_string(level) + " were given");
  for (const auto& [i, j] : cvs)
    if (!find(level, i, j))
      throw ModelError("hspline refine: there is no " + hsCvName(level, i, j) +
                       "; refine acts on CVs the level has");
  const bool added = level == levelCount() - 1;
  if (added) addLevel();
  try {
    const Cache& parent = cache_[static_cast<std::size_t>(level)];
    const HsLevel& coarse = levels_[static_cast<std::size_t>(level)];
    HsLevel& fine = levels_[static_cast<std::size_t>(level) + 1];
    std::unordered_set<std::int64_t> fresh;
    std::vector<HsCv> extra;
    for (const auto& [i, j] : cvs) {
      const int ci = parent.childU[static_cast<std::size_t>(coarse.u.wrap(i))];
      const int cj = parent.childV[static_cast<std::size_t>(coarse.v.wrap(j))];
      for (int b = -3; b <= 3; ++b)
        for (int a = -3; a <= 3; ++a) {
          const int fi = fine.u.wrap(long(ci) + a), fj = fine.v.wrap(long(cj) + b);
          if (fi < 0 || fj < 0 || slotOf(level + 1, fi, fj) >= 0) continue;
          if (fresh.insert(key(fi, fj)).second) extra.push_back({fi, fj, {0, 0, 0}});
        }
    }
    if (cvCount() + extra.size() > kMaxCvs)
      throw ModelError("hspline refine: the hspline would have " +
                       std::to_string(cvCount() + extra.size()) + " CVs, more than the " +
                       std::to_string(kMaxCvs) + " allowed");
    fine.cvs.insert(fine.cvs.end(), extra.begin(), extra.end());
    rebuildIndex(level + 1);
    refreshFrom(level + 1);
  } catch (...) {
    if (added) levels_.pop_back(), cache_.pop_back();
    throw;
  }
}

void HSpline::setValue(int level, int i, int j, const Vec3& value) {
  checkLevelIndex(level);
  const int s = slotOf(level, i, j);
  if (s < 0) throw ModelError("hspline: there is no " + hsCvName(level, i, j));
  if (!(std::isfinite(value[0]) && std::isfinite(value[1]) && std::isfinite(value[2])))
    throw ModelError("hspline: the value of " + hsCvName(level, i, j) + " must be finite");
  levels_[static_cast<std::size_t>(level)].cvs[static_cast<std::size_t>(s)].value = value;
  refreshAround(level, i, j);
}

void HSpline::moveCv(int level, int i, int j, const Vec3& target) {
  checkLevelIndex(level);
  const int s = slotOf(level, i, j);
  if (s < 0) throw ModelError("hspline move: there is no " + hsCvName(level, i, j));
  if (!movable(level, i, j))
    throw ModelError("hspline move: " + hsCvName(level, i, j) +
                     " is fixed: a CV of a refined level moves only when the 7 x 7 block of CVs "
                     "centred on it is all there, so that no crack opens at the border of the "
                     "refined region; refine the CVs around it on level " +
                     std::to_string(level - 1) + " first");
  if (level == 0) return setValue(level, i, j, target);
  // W = P + D: P, where the parent's net puts the CV, does not depend on its own offset.
  const Vec3 parentPoint =
      vsub(position(level, i, j),
           cache_[static_cast<std::size_t>(level)].displacement[static_cast<std::size_t>(s)]);
  const HsFrame f = frame(level, i, j);
  const Vec3 d = vsub(target, parentPoint);
  setValue(level, i, j, {vdot(d, f.tu), vdot(d, f.tv), vdot(d, f.n)});
}

void HSpline::zeroOffsets(const std::vector<HsCvRef>& cvs) {
  int lowest = levelCount();
  for (const HsCvRef& c : cvs) {
    if (c.level == 0)
      throw ModelError("hspline zero offsets: " + hsCvName(c.level, c.i, c.j) +
                       " is on level 0, whose CVs have positions, not offsets");
    checkLevelIndex(c.level);
    if (slotOf(c.level, c.i, c.j) < 0)
      throw ModelError("hspline zero offsets: there is no " + hsCvName(c.level, c.i, c.j));
    lowest = std::min(lowest, c.level);
  }
  for (const HsCvRef& c : cvs)
    levels_[static_cast<std::size_t>(c.level)]
        .cvs[static_cast<std::size_t>(slotOf(c.level, c.i, c.j))]
        .value = {0, 0, 0};
  refreshFrom(lowest);
}

std::size_t HSpline::unrefine() {
  std::size_t removed = 0;
  std::unordered_set<std::int64_t> neededByFiner;
  for (int level = levelCount() - 1; level >= 1; --level) {
    HsLevel& l = levels_[static_cast<std::size_t>(level)];
    std::unordered_set<std::int64_t> keep;
    for (const HsCv& cv : l.cvs) {
      if (neededByFiner.count(key(cv.i, cv.j))) keep.insert(key(cv.i, cv.j));
      if (cv.value == Vec3{0, 0, 0}) continue;
      for (int b = -3; b <= 3; ++b)
        for (int a = -3; a <= 3; ++a) {
          const int i = l.u.wrap(long(cv.i) + a), j = l.v.wrap(long(cv.j) + b);
          if (i >= 0 && j >= 0 && slotOf(level, i, j) >= 0) keep.insert(key(i, j));
        }
    }
    std::vector<HsCv> kept;
    for (const HsCv& cv : l.cvs)
      if (keep.count(key(cv.i, cv.j))) kept.push_back(cv);
    removed += l.cvs.size() - kept.size();
    l.cvs = std::move(kept);
    rebuildIndex(level);
    // The coarse CVs whose refinement made the kept ones stay too.
    const Cache& parent = cache_[static_cast<std::size_t>(level) - 1];
    const auto sourcesU = blockSources(l.u, parent.childU),
               sourcesV = blockSources(l.v, parent.childV);
    neededByFiner.clear();
    for (const HsCv& cv : l.cvs)
      for (int i : sourcesU[static_cast<std::size_t>(cv.i)])
        for (int j : sourcesV[static_cast<std::size_t>(cv.j)]) neededByFiner.insert(key(i, j));
  }
  while (levelCount() > 1 && levels_.back().cvs.empty()) levels_.pop_back(), cache_.pop_back();
  refreshFrom(1);
  return removed;
}

}  // namespace frep
