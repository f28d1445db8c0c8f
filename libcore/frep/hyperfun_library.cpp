#include "frep/hyperfun_library.h"

#include <array>
#include <cmath>
#include <functional>
#include <map>

namespace frep::hyperfun {

namespace {

constexpr double kEps = 1e-6;  // HyperFun's zero

using Args = std::vector<LibraryArgument>;
using Compute = std::function<ExprPtr(Args&, ExprBuilder&)>;

struct LibraryFunction {
  const char* title;  // as HyperFun's manual spells it
  const char* kinds;  // 'A' array, 'R' number
  Compute compute;
};

// Item i (from 0) of an array argument, which must have a value.
ExprPtr item(const LibraryArgument& a, std::size_t i, ExprBuilder& b) {
  if (i >= a.array->size())
    b.fail("the array " + a.name + " has " + std::to_string(a.array->size()) +
           " items; this call reads item " + std::to_string(i + 1));
  const ExprPtr& v = (*a.array)[i];
  if (!v) b.fail(a.name + "[" + std::to_string(i + 1) + "] is used before it is given a value");
  return v;
}

// A number the library checks: when it is known now, `bad` must not hold.
void check(const ExprPtr& v, const std::function<bool(double)>& bad, const std::string& what,
           ExprBuilder& b) {
  if (ExprBuilder::isConstant(v) && bad(v->value)) b.fail(what);
}

bool nearZero(double v) {
  return std::fabs(v) < kEps;
}

// (p_axis - c_axis) for a point array and a centre array
ExprPtr offset(Args& a, int axis, ExprBuilder& b) {
  return b.sub(item(a[0], axis, b), item(a[1], axis, b));
}

ExprPtr sumOfSquares(const std::vector<ExprPtr>& v, ExprBuilder& b) {
  ExprPtr s = b.sqr(v[0]);
  for (std::size_t i = 1; i < v.size(); ++i) s = b.add(s, b.sqr(v[i]));
  return s;
}

// R^2 - the squares of the offsets across `axis` (a cylinder) or of all three (a sphere)
Compute roundPrimitive(const char* title, int axis) {
  return [title, axis](Args& a, ExprBuilder& b) {
    std::vector<ExprPtr> across;
    for (int k = 0; k < 3; ++k)
      if (k != axis) across.push_back(offset(a, k, b));
    return b.primitive(title, b.sub(b.sqr(a[2].value), sumOfSquares(across, b)));
  };
}

// 1 - ((p_i - c_i)/r_i)^2 over the axes `axes` with half-axes args[first...]
Compute ellipticPrimitive(const char* title, std::vector<int> axes, std::size_t first) {
  return [title, axes, first](Args& a, ExprBuilder& b) {
    std::vector<ExprPtr> scaled;
    for (std::size_t k = 0; k < axes.size(); ++k) {
      const ExprPtr r = a[first + k].value;
      check(r, nearZero, std::string(title) + ": a half-axis is 0", b);
      scaled.push_back(b.div(offset(a, axes[k], b), r));
    }
    return b.primitive(title, b.sub(b.constant(1.0), sumOfSquares(scaled, b)));
  };
}

// (p_axis - c_axis)^2 - ((others)/R)^2
Compute cone(const char* title, int axis) {
  return [title, axis](Args& a, ExprBuilder& b) {
    const ExprPtr r = a[2].value;
    check(r, nearZero, std::string(title) + ": the radius at height 1 is 0", b);
    std::vector<ExprPtr> across;
    for (int k = 0; k < 3; ++k)
      if (k != axis) across.push_back(b.div(offset(a, k, b), r));
    return b.primitive(title, b.sub(b.sqr(offset(a, axis, b)), sumOfSquares(across, b)));
  };
}

// r0^2 - |p - c|^2 - R^2 + 2 R sqrt(distance^2 from the axis)
Compute torus(const char* title, int axis) {
  return [title, axis](Args& a, ExprBuilder& b) {
    const ExprPtr big = a[2].value, small = a[3].value;
    std::vector<ExprPtr> all, across;
    for (int k = 0; k < 3; ++k) {
      all.push_back(offset(a, k, b));
      if (k != axis) across.push_back(all.back());
    }
    ExprPtr f = b.sub(b.sqr(small), sumOfSquares(all, b));
    f = b.sub(f, b.sqr(big));
    f = b.add(f, b.mul(b.mul(b.constant(2.0), big), b.call("sqrt", {sumOfSquares(across, b)})));
    return b.primitive(title, f);
  };
}

// The intersection of the three slabs (p - v)(v + d - p) >= 0, by the R-function (alpha 0).
ExprPtr block(Args& a, ExprBuilder& b) {
  ExprPtr slab[3];
  for (int k = 0; k < 3; ++k) {
    check(
        a[2 + k].value, [](double d) { return d < 0.0; }, "hfBlock: an edge length is negative", b);
    const ExprPtr v = item(a[1], k, b), p = item(a[0], k, b);
    slab[k] = b.mul(b.sub(p, v), b.sub(b.add(v, a[2 + k].value), p));
  }
  auto meet = [&](ExprPtr f, ExprPtr g) {
    return b.sub(b.add(f, g), b.call("sqrt", {b.add(b.sqr(f), b.sqr(g))}));
  };
  return b.primitive("hfBlock", meet(meet(slab[0], slab[1]), slab[2]));
}

ExprPtr superellipsoid(Args& a, ExprBuilder& b) {
  for (int k = 2; k < 7; ++k)
    check(a[k].value, nearZero, "hfSuperell: a half-axis or shape parameter is 0", b);
  const ExprPtr s1 = a[5].value, s2 = a[6].value;
  ExprPtr t[3];
  for (int k = 0; k < 3; ++k) t[k] = b.call("abs", {b.div(offset(a, k, b), a[2 + k].value)});
  const ExprPtr p = b.div(b.constant(2.0), s2);
  const ExprPtr xy = b.add(b.pow(t[0], p), b.pow(t[1], p));
  const ExprPtr f = b.sub(b.sub(b.constant(1.0), b.pow(xy, b.div(s2, s1))),
                          b.pow(t[2], b.div(b.constant(2.0), s1)));
  return b.primitive("hfSuperell", f);
}

// Sum over the centres (arrays x0, y0, z0 of equal length) of kernel(squared distance, i).
ExprPtr centreSum(Args& a, const std::function<ExprPtr(ExprPtr, std::size_t)>& kernel,
                  ExprBuilder& b) {
  const std::size_t n = a[1].array->size();
  for (int k = 2; k <= 3; ++k)
    if (a[k].array->size() < n)
      b.fail("the centre arrays differ in length (" + a[1].name + ": " + std::to_string(n) + ", " +
             a[k].name + ": " + std::to_string(a[k].array->size()) + ")");
  ExprPtr sum = b.constant(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<ExprPtr> d;
    for (int k = 0; k < 3; ++k) d.push_back(b.sub(item(a[0], k, b), item(a[1 + k], i, b)));
    if (ExprPtr term = kernel(sumOfSquares(d, b), i)) sum = b.add(sum, term);
  }
  return sum;
}

ExprPtr blobby(Args& a, ExprBuilder& b) {
  const ExprPtr sum = centreSum(
      a,
      [&](ExprPtr r2, std::size_t i) {
        return b.mul(item(a[5], i, b), b.call("exp", {b.neg(b.mul(item(a[4], i, b), r2))}));
      },
      b);
  return b.primitive("hfBlobby", b.sub(sum, a[6].value));
}

// Nishimura's kernel: b (1 - 3 t^2) to t = 1/3, 3/2 b (1 - t)^2 to t = 1, then 0 (t = r/d),
// as one expression: the two pieces meet at t = 1/3 with value 2b/3.
ExprPtr metaball(Args& a, ExprBuilder& b) {
  const ExprPtr sum = centreSum(
      a,
      [&](ExprPtr r2, std::size_t i) -> ExprPtr {
        const ExprPtr d = item(a[5], i, b);
        const double radius = b.constantOf(d, "hfMetaball's radius of influence");
        if (radius <= 0.0) return nullptr;  // HyperFun skips such a centre
        const ExprPtr strength = item(a[4], i, b);
        const ExprPtr t = b.div(b.call("sqrt", {r2}), d);
        const ExprPtr inner = b.call("min", {t, b.constant(1.0 / 3.0)});
        const ExprPtr outer = b.call("clamp", {t, b.constant(1.0 / 3.0), b.constant(1.0)});
        ExprPtr k = b.mul(strength, b.sub(b.constant(1.0), b.mul(b.constant(3.0), b.sqr(inner))));
        k = b.add(k, b.mul(b.mul(b.constant(1.5), strength), b.sqr(b.sub(b.constant(1.0), outer))));
        return b.sub(k, b.mul(b.constant(2.0 / 3.0), strength));
      },
      b);
  return b.primitive("hfMetaball", b.sub(sum, a[6].value));
}

// Wyvill's soft objects: 1 - 22/9 t + 17/9 t^2 - 4/9 t^3 with t = min(r^2/d^2, 1)
ExprPtr soft(Args& a, ExprBuilder& b) {
  const ExprPtr sum = centreSum(
      a,
      [&](ExprPtr r2, std::size_t i) -> ExprPtr {
        const ExprPtr d = item(a[4], i, b);
        const double radius = b.constantOf(d, "hfSoft's radius of influence");
        if (radius <= 0.0) return nullptr;
        const ExprPtr t = b.call("min", {b.div(r2, b.sqr(d)), b.constant(1.0)});
        ExprPtr poly = b.sub(b.constant(1.0), b.mul(b.constant(22.0 / 9.0), t));
        poly = b.add(poly, b.mul(b.constant(17.0 / 9.0), b.sqr(t)));
        return b.sub(poly, b.mul(b.constant(4.0 / 9.0), b.mul(b.sqr(t), t)));
      },
      b);
  return b.primitive("hfSoft", b.sub(sum, a[5].value));
}

// Cauchy kernels 1 / (1 + S^2 r^2)^2 round the points of `vect` (x, y, z of each in turn)
ExprPtr convolutionPoints(Args& a, ExprBuilder& b) {
  const std::size_t n = a[2].array->size();
  if (a[1].array->size() < 3 * n)
    b.fail("hfConvPoint: " + a[1].name + " holds " + std::to_string(a[1].array->size()) +
           " coordinates for " + std::to_string(n) + " points (3 each)");
  ExprPtr sum = b.constant(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<ExprPtr> d;
    for (int k = 0; k < 3; ++k) d.push_back(b.sub(item(a[1], 3 * i + k, b), item(a[0], k, b)));
    const ExprPtr s = item(a[2], i, b);
    const ExprPtr q = b.add(b.constant(1.0), b.mul(b.sqr(s), sumOfSquares(d, b)));
    sum = b.add(sum, b.div(b.constant(1.0), b.sqr(q)));
  }
  return b.primitive("hfConvPoint", b.sub(sum, a[3].value));
}

ExprPtr dot(const std::vector<ExprPtr>& a, const std::vector<ExprPtr>& b, ExprBuilder& e) {
  return e.add(e.add(e.mul(a[0], b[0]), e.mul(a[1], b[1])), e.mul(a[2], b[2]));
}

// McCormack and Sherstyuk's closed form of the Cauchy kernel integrated along each segment
// (begin[3i..3i+2] to end[3i..3i+2], width S[i]).
ExprPtr convolutionLines(Args& a, ExprBuilder& b) {
  const std::size_t n = a[3].array->size();
  for (int k = 1; k <= 2; ++k)
    if (a[k].array->size() < 3 * n)
      b.fail("hfConvLine: " + a[k].name + " holds " + std::to_string(a[k].array->size()) +
             " coordinates for " + std::to_string(n) + " segments (3 each)");
  ExprPtr sum = b.constant(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<ExprPtr> along, d;
    for (int k = 0; k < 3; ++k) {
      along.push_back(b.sub(item(a[2], 3 * i + k, b), item(a[1], 3 * i + k, b)));
      d.push_back(b.sub(item(a[0], k, b), item(a[1], 3 * i + k, b)));
    }
    const ExprPtr l = b.call("sqrt", {sumOfSquares(along, b)});
    check(
        l, [](double v) { return v == 0.0; }, "hfConvLine: a segment's ends are the same", b);
    for (ExprPtr& c : along) c = b.div(c, l);
    const ExprPtr s = item(a[3], i, b), s2 = b.sqr(s);
    const ExprPtr t = dot(d, along, b), d2 = sumOfSquares(d, b);
    const ExprPtr p2 = b.add(b.constant(1.0), b.mul(s2, b.sub(d2, b.sqr(t))));
    const ExprPtr p = b.call("sqrt", {p2});
    const ExprPtr q2 =
        b.add(b.constant(1.0),
              b.mul(s2, b.sub(b.add(d2, b.sqr(l)), b.mul(b.mul(b.constant(2.0), l), t))));
    const ExprPtr rest = b.sub(l, t);
    ExprPtr f = b.div(t, b.mul(b.mul(b.constant(2.0), p2), b.add(p2, b.mul(s2, b.sqr(t)))));
    f = b.add(f, b.div(rest, b.mul(b.mul(b.constant(2.0), p2), q2)));
    const ExprPtr arcs =
        b.add(b.call("atan", {b.div(b.mul(s, t), p)}), b.call("atan", {b.div(b.mul(s, rest), p)}));
    f = b.add(f, b.div(arcs, b.mul(b.mul(b.mul(b.constant(2.0), s), p2), p)));
    sum = b.add(sum, f);
  }
  return b.primitive("hfConvLine", b.sub(sum, a[4].value));
}

// McCormack and Sherstyuk's closed form over each triangle (vect[9i..9i+8]): the triangle is
// split at the foot of its height on its longest side; the geometry is numbers, the point's
// part stays an expression.
ExprPtr convolutionTriangles(Args& a, ExprBuilder& b) {
  const std::size_t n = a[2].array->size();
  if (a[1].array->size() < 9 * n)
    b.fail("hfConvTriangle: " + a[1].name + " holds " + std::to_string(a[1].array->size()) +
           " coordinates for " + std::to_string(n) + " triangles (9 each)");
  using P = std::array<double, 3>;
  auto minus = [](const P& u, const P& v) { return P{u[0] - v[0], u[1] - v[1], u[2] - v[2]}; };
  auto norm = [](const P& u) { return std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]); };
  ExprPtr sum = b.constant(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    P v[3];
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k)
        v[c][k] = b.constantOf(item(a[1], 9 * i + 3 * c + k, b), "hfConvTriangle's corners");
    // the longest side first (from corner 1 to corner 2)
    const double l01 = norm(minus(v[1], v[0])), l12 = norm(minus(v[2], v[1])),
                 l20 = norm(minus(v[0], v[2]));
    if (l12 >= l20 && l12 > l01) {
      const P t = v[0];
      v[0] = v[1];
      v[1] = v[2];
      v[2] = t;
    } else if (l20 >= l12 && l20 > l01) {
      const P t = v[0];
      v[0] = v[2];
      v[2] = v[1];
      v[1] = t;
    }
    const P side = minus(v[1], v[0]), back = minus(v[0], v[2]);
    const double side2 = side[0] * side[0] + side[1] * side[1] + side[2] * side[2];
    if (side2 == 0.0) b.fail("hfConvTriangle: a triangle has no area");
    const double t = -(side[0] * back[0] + side[1] * back[1] + side[2] * back[2]) / side2;
    const P foot = {v[0][0] + t * side[0], v[0][1] + t * side[1], v[0][2] + t * side[2]};
    const P toCorner2 = minus(v[1], foot), toApex = minus(v[2], foot);
    const double h = norm(toApex), a1 = norm(minus(v[0], foot)), a2 = norm(toCorner2);
    if (h == 0.0 || a2 == 0.0) b.fail("hfConvTriangle: a triangle has no area");
    std::vector<ExprPtr> d, uAxis, vAxis;
    for (int k = 0; k < 3; ++k) {
      d.push_back(b.sub(item(a[0], k, b), b.constant(foot[k])));
      uAxis.push_back(b.constant(toCorner2[k] / a2));
      vAxis.push_back(b.constant(toApex[k] / h));
    }
    const ExprPtr s = item(a[2], i, b);
    const ExprPtr u = dot(d, uAxis, b), w = dot(d, vAxis, b), d2 = sumOfSquares(d, b);
    const ExprPtr H = b.constant(h), A1 = b.constant(a1), A2 = b.constant(a2);
    const ExprPtr g = b.sub(w, H);
    const ExprPtr m = b.add(b.mul(A2, g), b.mul(u, H));
    const ExprPtr k = b.sub(b.mul(u, H), b.mul(A1, g));
    const ExprPtr c2 = b.sub(b.add(b.div(b.constant(1.0), b.sqr(s)), d2), b.sqr(u));
    const ExprPtr c = b.call("sqrt", {c2});
    const ExprPtr q = b.sub(c2, b.sqr(w));
    const ExprPtr ww = b.add(b.sub(c2, b.mul(b.mul(b.constant(2.0), w), H)), b.constant(h * h));
    const ExprPtr hq = b.mul(b.constant(h * h), b.add(q, b.sqr(u)));
    const ExprPtr huG = b.mul(b.mul(b.constant(2.0 * h), u), g);
    const ExprPtr bigA = b.call(
        "sqrt", {b.sub(b.add(b.mul(b.constant(a1 * a1), ww), hq), b.mul(b.constant(a1), huG))});
    const ExprPtr bigB = b.call(
        "sqrt", {b.add(b.add(b.mul(b.constant(a2 * a2), ww), hq), b.mul(b.constant(a2), huG))});
    const ExprPtr n1 = b.add(A1, u), n2 = b.sub(A2, u);
    const ExprPtr n3 = b.add(b.mul(A1, n1), b.mul(w, H));
    const ExprPtr n4 = b.sub(b.neg(b.mul(A1, u)), b.mul(g, H));
    const ExprPtr n5 = b.sub(b.neg(b.mul(A2, n2)), b.mul(w, H));
    const ExprPtr n6 = b.add(b.neg(b.mul(A2, u)), b.mul(g, H));
    auto pair = [&](ExprPtr weight, ExprPtr p1, ExprPtr p2, ExprPtr r) {
      return b.div(
          b.mul(weight, b.add(b.call("atan", {b.div(p1, r)}), b.call("atan", {b.div(p2, r)}))), r);
    };
    const ExprPtr arc =
        b.add(b.add(pair(k, n3, n4, bigA), pair(m, n5, n6, bigB)), pair(w, n1, n2, c));
    sum = b.add(sum, b.div(arc, b.mul(b.mul(b.constant(2.0), q), s)));
  }
  return b.primitive("hfConvTriangle", b.sub(sum, a[3].value));
}

