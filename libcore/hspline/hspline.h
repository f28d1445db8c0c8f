// A hierarchical B-spline surface (Forsey and Bartels' hsplines, seed 003): a bicubic B-spline
// at level 0 and, at each finer level, control vertices (CVs) on a grid of twice the knot
// density whose offsets add detail where they are.
//
// The surface of level l is S_l(u,v) = S_{l-1}(u,v) + sum over the level's CVs of D_k B_k(u,v),
// where B_k is the CV's basis function on level l's knots and D_k its offset O_k turned from
// the frame of S_{l-1} at the CV's reference parameter into space (O = (along the u tangent,
// along the v tangent, along the normal)). A CV's position is W = P + D, P being the point the
// parent level's control net gives it by knot insertion: so a new CV (O = 0) leaves the surface
// as it was, zeroing an offset removes exactly that CV's detail, and detail turns and moves
// with the parent surface it was modelled on. docs/hsplines.md gives the reasons.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "base/vec.h"
#include "hspline/spline_axis.h"

namespace frep {

// One control vertex: its grid index on its level and its value, the position at level 0 and
// the offset (u tangent, v tangent, normal) at finer levels.
struct HsCv {
  int i = 0, j = 0;
  Vec3 value{0, 0, 0};
};

struct HsCvRef {
  int level = 0, i = 0, j = 0;
  bool operator==(const HsCvRef& o) const { return level == o.level && i == o.i && j == o.j; }
  bool operator<(const HsCvRef& o) const {
    return level != o.level ? level < o.level : j != o.j ? j < o.j : i < o.i;
  }
};

struct HsLevel {
  SplineAxis u, v;        // the level's knots (level 0's refined `level` times)
  std::vector<HsCv> cvs;  // the CVs it has, sorted by (j, i)
};

// A point of the surface with its first and second partial derivatives.
struct HsSurfacePoint {
  Vec3 position{}, du{}, dv{}, duu{}, duv{}, dvv{};
  Vec3 normal() const;  // unit du x dv, or zero where the surface is degenerate
  // Adds control point d's term for basis functions a of bu and b of bv.
  void add(const SpanBasis& bu, const SpanBasis& bv, int a, int b, const Vec3& d) {
    vaxpy(position, bu.value[a] * bv.value[b], d);
    vaxpy(du, bu.first[a] * bv.value[b], d);
    vaxpy(dv, bu.value[a] * bv.first[b], d);
    vaxpy(duu, bu.second[a] * bv.value[b], d);
    vaxpy(duv, bu.first[a] * bv.first[b], d);
    vaxpy(dvv, bu.value[a] * bv.second[b], d);
  }
};

// An orthonormal frame: the unit u tangent, the v tangent made orthogonal, the unit normal.
struct HsFrame {
  Vec3 tu{1, 0, 0}, tv{0, 1, 0}, n{0, 0, 1};
};

// An interval of one parameter axis in extended coordinates (a periodic one may run past the
// period's ends), or the whole axis; a region is one on each axis.
struct HsInterval {
  double lo = 0, hi = 0;
  bool all = false;
};
struct HsRegion {
  HsInterval u, v;
};

// "CV (level 1, i 4, j 7)": how messages name a CV.
std::string hsCvName(int level, int i, int j);

class HSpline {
 public:
  static constexpr int kMaxLevels = 12;
  static constexpr std::size_t kMaxCvs = 4u << 20;         // CVs in all, after any refine
  static constexpr std::size_t kMaxLevelGrid = 64u << 20;  // CV grid size of the finest level

  HSpline() = default;
  // Level 0 from its axes and nu x nv positions (index i + nu * j).
  HSpline(SplineAxis u, SplineAxis v, std::vector<Vec3> positions);

  int levelCount() const { return static_cast<int>(levels_.size()); }
  const HsLevel& level(int l) const { return levels_.at(static_cast<std::size_t>(l)); }
  std::size_t cvCount() const;
  // The CV at (level, i, j) (indices wrapped on periodic axes), or null where there is none.
  const HsCv* find(int level, int i, int j) const;
  // Whether the CV may move: level 0's always; a finer one when every CV of the 7 x 7 block
  // centred on it (the grid's own edges cut the block) is there, so its basis function's
  // support lies inside the refined region and no crack can open at the region's border.
  bool movable(int level, int i, int j) const;

