// Plane geometry shared by material regions and obstacles: polylines and polygons.
#pragma once
#include <vector>

#include "mpm_solver/core/types.hpp"

namespace grainbank::mpm {

// A chain of vertices: an open polyline (e.g. a single segment, a "line" obstacle) or a closed
// polygon (the last vertex joins the first; either orientation).
struct Polyline {
  std::vector<Vec2> vertices;
  bool closed = false;
};

// Throws std::invalid_argument unless an open chain has ≥ 2 and a closed one ≥ 3 finite vertices,
// with no zero-length edge.
void check(const Polyline& shape);

// Point-in-polygon (crossing number); always false for an open chain.
bool contains(const Polyline& shape, const Vec2& x);

// The point of the chain's edges nearest to x.
Vec2 closest_point(const Polyline& shape, const Vec2& x);

}  // namespace grainbank::mpm