// McCormack and Sherstyuk's closed form along each arc: the point is turned into the arc's
// frame (its axis and angle, in degrees, with HyperFun's own constants: pi as 3.141592 and
// 1e-6 added to the angle and axis), and an arc over 180 degrees is summed as two pieces. The
// form's p2 is never positive (it is minus a sum of squares), so its atan branch is the one.
ExprPtr convolutionArcs(Args& a, ExprBuilder& b) {
  const std::size_t n = a[6].array->size();
  for (int k : {1, 4})
    if (a[k].array->size() < 3 * n)
      b.fail("hfConvArc: " + a[k].name + " holds " + std::to_string(a[k].array->size()) +
             " coordinates for " + std::to_string(n) + " arcs (3 each)");
  for (int k : {2, 3, 5})
    if (a[k].array->size() < n)
      b.fail("hfConvArc: " + a[k].name + " has " + std::to_string(a[k].array->size()) +
             " items for " + std::to_string(n) + " arcs");
  constexpr double kPi = 3.141592, kDegree = kPi / 180.0;
  auto number = [&](int arg, std::size_t i) {
    return b.constantOf(item(a[arg], i, b), "hfConvArc's arcs");
  };
  // rotation by -angle (degrees) about the unit axis (i, j, k)
  using M = std::array<double, 9>;
  auto rotation = [&](double i, double j, double k, double angle) {
    const double c = std::cos(kDegree * -angle), s = std::sin(kDegree * -angle), o = 1.0 - c;
    return M{c + i * i * o,      -k * s + i * j * o, j * s + k * i * o,
             k * s + i * j * o,  c + j * j * o,      -i * s + j * k * o,
             -j * s + k * i * o, i * s + j * k * o,  c + k * k * o};
  };
  auto apply = [&](const M& m, const std::vector<ExprPtr>& p) {
    std::vector<ExprPtr> out;
    for (int r = 0; r < 3; ++r)
      out.push_back(
          b.add(b.add(b.mul(b.constant(m[3 * r]), p[0]), b.mul(b.constant(m[3 * r + 1]), p[1])),
                b.mul(b.constant(m[3 * r + 2]), p[2])));
    return out;
  };
  auto piece = [&](const std::vector<ExprPtr>& p, double r, ExprPtr s, double th) {
    const ExprPtr X = p[0], Y = p[1], Z = p[2], s2 = b.sqr(s);
    const ExprPtr A = b.mul(b.constant(2.0 * r), s2);
    const ExprPtr d2 = sumOfSquares(p, b);
    const ExprPtr r2s2 = b.mul(b.constant(r * r), s2);
    const ExprPtr B = b.add(b.add(b.constant(1.0), r2s2), b.mul(s2, d2));
    ExprPtr p2 = b.neg(b.sqr(r2s2));
    p2 = b.add(
        p2, b.mul(b.mul(b.constant(2.0), r2s2),
                  b.sub(b.mul(s2, b.sub(d2, b.mul(b.constant(2.0), b.sqr(Z)))), b.constant(1.0))));
    p2 = b.sub(p2, b.sqr(b.add(b.constant(1.0), b.mul(s2, d2))));
    const ExprPtr p1 = b.call("sqrt", {b.neg(p2)});
    const ExprPtr p3 = b.mul(p1, p2);
    const ExprPtr sinT = b.constant(std::sin(th)), cosT = b.constant(std::cos(th));
    ExprPtr f1 = b.div(b.mul(B, Y), b.mul(b.mul(X, p2), b.sub(b.mul(A, X), B)));
    const ExprPtr num = b.sub(b.mul(b.mul(A, b.add(b.sqr(X), b.sqr(Y))), sinT), b.mul(B, Y));
    const ExprPtr den =
        b.mul(b.mul(X, p2), b.sub(b.mul(A, b.add(b.mul(X, cosT), b.mul(Y, sinT))), B));
    f1 = b.add(f1, b.div(num, den));
    const ExprPtr first = b.call("atan", {b.div(b.neg(b.mul(A, Y)), p1)});
    const ExprPtr second = b.call(
        "atan",
        {b.div(b.sub(b.mul(A, Y), b.mul(b.add(b.mul(A, X), B), b.constant(std::tan(th / 2)))),
               p1)});
    const ExprPtr f2 = b.div(b.mul(b.mul(b.constant(2.0), B), b.add(first, second)), p3);
    return b.add(f1, f2);
  };
  constexpr double eps = 1e-6;
  ExprPtr sum = b.constant(0.0);
  for (std::size_t i = 0; i < n; ++i) {
    std::vector<ExprPtr> d;
    for (int k = 0; k < 3; ++k)
      d.push_back(b.sub(item(a[0], k, b), b.constant(number(1, 3 * i + k))));
    const double r = number(2, i);
    double theta = std::min(number(3, i), 360.0);
    double ax = number(4, 3 * i) + eps, ay = number(4, 3 * i + 1) + eps,
           az = number(4, 3 * i + 2) + eps;
    const double length = std::max(std::sqrt(ax * ax + ay * ay + az * az), eps);
    ax /= length, ay /= length, az /= length;
    const M turn = rotation(ax, ay, az, number(5, i) + eps);
    const std::vector<ExprPtr> p = apply(turn, d);
    const ExprPtr s = item(a[6], i, b);
    if (theta > 180.0) {  // the part beyond half a turn, turned back by 180 degrees about z
      sum = b.add(sum, piece(apply(rotation(0, 0, 1, 180.0), p), r, s, (theta - 180.0) * kDegree));
      theta = 180.0;
    }
    sum = b.add(sum, piece(p, r, s, theta * kDegree));
  }
  return b.primitive("hfConvArc", b.sub(sum, a[7].value));
}