  // The surface of the levels up to `upTo` (all when negative) at (u, v).
  HsSurfacePoint evaluate(double u, double v, int upTo = -1) const;
  // The surface at the grid points (us[a], vs[b]), vertex a + len(us) * b, of each run (first
  // vertex, count): each level's basis computed once per column and row, not per point.
  std::vector<HsSurfacePoint> evaluateGrid(
      const std::vector<double>& us, const std::vector<double>& vs,
      const std::vector<std::pair<std::size_t, std::size_t>>& runs) const;
  // The frame a CV's offset is measured in: S_{l-1}'s at the CV's reference parameter.
  HsFrame frame(int level, int i, int j) const;
  // A CV's position in space (P + D); works for grid points that hold no CV too.
  Vec3 position(int level, int i, int j) const;
  // D of the level's k-th CV (level(l).cvs order): its offset turned into space; level 0's
  // position.
  const Vec3& displacement(int level, int k) const;
  // Where the surface can change when the CV's value changes: its basis function's support,
  // grown by the supports of the finer CVs whose frame lies in it, level by level. A drag's
  // preview re-evaluates only there.
  HsRegion reach(int level, int i, int j) const;
  bool contains(const HsRegion& r, double u, double v) const;
  // The positions of all of a level's CVs, in the order of level(l).cvs.
  std::vector<Vec3> positions(int level) const;
  // The reference parameter of a CV: where its frame is taken.
  std::pair<double, double> referenceParameter(int level, int i, int j) const;

  // Edits (hspline/hspline_edit.cpp). Each throws ModelError with the CV and the rule on a
  // request it refuses, leaving the surface as it was.
  // Refines level `level` around the given CVs of it: level + 1 gets the 7 x 7 block of CVs
  // centred on each one's child, with zero offsets, so the surface does not change.
  void refine(int level, const std::vector<std::pair<int, int>>& cvs);
  // Moves a CV to a position in space (its offset follows).
  void moveCv(int level, int i, int j, const Vec3& target);
  // Sets a CV's value as stored: level 0 a position, finer levels an offset.
  void setValue(int level, int i, int j, const Vec3& value);
  // Zeroes the offsets of the given CVs (level 0's have positions, not offsets: refused).
  void zeroOffsets(const std::vector<HsCvRef>& cvs);
  // Removes every CV of level >= 1 whose offset is zero and that no non-zero CV needs (its
  // 7 x 7 block) nor any finer CV (the coarse CVs whose refinement made it), then empty finest
  // levels. The surface does not change. Returns how many CVs went.
  std::size_t unrefine();

  // Builds a hierarchy from stored levels (the .hs reader), checking every index; throws
  // ModelError naming what is wrong.
  static HSpline fromLevels(SplineAxis u, SplineAxis v, std::vector<std::vector<HsCv>> levels);

 private:
  struct Cache {
    int i0 = 0, j0 = 0, ni = 0, nj = 0;       // box of the level's CVs
    std::vector<std::int32_t> slot;           // index into cvs, -1 where no CV
    std::vector<Vec3> displacement;           // D per CV (level 0: the position)
    std::vector<RefinementRow> rowsU, rowsV;  // from the parent level's grid (level >= 1)
    std::vector<int> childU, childV;          // child centres on the next level
  };
  int slotOf(int level, int i, int j) const;
  // Adds one level's terms at a point whose bases on that level are given.
  void addLevel(HsSurfacePoint& p, int level, const SpanBasis& bu, const SpanBasis& bv) const;
  // Positions (P + D) of grid points of a level, through the parents' nets.
  std::vector<Vec3> gridPositions(int level, std::vector<std::pair<int, int>> points) const;
  void addLevel();
  void rebuildIndex(int level);
  // Recomputes D for levels from..end, in order (each needs its parent's).
  void refreshFrom(int from);
  // After one CV's value changed: its own D, then on each finer level only the CVs whose
  // frame the change can reach (reference parameter inside the supports changed so far).
  void refreshAround(int level, int i, int j);
  // Walks the CVs a change of (level, i, j) can reach (visit(level, index)), finest last;
  // returns the region of the surface that can change.
  template <class Visit>
  HsRegion walkReach(int level, int i, int j, Visit visit) const;
  void checkLevelIndex(int level) const;
  std::vector<HsLevel> levels_;
  std::vector<Cache> cache_;
};

}  // namespace frep
