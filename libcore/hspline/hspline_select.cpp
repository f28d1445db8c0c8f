#include "hspline/hspline_select.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace frep {

namespace {

std::vector<HsCvRef> sorted(std::vector<HsCvRef> v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

bool within(const SplineAxis& a, double t, double lo, double hi) {
  if (!a.isPeriodic() || lo <= hi) return t >= lo && t <= hi;
  return t >= lo || t <= hi;  // across the seam
}

double wrapped(const SplineAxis& a, double t) {
  if (!a.isPeriodic()) return t;
  const double k = std::floor((t - a.lo()) / a.period());
  return t - k * a.period();
}

template <class Keep>
std::vector<HsCvRef> levelWhere(const HSpline& h, int level, Keep keep) {
  std::vector<HsCvRef> out;
  if (level < 0 || level >= h.levelCount()) return out;
  for (const HsCv& cv : h.level(level).cvs)
    if (keep(cv)) out.push_back({level, cv.i, cv.j});
  return sorted(std::move(out));
}

}  // namespace

std::vector<HsCvRef> selectLevel(const HSpline& h, int level) {
  return levelWhere(h, level, [](const HsCv&) { return true; });
}

std::vector<HsCvRef> selectRegion(const HSpline& h, int level, double u0, double u1, double v0,
                                  double v1) {
  if (level < 0 || level >= h.levelCount()) return {};
  const HsLevel& l = h.level(level);
  return levelWhere(h, level, [&](const HsCv& cv) {
    return within(l.u, wrapped(l.u, l.u.reference(cv.i)), u0, u1) &&
           within(l.v, wrapped(l.v, l.v.reference(cv.j)), v0, v1);
  });
}

std::vector<HsCvRef> selectMovable(const HSpline& h, int level) {
  return levelWhere(h, level, [&](const HsCv& cv) { return h.movable(level, cv.i, cv.j); });
}

std::vector<HsCvRef> keepMovable(const HSpline& h, const std::vector<HsCvRef>& among) {
  std::vector<HsCvRef> out;
  for (const HsCvRef& c : among)
    if (h.movable(c.level, c.i, c.j)) out.push_back(c);
  return sorted(std::move(out));
}

// The CVs on the level of each selected CV that share its j (a u line) or its i (a v line).
static std::vector<HsCvRef> selectAlong(const HSpline& h, const std::vector<HsCvRef>& from,
                                        bool uLine) {
  std::vector<HsCvRef> out;
  for (const HsCvRef& c : from)
    for (const HsCvRef& r :
         levelWhere(h, c.level, [&](const HsCv& cv) { return uLine ? cv.j == c.j : cv.i == c.i; }))
      out.push_back(r);
  return sorted(std::move(out));
}

std::vector<HsCvRef> selectAlongU(const HSpline& h, const std::vector<HsCvRef>& from) {
  return selectAlong(h, from, true);
}

std::vector<HsCvRef> selectAlongV(const HSpline& h, const std::vector<HsCvRef>& from) {
  return selectAlong(h, from, false);
}

std::vector<HsCvRef> selectNeighbours(const HSpline& h, const std::vector<HsCvRef>& from) {
  std::vector<HsCvRef> out;
  for (const HsCvRef& c : from)
    for (int b = -1; b <= 1; ++b)
      for (int a = -1; a <= 1; ++a)
        if (const HsCv* cv = h.find(c.level, c.i + a, c.j + b))
          out.push_back({c.level, cv->i, cv->j});
  return sorted(std::move(out));
}

std::vector<HsCvRef> selectNonZeroOffsets(const HSpline& h, int level) {
  std::vector<HsCvRef> out;
  for (int l = std::max(level, 1); l < h.levelCount() && (level < 0 || l == level); ++l)
    for (const HsCvRef& r : levelWhere(h, l, [](const HsCv& cv) {
           return cv.value != Vec3{0, 0, 0};
         }))
      out.push_back(r);
  return sorted(std::move(out));
}

void refineSelection(HSpline& h, const std::vector<HsCvRef>& cvs) {
  std::map<int, std::vector<std::pair<int, int>>, std::greater<int>> byLevel;
  for (const HsCvRef& c : cvs) byLevel[c.level].push_back({c.i, c.j});
  for (const auto& [level, list] : byLevel) h.refine(level, list);
}

}  // namespace frep