// Gardner's solid noise: a product of three two-term sine series
ExprPtr noise(Args& a, ExprBuilder& b) {
  const ExprPtr amp = a[1].value, freq = a[2].value, phase = a[3].value;
  ExprPtr s[3], wave[3];
  for (int k = 0; k < 3; ++k) {
    wave[k] = b.mul(freq, item(a[0], k, b));
    s[k] = b.call("sin", {wave[k]});
  }
  const ExprPtr second = b.div(amp, b.constant(1.17));
  ExprPtr product;
  for (int k = 0; k < 3; ++k) {
    const ExprPtr shifted = b.add(b.div(wave[k], b.constant(1.35)), b.mul(phase, s[(k + 2) % 3]));
    const ExprPtr series = b.add(b.mul(amp, s[k]), b.mul(second, b.call("sin", {shifted})));
    product = k == 0 ? series : b.mul(product, series);
  }
  return b.primitive("hfNoiseG", product);
}

Compute blendOf(Expr::Kind kind, const char* title) {
  return [kind, title](Args& a, ExprBuilder& b) {
    const ExprPtr f1 = a[0].value, f2 = a[1].value;
    const ExprPtr a0 = a[2].value, a1 = a[3].value, a2 = a[4].value;
    check(a1, nearZero, std::string(title) + ": a1 is 0", b);
    check(a2, nearZero, std::string(title) + ": a2 is 0", b);
    if (ExprBuilder::isConstant(a0) && ExprBuilder::isConstant(a1) && ExprBuilder::isConstant(a2))
      return b.blend(kind, f1, f2, a0->value, a1->value, a2->value);
    // parameters that vary over space: the same value written out
    const Expr::Kind setKind =
        kind == Expr::Kind::BlendUnion ? Expr::Kind::Union : Expr::Kind::Intersection;
    const ExprPtr bump =
        b.div(a0, b.add(b.add(b.constant(1.0), b.sqr(b.div(f1, a1))), b.sqr(b.div(f2, a2))));
    return b.add(b.setOperation(setKind, f1, f2), bump);
  };
}

