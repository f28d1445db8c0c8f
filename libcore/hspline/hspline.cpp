#include "hspline/hspline.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>
#include <unordered_set>

#include "base/errors.h"

namespace frep {

namespace {

std::int64_t key(int i, int j) {
  return (static_cast<std::int64_t>(i) << 32) | static_cast<std::uint32_t>(j);
}

bool finite(const Vec3& p) {
  return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

HsFrame frameOf(const Vec3& du, const Vec3& dv) {
  HsFrame f;
  const Vec3 n = vcross(du, dv);
  const double lu = vlength(du), lv = vlength(dv), ln = vlength(n);
  // A degenerate parent point (a pole, a collapsed edge) keeps the world frame, so offsets
  // there stay defined; a smooth parent always takes the first branch.
  if (ln > 1e-12 * lu * lv && ln > 0) {
    f.tu = vscale(du, 1 / lu);
    f.n = vscale(n, 1 / ln);
    f.tv = vcross(f.n, f.tu);
  }
  return f;
}

HsInterval supportOf(const SplineAxis& a, int i) {
  return {a.knot(i), a.knot(i + 4), false};
}

bool holds(const SplineAxis& a, const HsInterval& s, double t) {
  if (s.all) return true;
  if (a.isPeriodic()) t += std::round((0.5 * (s.lo + s.hi) - t) / a.period()) * a.period();
  return t >= s.lo && t <= s.hi;
}

HsInterval merged(const SplineAxis& a, const HsInterval& s, HsInterval t) {
  if (s.all || t.all) return {0, 0, true};
  if (a.isPeriodic()) {
    const double shift =
        std::round((0.5 * (s.lo + s.hi) - 0.5 * (t.lo + t.hi)) / a.period()) * a.period();
    t.lo += shift, t.hi += shift;
  }
  HsInterval m{std::min(s.lo, t.lo), std::max(s.hi, t.hi), false};
  if (a.isPeriodic() && m.hi - m.lo >= a.period()) m.all = true;
  return m;
}

Vec3 displacementOf(const HsFrame& f, const Vec3& o) {
  Vec3 d = vscale(f.tu, o[0]);
  vaxpy(d, o[1], f.tv);
  vaxpy(d, o[2], f.n);
  return d;
}

}  // namespace

std::string hsCvName(int level, int i, int j) {
  return "CV (level " + std::to_string(level) + ", i " + std::to_string(i) + ", j " +
         std::to_string(j) + ")";
}

Vec3 HsSurfacePoint::normal() const {
  const Vec3 n = vcross(du, dv);
  const double l = vlength(n);
  return l > 0 ? vscale(n, 1 / l) : Vec3{0, 0, 0};
}

HSpline::HSpline(SplineAxis u, SplineAxis v, std::vector<Vec3> positions) {
  const std::size_t nu = static_cast<std::size_t>(u.count()),
                    nv = static_cast<std::size_t>(v.count());
  if (positions.size() != nu * nv)
    throw ModelError("hspline level 0: " + std::to_string(positions.size()) +
                     " CV positions given, " + std::to_string(nu) + " x " + std::to_string(nv) +
                     " = " + std::to_string(nu * nv) + " expected");
  HsLevel base{std::move(u), std::move(v), {}};
  base.cvs.reserve(positions.size());
  for (std::size_t j = 0; j < nv; ++j)
    for (std::size_t i = 0; i < nu; ++i) {
      const Vec3& p = positions[i + nu * j];
      if (!finite(p))
        throw ModelError("hspline: " + hsCvName(0, int(i), int(j)) +
                         " has a position that is not finite");
      base.cvs.push_back({int(i), int(j), p});
    }
  levels_.push_back(std::move(base));
  cache_.resize(1);
  rebuildIndex(0);
  refreshFrom(0);
}

std::size_t HSpline::cvCount() const {
  std::size_t n = 0;
  for (const HsLevel& l : levels_) n += l.cvs.size();
  return n;
}

void HSpline::checkLevelIndex(int level) const {
  if (level < 0 || level >= levelCount())
    throw ModelError("hspline: there is no level " + std::to_string(level) +
                     "; it has levels 0 to " + std::to_string(levelCount() - 1));
}

int HSpline::slotOf(int level, int i, int j) const {
  const HsLevel& l = levels_[static_cast<std::size_t>(level)];
  const int wi = l.u.wrap(i), wj = l.v.wrap(j);
  if (wi < 0 || wj < 0) return -1;
  const Cache& c = cache_[static_cast<std::size_t>(level)];
  const int a = wi - c.i0, b = wj - c.j0;
  if (a < 0 || b < 0 || a >= c.ni || b >= c.nj) return -1;
  return c.slot[static_cast<std::size_t>(a) +
                static_cast<std::size_t>(c.ni) * static_cast<std::size_t>(b)];
}

const HsCv* HSpline::find(int level, int i, int j) const {
  if (level < 0 || level >= levelCount()) return nullptr;
  const int s = slotOf(level, i, j);
  return s < 0 ? nullptr
               : &levels_[static_cast<std::size_t>(level)].cvs[static_cast<std::size_t>(s)];
}

bool HSpline::movable(int level, int i, int j) const {
  if (!find(level, i, j)) return false;
  if (level == 0) return true;
  const HsLevel& l = levels_[static_cast<std::size_t>(level)];
  for (int b = -3; b <= 3; ++b)
    for (int a = -3; a <= 3; ++a) {
      if (l.u.wrap(long(i) + a) < 0 || l.v.wrap(long(j) + b) < 0)
        continue;  // beyond the grid's edge
      if (slotOf(level, i + a, j + b) < 0) return false;
    }
  return true;
}

void HSpline::rebuildIndex(int level) {
  HsLevel& l = levels_[static_cast<std::size_t>(level)];
  Cache& c = cache_[static_cast<std::size_t>(level)];
  std::sort(l.cvs.begin(), l.cvs.end(),
            [](const HsCv& a, const HsCv& b) { return a.j != b.j ? a.j < b.j : a.i < b.i; });
  c.slot.clear();
  if (l.cvs.empty()) {
    c.i0 = c.j0 = c.ni = c.nj = 0;
    return;
  }
  int i0 = l.cvs[0].i, i1 = i0, j0 = l.cvs[0].j, j1 = j0;
  for (const HsCv& cv : l.cvs)
    i0 = std::min(i0, cv.i), i1 = std::max(i1, cv.i), j0 = std::min(j0, cv.j),
    j1 = std::max(j1, cv.j);
  c.i0 = i0, c.j0 = j0, c.ni = i1 - i0 + 1, c.nj = j1 - j0 + 1;
  c.slot.assign(static_cast<std::size_t>(c.ni) * static_cast<std::size_t>(c.nj), -1);
  for (std::size_t k = 0; k < l.cvs.size(); ++k) {
    const HsCv& cv = l.cvs[k];
    auto& s = c.slot[static_cast<std::size_t>(cv.i - i0) +
                     static_cast<std::size_t>(c.ni) * static_cast<std::size_t>(cv.j - j0)];
    if (s >= 0) throw ModelError("hspline: " + hsCvName(level, cv.i, cv.j) + " is given twice");
    s = static_cast<std::int32_t>(k);
  }
}

void HSpline::addLevel() {
  const HsLevel& last = levels_.back();
  if (levelCount() >= kMaxLevels)
    throw ModelError("hspline: a refinement would make level " + std::to_string(levelCount()) +
                     "; at most " + std::to_string(kMaxLevels) + " levels (0 to " +
                     std::to_string(kMaxLevels - 1) + ") are allowed");
  SplineAxis u = last.u.refined(), v = last.v.refined();
  if (static_cast<std::size_t>(u.count()) * static_cast<std::size_t>(v.count()) > kMaxLevelGrid)
    throw ModelError("hspline: level " + std::to_string(levelCount()) + " would have a grid of " +
                     std::to_string(u.count()) + " x " + std::to_string(v.count()) +
                     " CVs, more than the " + std::to_string(kMaxLevelGrid) + " allowed");
  Cache c;
  c.rowsU = last.u.rowsOnto(u);
  c.rowsV = last.v.rowsOnto(v);
  cache_.back().childU = last.u.childCentres(u);
  cache_.back().childV = last.v.childCentres(v);
  levels_.push_back({std::move(u), std::move(v), {}});
  cache_.push_back(std::move(c));
}

std::pair<double, double> HSpline::referenceParameter(int level, int i, int j) const {
  checkLevelIndex(level);
  const HsLevel& l = levels_[static_cast<std::size_t>(level)];
  return {l.u.reference(i), l.v.reference(j)};
}

void HSpline::addLevel(HsSurfacePoint& p, int level, const SpanBasis& bu,
                       const SpanBasis& bv) const {
  const HsLevel& l = levels_[static_cast<std::size_t>(level)];
  const Cache& c = cache_[static_cast<std::size_t>(level)];
  for (int b = 0; b < 4; ++b) {
    const int j = l.v.wrap(bv.span - 3 + b) - c.j0;
    if (j < 0 || j >= c.nj) continue;
    for (int a = 0; a < 4; ++a) {
      const int i = l.u.wrap(bu.span - 3 + a) - c.i0;
      if (i < 0 || i >= c.ni) continue;
      const int s = c.slot[static_cast<std::size_t>(i) +
                           static_cast<std::size_t>(c.ni) * static_cast<std::size_t>(j)];
      if (s < 0) continue;
      p.add(bu, bv, a, b, c.displacement[static_cast<std::size_t>(s)]);
    }
  }
}

HsSurfacePoint HSpline::evaluate(double u, double v, int upTo) const {
  HsSurfacePoint p;
  const int last = upTo < 0 ? levelCount() - 1 : std::min(upTo, levelCount() - 1);
  for (int level = 0; level <= last; ++level) {
    const HsLevel& l = levels_[static_cast<std::size_t>(level)];
    if (!l.cvs.empty()) addLevel(p, level, l.u.basis(u), l.v.basis(v));
  }
  return p;
}

std::vector<HsSurfacePoint> HSpline::evaluateGrid(
    const std::vector<double>& us, const std::vector<double>& vs,
    const std::vector<std::pair<std::size_t, std::size_t>>& runs) const {
  // Each level's basis once per column and per row that the runs touch, not once per point.
  const std::size_t nu = us.size(), total = nu * vs.size();
  std::vector<char> column(nu, 0), row(vs.size(), 0);
  std::size_t count = 0;
  for (const auto& [first, n] : runs)
    for (std::size_t at = first; at < first + n && at < total; ++at)
      column[at % nu] = row[at / nu] = 1, ++count;
  std::vector<HsSurfacePoint> out;
  out.reserve(count);
  std::vector<std::vector<SpanBasis>> bu(levels_.size()), bv(levels_.size());
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    if (levels_[l].cvs.empty()) continue;
    bu[l].resize(nu), bv[l].resize(vs.size());
    for (std::size_t a = 0; a < nu; ++a)
      if (column[a]) bu[l][a] = levels_[l].u.basis(us[a]);
    for (std::size_t b = 0; b < vs.size(); ++b)
      if (row[b]) bv[l][b] = levels_[l].v.basis(vs[b]);
  }
  for (const auto& [first, n] : runs)
    for (std::size_t at = first; at < first + n && at < total; ++at) {
      HsSurfacePoint p;
      for (std::size_t l = 0; l < levels_.size(); ++l)
        if (!levels_[l].cvs.empty()) addLevel(p, int(l), bu[l][at % nu], bv[l][at / nu]);
      out.push_back(p);
    }
  return out;
}

HsFrame HSpline::frame(int level, int i, int j) const {
  checkLevelIndex(level);
  if (level == 0) return HsFrame{};
  const auto [u, v] = referenceParameter(level, i, j);
  const HsSurfacePoint p = evaluate(u, v, level - 1);
  return frameOf(p.du, p.dv);
}

void HSpline::refreshFrom(int from) {
  for (int level = std::max(from, 0); level < levelCount(); ++level) {
    const HsLevel& l = levels_[static_cast<std::size_t>(level)];
    Cache& c = cache_[static_cast<std::size_t>(level)];
    c.displacement.resize(l.cvs.size());
    for (std::size_t k = 0; k < l.cvs.size(); ++k) {
      const HsCv& cv = l.cvs[k];
      if (level == 0) {
        c.displacement[k] = cv.value;
        continue;
      }
      if (cv.value == Vec3{0, 0, 0}) {
        c.displacement[k] = {0, 0, 0};  // exactly nothing, whatever the frame
        continue;
      }
      c.displacement[k] = displacementOf(frame(level, cv.i, cv.j), cv.value);
    }
  }
}

template <class Visit>
HsRegion HSpline::walkReach(int level, int i, int j, Visit visit) const {
  const HsLevel& own = levels_[static_cast<std::size_t>(level)];
  HsRegion r{supportOf(own.u, i), supportOf(own.v, j)};
  for (int l = level + 1; l < levelCount(); ++l) {
    const HsLevel& fine = levels_[static_cast<std::size_t>(l)];
    HsRegion grown = r;
    for (std::size_t k = 0; k < fine.cvs.size(); ++k) {
      const HsCv& f = fine.cvs[k];
      if (!holds(fine.u, r.u, fine.u.reference(f.i)) || !holds(fine.v, r.v, fine.v.reference(f.j)))
        continue;
      visit(l, k);
      grown.u = merged(fine.u, grown.u, supportOf(fine.u, f.i));
      grown.v = merged(fine.v, grown.v, supportOf(fine.v, f.j));
    }
    r = grown;
  }
  return r;
}

void HSpline::refreshAround(int level, int i, int j) {
  const int s = slotOf(level, i, j);
  const HsCv& cv = levels_[static_cast<std::size_t>(level)].cvs[static_cast<std::size_t>(s)];
  Vec3& d = cache_[static_cast<std::size_t>(level)].displacement[static_cast<std::size_t>(s)];
  d = level == 0                  ? cv.value
      : cv.value == Vec3{0, 0, 0} ? Vec3{0, 0, 0}
                                  : displacementOf(frame(level, i, j), cv.value);
  // Finer CVs whose frame sits where the surface changed, level by level (each frame needs
  // the levels below it refreshed first).
  walkReach(level, i, j, [this](int l, std::size_t k) {
    const HsCv& f = levels_[static_cast<std::size_t>(l)].cvs[k];
    cache_[static_cast<std::size_t>(l)].displacement[k] =
        f.value == Vec3{0, 0, 0} ? Vec3{0, 0, 0} : displacementOf(frame(l, f.i, f.j), f.value);
  });
}

HsRegion HSpline::reach(int level, int i, int j) const {
  checkLevelIndex(level);
  if (!find(level, i, j)) throw ModelError("hspline: there is no " + hsCvName(level, i, j));
  const HsLevel& l = levels_[static_cast<std::size_t>(level)];
  return walkReach(level, l.u.wrap(i), l.v.wrap(j), [](int, std::size_t) {});
}

bool HSpline::contains(const HsRegion& r, double u, double v) const {
  return holds(levels_[0].u, r.u, u) && holds(levels_[0].v, r.v, v);
}

std::vector<Vec3> HSpline::gridPositions(int level, std::vector<std::pair<int, int>> points) const {
  // Which grid points each level needs, finest first; then their positions, coarsest first.
  std::vector<std::vector<std::pair<int, int>>> need(static_cast<std::size_t>(level) + 1);
  need[static_cast<std::size_t>(level)] = std::move(points);
  for (int l = level; l > 0; --l) {
    std::unordered_set<std::int64_t> seen;
    const Cache& c = cache_[static_cast<std::size_t>(l)];
    for (const auto& [i, j] : need[static_cast<std::size_t>(l)])
      for (const auto& [a, wa] : c.rowsU[static_cast<std::size_t>(i)])
        for (const auto& [b, wb] : c.rowsV[static_cast<std::size_t>(j)])
          if (seen.insert(key(a, b)).second)
            need[static_cast<std::size_t>(l - 1)].push_back({a, b});
  }
  std::unordered_map<std::int64_t, Vec3> below, here;
  for (int l = 0; l <= level; ++l) {
    const Cache& c = cache_[static_cast<std::size_t>(l)];
    here.clear();
    for (const auto& [i, j] : need[static_cast<std::size_t>(l)]) {
      Vec3 p{0, 0, 0};
      if (l > 0)
        for (const auto& [a, wa] : c.rowsU[static_cast<std::size_t>(i)])
          for (const auto& [b, wb] : c.rowsV[static_cast<std::size_t>(j)])
            vaxpy(p, wa * wb, below.at(key(a, b)));
      const int s = slotOf(l, i, j);
      if (s >= 0) p = vadd(p, c.displacement[static_cast<std::size_t>(s)]);
      here[key(i, j)] = p;
    }
    std::swap(below, here);
  }
  std::vector<Vec3> out;
  out.reserve(need[static_cast<std::size_t>(level)].size());
  for (const auto& [i, j] : need[static_cast<std::size_t>(level)])
    out.push_back(below.at(key(i, j)));
  return out;
}

const Vec3& HSpline::displacement(int level, int k) const {
  return cache_.at(static_cast<std::size_t>(level)).displacement.at(static_cast<std::size_t>(k));
}

std::vector<Vec3> HSpline::positions(int level) const {
  checkLevelIndex(level);
  std::vector<std::pair<int, int>> points;
  for (const HsCv& cv : levels_[static_cast<std::size_t>(level)].cvs)
    points.push_back({cv.i, cv.j});
  return gridPositions(level, std::move(points));
}

Vec3 HSpline::position(int level, int i, int j) const {
  checkLevelIndex(level);
  const HsLevel& l = levels_[static_cast<std::size_t>(level)];
  const int wi = l.u.wrap(i), wj = l.v.wrap(j);
  if (wi < 0 || wj < 0)
    throw ModelError("hspline: " + hsCvName(level, i, j) + " lies outside the level's grid");
  return gridPositions(level, {{wi, wj}})[0];
}

HSpline HSpline::fromLevels(SplineAxis u, SplineAxis v, std::vector<std::vector<HsCv>> levels) {
  if (levels.empty()) throw ModelError("hspline: no level 0");
  const int nu = u.count(), nv = v.count();
  if (levels[0].size() != static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv))
    throw ModelError("hspline level 0: " + std::to_string(levels[0].size()) +
                     " CVs given, its grid has " + std::to_string(nu) + " x " + std::to_string(nv));
  std::vector<Vec3> grid(static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv));
  std::vector<char> have(grid.size(), 0);
  for (const HsCv& cv : levels[0]) {
    if (cv.i < 0 || cv.i >= nu || cv.j < 0 || cv.j >= nv)
      throw ModelError("hspline: " + hsCvName(0, cv.i, cv.j) + " lies outside level 0's " +
                       std::to_string(nu) + " x " + std::to_string(nv) + " grid");
    const std::size_t at = static_cast<std::size_t>(cv.i) +
                           static_cast<std::size_t>(nu) * static_cast<std::size_t>(cv.j);
    if (have[at]) throw ModelError("hspline: " + hsCvName(0, cv.i, cv.j) + " is given twice");
    have[at] = 1;
    grid[at] = cv.value;
  }
  HSpline h(std::move(u), std::move(v), std::move(grid));
  std::size_t total = h.cvCount();
  for (std::size_t level = 1; level < levels.size(); ++level) {
    h.addLevel();
    HsLevel& l = h.levels_.back();
    total += levels[level].size();
    if (total > kMaxCvs)
      throw ModelError("hspline: more than " + std::to_string(kMaxCvs) + " CVs in all");
    for (const HsCv& cv : levels[level]) {
      if (l.u.wrap(cv.i) != cv.i || l.v.wrap(cv.j) != cv.j)
        throw ModelError("hspline: " + hsCvName(int(level), cv.i, cv.j) + " lies outside level " +
                         std::to_string(level) + "'s " + std::to_string(l.u.count()) + " x " +
                         std::to_string(l.v.count()) + " grid");
      if (!finite(cv.value))
        throw ModelError("hspline: " + hsCvName(int(level), cv.i, cv.j) +
                         " has an offset that is not finite");
    }
    l.cvs = std::move(levels[level]);
    h.rebuildIndex(int(level));
  }
  h.refreshFrom(1);
  return h;
}

}  // namespace frep
