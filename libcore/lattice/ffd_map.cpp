// FfdMap: leaf bounds by Bezier restriction, inverse by leaf-local first guesses.
#include "lattice/ffd_map.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace frep {

namespace {

double distance2(const Vec3& a, const Vec3& b) {
  const double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
  return x * x + y * y + z * z;
}

// The trilinear map of a cell's eight corner images at (a, b, c) and its Jacobian.
Vec3 trilinear(const std::array<Vec3, 8>& q, const Vec3& w, Mat3* jac) {
  Vec3 x{0, 0, 0};
  Mat3 j{};
  for (int corner = 0; corner < 8; ++corner) {
    const int bits[3] = {corner & 1, (corner >> 1) & 1, (corner >> 2) & 1};
    double f[3], df[3];
    for (int k = 0; k < 3; ++k) {
      f[k] = bits[k] ? w[k] : 1.0 - w[k];
      df[k] = bits[k] ? 1.0 : -1.0;
    }
    const double weight = f[0] * f[1] * f[2];
    const double dw[3] = {df[0] * f[1] * f[2], f[0] * df[1] * f[2], f[0] * f[1] * df[2]};
    for (int r = 0; r < 3; ++r) {
      x[r] += weight * q[corner][r];
      for (int c = 0; c < 3; ++c) j[r][c] += dw[c] * q[corner][r];
    }
  }
  *jac = j;
  return x;
}

// The cell coordinates whose trilinear image is nearest y: a few Newton steps kept inside the
// cell. Only a first guess, so no convergence test.
Vec3 trilinearInverse(const std::array<Vec3, 8>& q, const Vec3& y) {
  Vec3 w{0.5, 0.5, 0.5};
  for (int it = 0; it < 3; ++it) {
    Mat3 j;
    const Vec3 x = trilinear(q, w, &j);
    const double det = determinant(j);
    if (!(std::abs(det) > 1e-300)) break;
    const Vec3 r{y[0] - x[0], y[1] - x[1], y[2] - x[2]};
    Vec3 step;
    for (int c = 0; c < 3; ++c) {
      Mat3 m = j;
      for (int row = 0; row < 3; ++row) m[row][c] = r[row];
      step[c] = determinant(m) / det;
    }
    for (int k = 0; k < 3; ++k) w[k] = std::clamp(w[k] + step[k], 0.0, 1.0);
  }
  return w;
}

Vec3 clampToCube(const Vec3& s) {
  return {std::clamp(s[0], 0.0, 1.0), std::clamp(s[1], 0.0, 1.0), std::clamp(s[2], 0.0, 1.0)};
}

}  // namespace

FfdMap::FfdMap(FfdLattice lattice) : lattice_(std::move(lattice)) {
  // A leaf's bounds cost about (points) x (sum of divisions) operations: keep all of them
  // within a few tens of millions.
  const double perLeaf = double(lattice_.pointCount()) *
                         (lattice_.divisions(0) + lattice_.divisions(1) + lattice_.divisions(2));
  g_ = 8;
  while (g_ > 1 && double(g_) * g_ * g_ * perLeaf > 4e7) --g_;
  const int g = g_;
  std::vector<Vec3> grid(std::size_t(g + 1) * (g + 1) * (g + 1));
  auto at = [g](int i, int j, int k) { return (std::size_t(i) * (g + 1) + j) * (g + 1) + k; };
  for (int i = 0; i <= g; ++i)
    for (int j = 0; j <= g; ++j)
      for (int k = 0; k <= g; ++k)
        grid[at(i, j, k)] = lattice_.forward({double(i) / g, double(j) / g, double(k) / g});
  leaves_.reserve(std::size_t(g) * g * g);
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j)
      for (int k = 0; k < g; ++k) {
        Leaf leaf;
        leaf.stu = {{double(i) / g, double(j) / g, double(k) / g},
                    {double(i + 1) / g, double(j + 1) / g, double(k + 1) / g}};
        leaf.image = lattice_.imageBounds(leaf.stu);
        for (int c = 0; c < 8; ++c)
          leaf.corners[c] = grid[at(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))];
        leaf.centre = lattice_.forward({(i + 0.5) / g, (j + 0.5) / g, (k + 0.5) / g});
        const int cell[3] = {i, j, k};
        for (int a = 0; a < 3; ++a)
          for (int side = 0; side < 2; ++side) {
            if (cell[a] != (side ? g - 1 : 0)) continue;
            Box3 face = leaf.stu;
            face.lo[a] = face.hi[a] = side ? 1.0 : 0.0;
            leaf.faces.push_back(lattice_.imageBounds(face));
          }
        image_ = leaves_.empty() ? leaf.image : boxHull(image_, leaf.image);
        leaves_.push_back(std::move(leaf));
      }
  index_.assign(std::size_t(kIndexCells) * kIndexCells * kIndexCells, {});
  for (std::size_t id = 0; id < leaves_.size(); ++id) {
    const Box3& b = leaves_[id].image;
    for (int x = indexCell(b.lo[0], 0); x <= indexCell(b.hi[0], 0); ++x)
      for (int y = indexCell(b.lo[1], 1); y <= indexCell(b.hi[1], 1); ++y)
        for (int z = indexCell(b.lo[2], 2); z <= indexCell(b.hi[2], 2); ++z)
          index_[(std::size_t(x) * kIndexCells + y) * kIndexCells + z].push_back(int(id));
  }
}

int FfdMap::indexCell(double v, int axis) const {
  const double t = (v - image_.lo[axis]) / (image_.hi[axis] - image_.lo[axis]);
  return std::clamp(int(std::floor(t * kIndexCells)), 0, kIndexCells - 1);
}