// Transformations: each replaces the items of the array args[0] (an inverse mapping of the
// point) and returns 1.
using Mapping = std::function<void(std::vector<ExprPtr>& p, Args& a, ExprBuilder& b)>;

Compute transformation(Mapping mapping) {
  return [mapping](Args& a, ExprBuilder& b) {
    std::vector<ExprPtr> p;
    for (int k = 0; k < 3; ++k) p.push_back(item(a[0], k, b));
    mapping(p, a, b);
    for (int k = 0; k < 3; ++k) (*a[0].array)[k] = p[k];
    return b.constant(1.0);
  };
}

// (u, v) -> (u cos t + v sin t, -u sin t + v cos t)
void rotatePair(ExprPtr& u, ExprPtr& v, const ExprPtr& angle, ExprBuilder& b) {
  const ExprPtr c = b.call("cos", {angle}), s = b.call("sin", {angle});
  const ExprPtr u2 = b.add(b.mul(u, c), b.mul(v, s));
  const ExprPtr v2 = b.add(b.neg(b.mul(u, s)), b.mul(v, c));
  u = u2;
  v = v2;
}

// The rotated pair for each axis: about x (y, z), about y (z, x), about z (x, y).
constexpr int kPair[3][2] = {{1, 2}, {2, 0}, {0, 1}};

