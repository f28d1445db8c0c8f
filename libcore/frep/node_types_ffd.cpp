// The ffd node: a Sederberg-Parry lattice deforming its input, evaluated by pulling back
// through the lattice's inverse map (frep/ffd_field.h), so the deformed solid has no gaps at
// any resolution.
#include <algorithm>
#include <cmath>
#include <mutex>
#include <optional>

#include "base/errors.h"
#include "frep/ffd_field.h"
#include "frep/node_helpers.h"
#include "frep/periodic_segments.h"
#include "frep/program.h"
#include "frep/registry.h"
#include "frep/straight_struts.h"
#include "frep/tree.h"
#include "lattice/ffd_map.h"

namespace frep {

namespace {

int divisionsOf(const Node& n, int axis) {
  static const char* names[3] = {"divisions_x", "divisions_y", "divisions_z"};
  return static_cast<int>(n.real(names[axis]));
}

std::size_t controlPointCount(const Node& n) {
  return std::size_t(divisionsOf(n, 0) + 1) * (divisionsOf(n, 1) + 1) * (divisionsOf(n, 2) + 1);
}

bool isUndeformed(const Node& n) {
  return n.param("points").numbers.empty() || ffdLatticeOf(n).isUndeformed();
}

// The map of the last lattice asked for: the bounds rule and the compiler both need it, and
// its leaf bounds cost more than the rest of a compile.
std::shared_ptr<const FfdMap> mapOf(const Node& n) {
  static std::mutex mutex;
  static std::vector<double> lastKey;
  static std::shared_ptr<const FfdMap> last;
  std::vector<double> key;
  for (const char* name :
       {"rest_min", "rest_max", "divisions_x", "divisions_y", "divisions_z", "points"}) {
    const auto& v = n.param(name).numbers;
    key.push_back(double(v.size()));
    key.insert(key.end(), v.begin(), v.end());
  }
  std::lock_guard<std::mutex> lock(mutex);
  if (!last || key != lastKey) {
    last = std::make_shared<const FfdMap>(ffdLatticeOf(n));
    lastKey = std::move(key);
  }
  return last;
}

bool straightStruts(const Node& n) {
  return n.param("struts").text == "straight";
}

// Where straight struts find their network: the input itself, or the first input of an
// intersection that is one (the network cut to a part); -1 for the input, the intersection's
// input index otherwise, or nullopt.
std::optional<int> networkInput(const Node& n) {
  const Node& input = *n.inputs.at(0);
  if (isStrutNetwork(input)) return -1;
  if (input.type->id == "intersection")
    for (std::size_t k = 0; k < input.inputs.size(); ++k)
      if (isStrutNetwork(*input.inputs[k])) return int(k);
  return std::nullopt;
}

bool holdsNetwork(const Node& n) {
  if (isStrutNetwork(n)) return true;
  return std::any_of(n.inputs.begin(), n.inputs.end(),
                     [](const NodePtr& i) { return holdsNetwork(*i); });
}

std::string checkStraightStruts(const Node& n) {
  const std::optional<int> at = networkInput(n);
  if (!at) {
    if (!holdsNetwork(*n.inputs.at(0))) return "";  // nothing to straighten: a plain ffd
    return "parameter 'struts' = 'straight' needs the strut_lattice or voronoi_foam as the "
           "ffd's input, or as an input of an intersection that is (the lattice cut to a "
           "part); here it is deeper in the input (" +
           n.inputs[0]->type->id + ")";
  }
  const Node& network = *at < 0 ? *n.inputs[0] : *n.inputs[0]->inputs[std::size_t(*at)];
  if (network.type->id == "strut_lattice" && network.param("conform").text != "none")
    return "parameter 'struts' = 'straight' needs the strut_lattice's cells as boxes (its "
           "'conform' is '" +
           network.param("conform").text + "'; the ffd then bends them with it: 'curved')";
  const FfdLattice lattice = ffdLatticeOf(n);
  const double count = strutCountEstimate(network, lattice.rest());
  if (count > kMostStraightStruts)
    return "parameter 'struts' = 'straight' keeps every strut of the rest box in memory: this " +
           network.type->id + "'s cells put about " + numberText(std::round(count)) +
           " struts there, at most " + numberText(kMostStraightStruts) +
           " (larger cells or a smaller rest box)";
  return "";
}

// The straight struts' field: radius (a graded radius read where the point was before the
// bend) - the distance to the struts, and the node spheres.
Slot straightNetwork(CompileContext& c, const Node& network) {
  ProgramBuilder& b = c.b;
  const StraightStrutFields fields = straightStrutFields(network, mapOf(c.node())->lattice());
  Slot radius;
  if (!network.inputs.empty()) {
    auto grading = std::make_shared<const Program>(compile(network.inputs[0]));
    radius = b.external(std::make_shared<const FfdField>(std::move(grading), mapOf(c.node())),
                        c.p.x, c.p.y, c.p.z);
  } else {
    radius = b.constant(network.real("radius"));
  }
  Slot field = b.sub(radius, b.external(fields.struts, c.p.x, c.p.y, c.p.z));
  if (fields.nodes)
    field = b.max(field, b.sub(b.constant(network.real("node_radius")),
                               b.external(fields.nodes, c.p.x, c.p.y, c.p.z)));
  return field;
}

// The ffd over its input with straight struts: the network straightened, and the rest of an
// intersection (the part it is cut to) pulled back as the ffd always does.
std::optional<Slot> compileStraight(CompileContext& c) {
  const std::optional<int> at = networkInput(c.node());
  if (!at) return std::nullopt;
  const NodePtr& input = c.node().inputs[0];
  if (*at < 0) return straightNetwork(c, *input);
  std::vector<NodePtr> others;
  for (std::size_t k = 0; k < input->inputs.size(); ++k)
    if (int(k) != *at) others.push_back(input->inputs[k]);
  const NodePtr part =
      others.size() == 1 ? others[0] : makeNode("intersection", input->params, others);
  auto program = std::make_shared<const Program>(compile(part));
  const Slot bent = c.b.external(
      std::make_shared<const FfdField>(std::move(program), mapOf(c.node())), c.p.x, c.p.y, c.p.z);
  const Slot struts = straightNetwork(c, *input->inputs[std::size_t(*at)]);
  return c.b.emit(Op::RIntersect, struts, bent, 0, {input->real("alpha")});
}

std::string checkFfd(const Node& n) {
  const Vec3 lo = n.vec3("rest_min"), hi = n.vec3("rest_max");
  for (int a = 0; a < 3; ++a)
    if (!(lo[a] < hi[a]))
      return "parameter 'rest_max' must exceed 'rest_min' on every axis (the rest box is "
             "empty along " +
             std::string(1, "xyz"[a]) + ")";
  const std::size_t given = pointsOf(n.param("points")).size(), needed = controlPointCount(n);
  if (given != 0 && given != needed)
    return "parameter 'points' has " + std::to_string(given) + " points; a " +
           std::to_string(divisionsOf(n, 0)) + " x " + std::to_string(divisionsOf(n, 1)) + " x " +
           std::to_string(divisionsOf(n, 2)) + " lattice has " + std::to_string(needed) +
           " control points (i slowest, k fastest), or give none for the undeformed lattice";
  if (given != 0 && !isUndeformed(n))
    if (auto fold = mapOf(n)->lattice().findFold()) return fold->text();
  if (straightStruts(n) && !n.inputs.empty()) return checkStraightStruts(n);
  return "";
}

}  // namespace

FfdLattice ffdLatticeOf(const Node& n) {
  FfdLattice lattice({n.vec3("rest_min"), n.vec3("rest_max")}, divisionsOf(n, 0), divisionsOf(n, 1),
                     divisionsOf(n, 2));
  const std::vector<Vec3> points = pointsOf(n.param("points"));
  if (!points.empty()) lattice.setPoints(points);
  return lattice;
}

std::map<std::string, ParamValue> ffdParams(const FfdLattice& lattice) {
  std::map<std::string, ParamValue> p;
  p["rest_min"] = vec3Value(lattice.rest().lo);
  p["rest_max"] = vec3Value(lattice.rest().hi);
  for (int a = 0; a < 3; ++a)
    p[std::string("divisions_") + "xyz"[a]] = realValue(double(lattice.divisions(a)));
  ParamValue points;
  for (const Vec3& q : lattice.points())
    points.numbers.insert(points.numbers.end(), q.begin(), q.end());
  p["points"] = points;
  return p;
}

void registerLattices(Registry& r) {
  std::vector<ParamTemplate> params;
  params.push_back(vec3Param("rest_min", {-1, -1, -1}, "length",
                             "The rest box's lowest corner: the undeformed lattice spans the "
                             "box from rest_min to rest_max."));
  params.push_back(vec3Param("rest_max", {1, 1, 1}, "length", "The rest box's highest corner."));
  for (const char* axis : {"x", "y", "z"}) {
    ParamTemplate d =
        intParam(std::string("divisions_") + axis, 2,
                 std::string("Lattice cells along ") + axis + " (control points: one more).");
    range(d, 1, kMaxLatticeDivisions);
    params.push_back(d);
  }
  params.push_back(pointsParam(
      "points", {}, 0, "length",
      "The deformed control points, (divisions_x + 1)(divisions_y + 1)(divisions_z + 1) of "
      "them, index i (along x) slowest and k (along z) fastest; none for the undeformed "
      "lattice."));
  params.push_back(choiceParam(
      "struts", {"curved", "straight"},
      "For a strut_lattice or voronoi_foam input (alone or cut to a part by an intersection): "
      "'curved' bends the struts with their cells; 'straight' keeps each strut of the rest "
      "box straight from the image of one end to the image of the other, the cells following "
      "the lattice (straight beams print stiffer and go into a 3MF beam lattice one beam a "
      "strut). Other inputs are bent either way."));
  r.add({"ffd", "deformation",
         "Free-form deformation by a Sederberg-Parry lattice (as Houdini's, Blender's or "
         "Maya's lattice): the rest box is divided into cells, and moving the control points "
         "bends the space inside it, and the input with it. Every point is pulled back "
         "through the lattice's inverse map (Newton's method), so the deformed solid is "
         "exact at any resolution and has no gaps, however far the lattice stretches. "
         "Outside the deformed lattice the input is untouched, except inside the rest box, "
         "where the lattice carried the solid away: keep the solid inside the rest box. A "
         "lattice that folds over itself is refused, naming the cell.",
         "F(p) = f(R(s)) where X(s) = p, X(s) = sum B_i(s) B_j(t) B_k(u) P_ijk (Bernstein), "
         "R(s) = rest_min + s (rest_max - rest_min); outside the deformed lattice f(p), or "
         "min(f(p), -eps) inside the rest box; with struts = straight, a strut network's "
         "F(p) = radius(R(s)) - min over its struts [a, b] in the rest box (cut to it) of "
         "dist(p, [X(a), X(b)]), an intersection's other inputs bent as above",
         1, 1, params,
         [](CompileContext& c) {
           if (isUndeformed(c.node())) return c.input(0);
           if (straightStruts(c.node()))
             if (const std::optional<Slot> straight = compileStraight(c)) return *straight;
           auto input = std::make_shared<const Program>(compile(c.node().inputs.at(0)));
           auto field = std::make_shared<const FfdField>(std::move(input), mapOf(c.node()));
           return c.b.external(std::move(field), c.p.x, c.p.y, c.p.z);
         },
         [](const Node& n, const std::vector<Box3>& in) {
           return isUndeformed(n) ? in[0] : deformedBounds(*mapOf(n), in[0]);
         },
         checkFfd});
}

}  // namespace frep
