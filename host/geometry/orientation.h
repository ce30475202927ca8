// orient2d: the 2-D orientation determinant with an exact sign, for inside tests that must not be fooled
// by a point exactly on an edge or a vertex.
#pragma once

namespace romp::geometry {

// (a − c) × (b − c): positive when a, b, c turn counter-clockwise, negative when clockwise, zero
// when collinear. The sign is exact for any finite inputs whose products neither overflow nor
// underflow (Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust geometric
// predicates"): a floating-point evaluation decides when its error bound allows, and an exact
// expansion sum decides the rest. The magnitude is the floating-point estimate.
double orient2d(double ax, double ay, double bx, double by, double cx, double cy);

}  // namespace romp::geometry