Compute rotation(int axis) {
  return transformation([axis](std::vector<ExprPtr>& p, Args& a, ExprBuilder& b) {
    rotatePair(p[kPair[axis][0]], p[kPair[axis][1]], a[1].value, b);
  });
}

Compute twist(const char* title, int axis) {
  return transformation([axis, title](std::vector<ExprPtr>& p, Args& a, ExprBuilder& b) {
    const ExprPtr span = b.sub(a[2].value, a[1].value);
    check(span, nearZero, std::string(title) + ": the two ends are the same", b);
    const ExprPtr t = b.div(b.sub(p[axis], a[1].value), span);
    const ExprPtr angle = b.add(b.mul(b.sub(b.constant(1.0), t), a[3].value), b.mul(t, a[4].value));
    rotatePair(p[kPair[axis][0]], p[kPair[axis][1]], angle, b);
  });
}

Compute taper(const char* title, int axis) {
  return transformation([axis, title](std::vector<ExprPtr>& p, Args& a, ExprBuilder& b) {
    for (int k = 3; k <= 4; ++k)
      check(
          a[k].value, [](double s) { return s <= 0.0; },
          std::string(title) + ": the scales must be > 0", b);
    const ExprPtr span = b.sub(a[2].value, a[1].value);
    check(span, nearZero, std::string(title) + ": the two ends are the same", b);
    const ExprPtr t = b.call(
        "clamp", {b.div(b.sub(p[axis], a[1].value), span), b.constant(0.0), b.constant(1.0)});
    const ExprPtr scale = b.add(b.mul(b.sub(b.constant(1.0), t), a[3].value), b.mul(t, a[4].value));
    for (int k = 0; k < 3; ++k)
      if (k != axis) p[k] = b.div(p[k], scale);
  });
}

