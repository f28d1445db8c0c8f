// Bounds from the tree's structure: each node type may say where its solid can be, given where
// its inputs can be (a sphere's box, the hull of a union, a twist's enclosing cylinder).
// Interval arithmetic alone cannot bound some exact maps: a twist mixes x and y through sin
// and cos of z, and the intervals lose the fact that the rotation keeps distances, so a
// twisted box looked unbounded. These boxes narrow findBounds' search (BoundsOptions::known).
#pragma once

#include <vector>

#include "frep/tree.h"
#include "base/vec.h"

namespace frep {

// A box every point of the solid lies in; infinite sides where the structure tells nothing.
Box3 structuralBounds(const NodePtr& root);

// Helpers for the node types' bounds rules.
Box3 unknownBounds();
bool isFinite(const Box3& b);
// center +- half (per axis).
Box3 boxAround(const Vec3& center, const Vec3& half);
// b grown by pad on every side.
Box3 paddedBox(const Box3& b, double pad);
// The box of the points grown by pad (points not empty).
Box3 pointsBounds(const std::vector<Vec3>& points, double pad);
// The image of a box under the affine map q = M p + t (row-major 3x4).
Box3 affineImage(const Mat34& m, const Box3& b);
// The box around the solid of revolution reaching `radius` from the axis line through
// `origin` along unit `axis`, between axial coordinates lo and hi.
Box3 cylinderBounds(const Vec3& origin, const Vec3& axis, double lo, double hi, double radius);
// Everything a box can reach when turned about the axis line through `origin` along `axis`
// (any angles): the enclosing cylinder's box. Unknown when the box is not finite.
Box3 turnedAboutAxis(const Box3& b, const Vec3& origin, const Vec3& axis);
// For a finite box: its farthest distance from that axis line and its axial extent.
void radialExtent(const Box3& b, const Vec3& origin, const Vec3& axis, double* radius, double* lo,
                  double* hi);

}  // namespace frep
