// An FFD lattice whose cells follow a surface: its rest box's x and y run along the surface's
// two parameters and its z across it, so a strut lattice bent by it (the ffd node) has its
// cells carried by the surface's parameters, as a shell of the given thickness. The lattice's
// map is a Bernstein volume (ffd_lattice.h), linear across; its control points are the least
// squares fit of the surface and its normals at samples of the parameters, so a lattice of a
// few divisions follows a smooth surface within a small fraction of the thickness (the fit
// reports how close).
#pragma once

#include <functional>

#include "base/vec.h"
#include "lattice/ffd_lattice.h"

namespace frep {

// The surface at parameters (s, t) in [0, 1]^2: its point and unit normal.
struct SurfaceSample {
  Vec3 point, normal;
};
using SurfaceSampler = std::function<SurfaceSample(double s, double t)>;

struct SurfaceLattice {
  FfdLattice lattice;
  // The largest distance, at check samples between the fit's, of the lattice's middle layer
  // from the surface, and of its two faces from the surface offset by half the thickness
  // along the normal.
  double deviation = 0.0;
};

// The lattice over the rest box [0, size x] x [0, size y] x [0, size z] (size z the shell's
// thickness) with l x m divisions along the surface (1 <= l, m <= kMaxSurfaceDivisions) and
// one across: local (s, t, u) goes to about surface(s, t) + (u - 1/2) size z normal(s, t).
// Throws ModelError naming what is wrong for a bad size or division count, or a surface
// sample that is not finite.
constexpr int kMaxSurfaceDivisions = 24;
SurfaceLattice latticeAlongSurface(const SurfaceSampler& surface, const Vec3& size, int l, int m);

}  // namespace frep