const std::map<std::string, LibraryFunction>& library() {
  static const std::map<std::string, LibraryFunction> table = [] {
    std::map<std::string, LibraryFunction> t;
    t["hfsphere"] = {"hfSphere", "AAR", roundPrimitive("hfSphere", -1)};
    t["hfcylinderx"] = {"hfCylinderX", "AAR", roundPrimitive("hfCylinderX", 0)};
    t["hfcylindery"] = {"hfCylinderY", "AAR", roundPrimitive("hfCylinderY", 1)};
    t["hfcylinderz"] = {"hfCylinderZ", "AAR", roundPrimitive("hfCylinderZ", 2)};
    t["hfellipsoid"] = {"hfEllipsoid", "AARRR", ellipticPrimitive("hfEllipsoid", {0, 1, 2}, 2)};
    t["hfellcylx"] = {"hfEllCylX", "AARR", ellipticPrimitive("hfEllCylX", {1, 2}, 2)};
    t["hfellcyly"] = {"hfEllCylY", "AARR", ellipticPrimitive("hfEllCylY", {0, 2}, 2)};
    t["hfellcylz"] = {"hfEllCylZ", "AARR", ellipticPrimitive("hfEllCylZ", {0, 1}, 2)};
    t["hfconex"] = {"hfConeX", "AAR", cone("hfConeX", 0)};
    t["hfconey"] = {"hfConeY", "AAR", cone("hfConeY", 1)};
    t["hfconez"] = {"hfConeZ", "AAR", cone("hfConeZ", 2)};
    t["hftorusx"] = {"hfTorusX", "AARR", torus("hfTorusX", 0)};
    t["hftorusy"] = {"hfTorusY", "AARR", torus("hfTorusY", 1)};
    t["hftorusz"] = {"hfTorusZ", "AARR", torus("hfTorusZ", 2)};
    t["hfblock"] = {"hfBlock", "AARRR", block};
    t["hfsuperell"] = {"hfSuperell", "AARRRRR", superellipsoid};
    t["hfblobby"] = {"hfBlobby", "AAAAAAR", blobby};
    t["hfmetaball"] = {"hfMetaball", "AAAAAAR", metaball};
    t["hfsoft"] = {"hfSoft", "AAAAAR", soft};
    t["hfconvpoint"] = {"hfConvPoint", "AAAR", convolutionPoints};
    t["hfconvline"] = {"hfConvLine", "AAAAR", convolutionLines};
    t["hfconvtriangle"] = {"hfConvTriangle", "AAAR", convolutionTriangles};
    t["hfconvarc"] = {"hfConvArc", "AAAAAAAR", convolutionArcs};
    t["hfnoiseg"] = {"hfNoiseG", "ARRR", noise};
    t["hfblenduni"] = {"hfBlendUni", "RRRRR", blendOf(Expr::Kind::BlendUnion, "hfBlendUni")};
    t["hfblendint"] = {"hfBlendInt", "RRRRR", blendOf(Expr::Kind::BlendIntersection, "hfBlendInt")};
    t["hfshift3d"] = {"hfShift3D", "ARRR", transformation([](auto& p, Args& a, ExprBuilder& b) {
                        for (int k = 0; k < 3; ++k) p[k] = b.sub(p[k], a[1 + k].value);
                      })};
    t["hfscale3d"] = {"hfScale3D", "ARRR", transformation([](auto& p, Args& a, ExprBuilder& b) {
                        for (int k = 0; k < 3; ++k) {
                          check(a[1 + k].value, nearZero, "hfScale3D: a scale is 0", b);
                          p[k] = b.div(p[k], a[1 + k].value);
                        }
                      })};
    t["hfstretch3d"] = {"hfStretch3D", "AARRR",
                        transformation([](auto& p, Args& a, ExprBuilder& b) {
                          for (int k = 0; k < 3; ++k) {
                            check(a[2 + k].value, nearZero, "hfStretch3D: a scale is 0", b);
                            const ExprPtr c = item(a[1], k, b);
                            p[k] = b.add(c, b.div(b.sub(p[k], c), a[2 + k].value));
                          }
                        })};
    t["hfrotate3dx"] = {"hfRotate3DX", "AR", rotation(0)};
    t["hfrotate3dy"] = {"hfRotate3DY", "AR", rotation(1)};
    t["hfrotate3dz"] = {"hfRotate3DZ", "AR", rotation(2)};
    t["hftwistx"] = {"hfTwistX", "ARRRR", twist("hfTwistX", 0)};
    t["hftwisty"] = {"hfTwistY", "ARRRR", twist("hfTwistY", 1)};
    t["hftwistz"] = {"hfTwistZ", "ARRRR", twist("hfTwistZ", 2)};
    t["hftaperx"] = {"hfTaperX", "ARRRR", taper("hfTaperX", 0)};
    t["hftapery"] = {"hfTaperY", "ARRRR", taper("hfTaperY", 1)};
    t["hftaperz"] = {"hfTaperZ", "ARRRR", taper("hfTaperZ", 2)};
    return t;
  }();
  return table;
}

}  // namespace

