// The Voronoi foam's network from CGAL's 3D Delaunay triangulation (voronoi_foam.h).
#include "volume/voronoi_foam.h"

#include <CGAL/Delaunay_triangulation_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/hilbert_sort.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "base/errors.h"
#include "frep/strut_field.h"

namespace frep {

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Delaunay = CGAL::Delaunay_triangulation_3<Kernel>;

// splitmix64: a fixed sequence for a seed on every platform.
class SeedSequence {
 public:
  explicit SeedSequence(std::uint64_t seed) : state_(seed) {}
  double uniform() {  // in [0, 1)
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return double(z >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

Vec3 toVec(const Kernel::Point_3& p) {
  return {p.x(), p.y(), p.z()};
}

// Whether p lies in the tile [origin, origin + period), with a sliver below the lower faces
// so that rounding never loses an edge (one listed twice changes no distance).
bool inTile(const Vec3& p, const Vec3& origin, const Vec3& period) {
  for (int a = 0; a < 3; ++a) {
    const double u = p[a] - origin[a];
    if (u < -1e-9 * period[a] || u >= period[a]) return false;
  }
  return true;
}

}  // namespace

VoronoiFoamNetwork voronoiFoamNetwork(const VoronoiFoamSettings& s) {
  VoronoiFoamNetwork net;
  net.cells = foamCellsPerPeriod(s.cell, s.tile);
  for (int a = 0; a < 3; ++a) net.period[a] = s.cell[a] * net.cells[a];
  SeedSequence random(s.seed);
  for (int k = 0; k < net.cells[2]; ++k)
    for (int j = 0; j < net.cells[1]; ++j)
      for (int i = 0; i < net.cells[0]; ++i) {
        const int index[3] = {i, j, k};
        Vec3 p;
        for (int a = 0; a < 3; ++a)
          p[a] = s.origin[a] + s.cell[a] * (index[a] + 0.5 + s.jitter * (random.uniform() - 0.5));
        net.seeds.push_back(p);
      }
  // The tile's seeds and their copies in the 26 tiles round it: the diagram is then right
  // for every cell of the middle tile (a Voronoi cell depends only on seeds within about two
  // cells of it).
  std::vector<Kernel::Point_3> points;
  for (int i = -1; i <= 1; ++i)
    for (int j = -1; j <= 1; ++j)
      for (int k = -1; k <= 1; ++k)
        for (const Vec3& p : net.seeds)
          points.emplace_back(p[0] + i * net.period[0], p[1] + j * net.period[1],
                              p[2] + k * net.period[2]);
  // Inserted one by one in an order of their own (a Hilbert curve's, by medians) rather than
  // shuffled with CGAL's default random numbers, which are seeded from the clock.
  CGAL::hilbert_sort(points.begin(), points.end());
  Delaunay dt;
  Delaunay::Vertex_handle last;
  for (const Kernel::Point_3& p : points)
    last = dt.insert(p, last == Delaunay::Vertex_handle() ? Delaunay::Cell_handle() : last->cell());
  // The foam must not depend on how the triangulation stores its cells (their order and each
  // cell's order of vertices change from run to run): each Voronoi vertex is the circumcentre
  // of its four seeds taken in sorted order, and the edges and vertices are listed sorted.
  auto centre = [](const Delaunay::Cell_handle& c) {
    std::array<Kernel::Point_3, 4> p{c->vertex(0)->point(), c->vertex(1)->point(),
                                     c->vertex(2)->point(), c->vertex(3)->point()};
    std::sort(p.begin(), p.end());
    return toVec(CGAL::circumcenter(p[0], p[1], p[2], p[3]));
  };
  for (auto f = dt.finite_facets_begin(); f != dt.finite_facets_end(); ++f) {
    const Delaunay::Cell_handle c = f->first, n = c->neighbor(f->second);
    if (dt.is_infinite(c) || dt.is_infinite(n)) continue;
    Vec3 a = centre(c), b = centre(n);
    const Vec3 middle{0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])};
    if (!inTile(middle, s.origin, net.period)) continue;
    if (b < a) std::swap(a, b);
    net.edges.push_back({a, b});
  }
  for (auto c = dt.finite_cells_begin(); c != dt.finite_cells_end(); ++c) {
    const Vec3 v = centre(c);
    if (inTile(v, s.origin, net.period)) net.nodes.push_back(v);
  }
  std::sort(net.edges.begin(), net.edges.end(), [](const StrutPiece& u, const StrutPiece& w) {
    return u.a != w.a ? u.a < w.a : u.b < w.b;
  });
  std::sort(net.nodes.begin(), net.nodes.end());
  return net;
}

VoronoiFoamSettings voronoiFoamSettings(const Node& node) {
  VoronoiFoamSettings s;
  s.cell = node.vec3("cell");
  s.origin = node.vec3("origin");
  s.seed = std::uint64_t(node.real("seed"));
  s.jitter = node.real("jitter");
  s.tile = int(node.real("tile"));
  s.blend = node.real("blend");
  return s;
}

std::shared_ptr<const Field> makeVoronoiFoam(const VoronoiFoamSettings& s) {
  const VoronoiFoamNetwork net = voronoiFoamNetwork(s);
  // Bins of half a cell: a point then meets the struts within about a cell of it.
  const std::array<int, 3> bins{2 * net.cells[0], 2 * net.cells[1], 2 * net.cells[2]};
  try {
    return std::make_shared<PeriodicNetworkField>(net.edges, net.nodes, net.period, s.origin, bins,
                                                  s.blend);
  } catch (const std::invalid_argument&) {
    throw ModelError("voronoi_foam: parameter 'tile' = " + std::to_string(s.tile) +
                     " cells is too short a period for this foam's struts; use more");
  }
}

}  // namespace frep