// Calls visit(id) once for each leaf, in increasing order, that the caller's list holds (all
// leaves when none) and whose image box may meet `box`: from the index where the box spans
// few of its cells, else by scanning the list.
template <class Visit>
void FfdMap::forLeavesNear(const Box3& box, const std::vector<int>* leaves, Visit visit) const {
  if (!boxesMeet(image_, box)) return;
  int lo[3], hi[3], cells = 1;
  for (int a = 0; a < 3; ++a) {
    lo[a] = indexCell(box.lo[a], a);
    hi[a] = indexCell(box.hi[a], a);
    cells *= hi[a] - lo[a] + 1;
  }
  const std::size_t listed = leaves ? leaves->size() : leaves_.size();
  auto listedHere = [&](int id) {
    return !leaves || std::binary_search(leaves->begin(), leaves->end(), id);
  };
  if (cells == 1) {  // a cell's list is in increasing order already
    for (int id : index_[(std::size_t(lo[0]) * kIndexCells + lo[1]) * kIndexCells + lo[2]])
      if (listedHere(id)) visit(id);
    return;
  }
  if (std::size_t(cells) * 4 < listed) {
    std::vector<int> found;
    for (int x = lo[0]; x <= hi[0]; ++x)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int z = lo[2]; z <= hi[2]; ++z) {
          const auto& list = index_[(std::size_t(x) * kIndexCells + y) * kIndexCells + z];
          found.insert(found.end(), list.begin(), list.end());
        }
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    for (int id : found)
      if (listedHere(id)) visit(id);
    return;
  }
  if (leaves)
    for (int id : *leaves) visit(id);
  else
    for (std::size_t i = 0; i < leaves_.size(); ++i) visit(int(i));
}

std::vector<int> FfdMap::leavesMeeting(const Box3& box) const {
  std::vector<int> out;
  forLeavesNear(box, nullptr, [&](int id) {
    if (boxesMeet(leaves_[std::size_t(id)].image, box)) out.push_back(id);
  });
  return out;
}

std::optional<Vec3> FfdMap::inverse(const Vec3& y, const std::vector<int>* leaves) const {
  if (!boxHolds(image_, y)) return std::nullopt;
  // The candidates, nearest centre first (ties by index: the same order whatever list the
  // caller passed, so the answer is too).
  int found[512];
  double dist[512];
  int n = 0;
  forLeavesNear(Box3{y, y}, leaves, [&](int id) {
    const Leaf& leaf = leaves_[std::size_t(id)];
    if (!boxHolds(leaf.image, y) || n == 512) return;
    found[n] = id;
    dist[n++] = distance2(leaf.centre, y);
  });
  if (n == 0) return std::nullopt;
  int order[512];
  std::iota(order, order + n, 0);
  std::sort(order, order + n, [&](int a, int b) {
    return dist[a] < dist[b] || (dist[a] == dist[b] && found[a] < found[b]);
  });
  for (int o = 0; o < n; ++o) {
    const Leaf& leaf = leaves_[std::size_t(found[order[o]])];
    const Vec3 w = trilinearInverse(leaf.corners, y);
    Vec3 guess;
    for (int k = 0; k < 3; ++k)
      guess[k] = leaf.stu.lo[k] + w[k] * (leaf.stu.hi[k] - leaf.stu.lo[k]);
    const auto s = lattice_.newton(y, guess);
    if (!s) continue;
    if (insideUnitCube(*s)) return clampToCube(*s);
    if (nearUnitCube(*s)) return std::nullopt;  // outside the deformed lattice
  }
  return std::nullopt;
}

FfdMap::BoxCover FfdMap::cover(const Box3& box, const std::vector<int>* leaves) const {
  BoxCover out;
  bool any = false, boundary = false;
  std::vector<int> meeting;
  auto consider = [&](int id) {
    const Leaf& leaf = leaves_[std::size_t(id)];
    if (!boxesMeet(leaf.image, box)) return;
    out.preimage = any ? boxHull(out.preimage, leaf.stu) : leaf.stu;
    any = true;
    meeting.push_back(id);
    for (const Box3& f : leaf.faces)
      if (boxesMeet(f, box)) boundary = true;
  };
  forLeavesNear(box, leaves, consider);
  if (!any) return out;
  if (boundary) {
    out.cover = Cover::Partly;
    return out;
  }
  // The box misses the lattice's boundary, so it lies wholly inside the deformed lattice or
  // wholly outside (for a lattice that does not fold): its centre tells which.
  const Vec3 c{0.5 * (box.lo[0] + box.hi[0]), 0.5 * (box.lo[1] + box.hi[1]),
               0.5 * (box.lo[2] + box.hi[2])};
  out.cover = inverse(c, &meeting) ? Cover::Inside : Cover::Outside;
  return out;
}

Box3 FfdMap::imageOf(const Box3& restBox) const {
  Box3 stu;
  const Vec3 lo = lattice_.local(restBox.lo), hi = lattice_.local(restBox.hi);
  for (int k = 0; k < 3; ++k) {
    stu.lo[k] = std::max(lo[k], 0.0);
    stu.hi[k] = std::min(hi[k], 1.0);
    if (!(stu.lo[k] <= stu.hi[k])) return Box3{{1, 1, 1}, {0, 0, 0}};
  }
  Box3 out{{1, 1, 1}, {0, 0, 0}};
  bool any = false;
  for (const Leaf& leaf : leaves_)
    if (boxesMeet(leaf.stu, stu)) {
      out = any ? boxHull(out, leaf.image) : leaf.image;
      any = true;
    }
  return out;
}

}  // namespace frep