std::string libraryArguments(const std::string& name, std::string* unsupported) {
  if (unsupported) unsupported->clear();
  const auto it = library().find(name);
  if (it != library().end()) return it->second.kinds;
  if (unsupported && name.rfind("hf", 0) == 0) {
    static const std::map<std::string, const char*> others = {
        {"hfconvliner", "convolution line segments of varying width"},
        {"hfconvcurve", "convolution curves"},
        {"hfconvmesh", "convolution meshes"},
        {"hfellconex", "elliptic cones"},
        {"hfellconey", "elliptic cones"},
        {"hfellconez", "elliptic cones"},
        {"hfbeziervolume", "Bezier volumes"},
        {"hfspacemapcubic", "space mappings"},
        {"hfspacemapexp", "space mappings"},
    };
    const auto o = others.find(name);
    if (o != others.end())
      *unsupported = std::string(o->second) + " (" + name + ") are not translated yet";
    else if (name.rfind("hfa_", 0) == 0)
      *unsupported = "attribute functions (" + name + ") give colours, not shape";
  }
  return "";
}

ExprPtr callLibrary(const std::string& name, std::vector<LibraryArgument>& args, ExprBuilder& b) {
  return library().at(name).compute(args, b);
}

std::vector<std::string> libraryNames() {
  std::vector<std::string> out;
  for (const auto& [key, f] : library()) out.push_back(f.title);
  return out;
}

}  // namespace frep::hyperfun
