#include "pipeline/hspline_shell.h"

#include <algorithm>
#include <cmath>

#include "base/errors.h"
#include "frep/ffd_field.h"
#include "frep/registry.h"
#include "frep/tree.h"
#include "lattice/surface_lattice.h"

namespace frep {

namespace {

// The surface's length along one parameter at the middle of the other (a polyline of 64).
double lengthAlong(const SurfaceSampler& surface, bool alongS) {
  double length = 0.0;
  Vec3 last = surface(alongS ? 0.0 : 0.5, alongS ? 0.5 : 0.0).point;
  for (int k = 1; k <= 64; ++k) {
    const double x = k / 64.0;
    const Vec3 p = surface(alongS ? x : 0.5, alongS ? 0.5 : x).point;
    length += vlength(vsub(p, last));
    last = p;
  }
  return length;
}

}  // namespace

HsplineShell hsplineShellLattice(const HSpline& h, const HsplineShellSettings& settings,
                                 const std::string& source) {
  const double thickness = settings.thickness;
  if (!(thickness > 0.0) || !std::isfinite(thickness))
    throw ModelError("hspline lattice: thickness " + numberText(thickness) +
                     "; the shell's thickness must be a positive length");
  const HsLevel& base = h.level(0);
  const SurfaceSampler surface = [&h, &base](double s, double t) {
    const HsSurfacePoint p = h.evaluate(base.u.lo() + s * (base.u.hi() - base.u.lo()),
                                        base.v.lo() + t * (base.v.hi() - base.v.lo()));
    return SurfaceSample{p.position, p.normal()};
  };
  HsplineShell out;
  out.divisions[0] = settings.divisionsU ? settings.divisionsU
                                         : std::min(base.u.count() - 1, kMaxSurfaceDivisions);
  out.divisions[1] = settings.divisionsV ? settings.divisionsV
                                         : std::min(base.v.count() - 1, kMaxSurfaceDivisions);
  out.size = {lengthAlong(surface, true), lengthAlong(surface, false), thickness};
  const SurfaceLattice fit = latticeAlongSurface(surface, out.size, std::max(out.divisions[0], 1),
                                                 std::max(out.divisions[1], 1));
  out.deviation = fit.deviation;
  const double cell = settings.cell > 0.0 ? settings.cell : 0.5 * thickness;
  // Round a closed surface (a periodic parameter) whole cells make a turn, so the cells meet
  // across the seam as everywhere else.
  out.cells = {cell, cell, cell};
  const bool closed[2] = {base.u.isPeriodic(), base.v.isPeriodic()};
  for (int a = 0; a < 2; ++a)
    if (closed[a]) out.cells[a] = out.size[a] / std::max(1.0, std::round(out.size[a] / cell));
  const NodePtr struts =
      makeNode("strut_lattice",
               {{"cell_type", textValue(settings.cellType)},
                {"cell", vec3Value(out.cells)},
                {"radius", realValue(settings.radius > 0.0 ? settings.radius : 0.1 * cell)}},
               {});
  const NodePtr shell = makeNode("box", {{"size", vec3Value(out.size)}}, {});
  auto bend = ffdParams(fit.lattice);
  bend["struts"] = textValue(settings.straight ? "straight" : "curved");
  out.model.root = makeNode("ffd", bend, {makeNode("intersection", {}, {struts, shell})});
  out.model.description = "a strut lattice of " + settings.cellType + " cells along " + source +
                          ", a shell " + numberText(thickness) + " thick (hspline lattice)";
  return out;
}

}  // namespace frep
