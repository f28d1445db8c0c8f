// Where the surface crosses an edge between two samples of opposite sides: the conventions
// the brick mesher and the local refinement share (the side of a value, the model's field
// cut by the box, the margin off an edge's ends) and one step of Illinois' method (regula
// falsi whose end kept twice has its value halved), which the mesher runs on all of a
// brick's edges in one batch, the refinement on its half-cell edges in one batch, and a
// refined cell on one spoke at a time.
#pragma once

namespace frep {

// A vertex is kept at least this fraction of its edge away from both ends, so no two vertices
// coincide and no triangle degenerates, whatever the field does at the samples.
constexpr double kEdgeMargin = 0.01;
// Root finding stops on an edge once its bracket is this narrow (a fraction of the edge) ...
constexpr double kRootBracket = 1e-7;
// ... or after this many steps where nothing else stops it (the refinement's edges, which
// have no float32 vertex test; the mesher stops at MeshingOptions::rootIterations)
constexpr int kMaxRootSteps = 40;

// The side of a field value: inside where F >= 0 (NaN counts as outside).
inline bool isInside(double v) {
  return v >= 0.0;
}
// min(F, B) of the model's field F and the box's B that keeps a NaN from F (outside).
inline double combine(double f, double b) {
  return b < f ? b : f;
}

// The bracket [ta, tb] of an edge's parameter with the values fa, fb at its ends (of opposite
// sides), and which end moved last (+1: a, -1: b, 0: neither yet).
struct IllinoisBracket {
  double ta = 0.0, tb = 1.0, fa = 0.0, fb = 0.0;
  int lastMoved = 0;
};

// The next estimate: the secant's zero, or the middle where that is not inside the bracket
// (NaN, infinities, a flat bracket).
inline double illinoisEstimate(double ta, double tb, double fa, double fb) {
  double x = (ta * fb - tb * fa) / (fb - fa);
  if (!(x > ta && x < tb)) x = 0.5 * (ta + tb);
  return x;
}
inline double illinoisEstimate(const IllinoisBracket& b) {
  return illinoisEstimate(b.ta, b.tb, b.fa, b.fb);
}

// The bracket after the value v at t: the end on v's side moves to t; an end kept a second
// time running has its value halved (Illinois), so the estimates close in from both sides.
// (Side: any signed integer type; the mesher keeps a byte per edge.)
template <typename Side>
inline void illinoisUpdate(double& ta, double& tb, double& fa, double& fb, Side& lastMoved,
                           double t, double v) {
  if (isInside(v) == isInside(fa)) {
    ta = t;
    fa = v;
    if (lastMoved == 1) fb *= 0.5;
    lastMoved = 1;
  } else {
    tb = t;
    fb = v;
    if (lastMoved == -1) fa *= 0.5;
    lastMoved = -1;
  }
}
inline void illinoisUpdate(IllinoisBracket& b, double t, double v) {
  illinoisUpdate(b.ta, b.tb, b.fa, b.fb, b.lastMoved, t, v);
}

}  // namespace frep
