// A lattice's map made fast to invert and to bound over boxes: the parameter cube cut into
// g^3 leaves, each with a box that holds its image (the restricted Bezier control points) and
// the images of its corners. What the ffd node (frep/ffd_field.h) and grid deformation
// (volume/) evaluate at millions of points.
//
// - inverse(y) tries only the leaves whose image box holds y, nearest first, each from the
//   trilinear inverse of the leaf's corner images (the first guess), then Newton on the true
//   map; a point that no leaf's box holds is outside the deformed lattice at once.
// - cover(box) says whether a box of space is outside the deformed lattice, inside it, or
//   neither, and which part of the parameter cube can map into it: what interval bounds of a
//   deformed field need.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "lattice/ffd_lattice.h"

namespace frep {

class FfdMap {
 public:
  // Leaves per axis: up to 8, fewer for lattices so large that computing the leaf bounds
  // would cost more than a fraction of a second.
  explicit FfdMap(FfdLattice lattice);

  const FfdLattice& lattice() const { return lattice_; }
  int leavesPerAxis() const { return g_; }
  std::size_t leafCount() const { return leaves_.size(); }

  // Leaf `id`'s part of the parameter cube.
  const Box3& leafParameters(int id) const { return leaves_[std::size_t(id)].stu; }
  // The leaves whose image box meets `box` (in increasing index order).
  std::vector<int> leavesMeeting(const Box3& box) const;

  // The local coordinates (clamped to [0, 1]^3) whose image is y, or nullopt outside the
  // deformed lattice. `leaves`, when given, must hold every leaf whose image box holds y
  // (leavesMeeting of a box around y): the answer is then bit-identical to the full search.
  std::optional<Vec3> inverse(const Vec3& y, const std::vector<int>* leaves = nullptr) const;

  // Where a box of space lies with respect to the deformed lattice D.
  enum class Cover { Outside, Inside, Partly };
  struct BoxCover {
    Cover cover = Cover::Outside;
    Box3 preimage;  // the parameter box holding every s with X(s) in the box (not Outside)
  };
  BoxCover cover(const Box3& box, const std::vector<int>* leaves = nullptr) const;

  // A box holding the image of the part of the rest box inside `restBox` (a box of rest
  // space), or an invalid box when it misses the rest box.
  Box3 imageOf(const Box3& restBox) const;
  // The box holding the whole deformed lattice.
  const Box3& image() const { return image_; }

 private:
  struct Leaf {
    Box3 stu;                     // its part of the parameter cube
    Box3 image;                   // holds X(stu)
    std::array<Vec3, 8> corners;  // X at the corners, bit 0: s, bit 1: t, bit 2: u
    Vec3 centre;                  // X at the centre
    std::vector<Box3> faces;      // boxes holding the images of its faces on the cube's boundary
  };
  // The leaves whose image box may hold a point of cell c of a uniform index grid over the
  // image (kIndexCells per axis), so a point looks at a few leaves, not all of them.
  static constexpr int kIndexCells = 16;
  int indexCell(double v, int axis) const;
  template <class Visit>
  void forLeavesNear(const Box3& box, const std::vector<int>* leaves, Visit visit) const;
  FfdLattice lattice_;
  int g_ = 1;
  std::vector<Leaf> leaves_;
  Box3 image_;
  std::vector<std::vector<int>> index_;
};

}  // namespace frep
