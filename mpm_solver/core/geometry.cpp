#include "mpm_solver/core/geometry.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace grainbank::mpm {

namespace {
template <class F>
void for_each_edge(const Polyline& shape, F&& f) {
  const std::size_t n = shape.vertices.size();
  const std::size_t edges = shape.closed ? n : n - 1;
  for (std::size_t k = 0; k < edges; ++k) f(shape.vertices[k], shape.vertices[(k + 1) % n]);
}
}  // namespace

void check(const Polyline& shape) {
  const std::size_t need = shape.closed ? 3 : 2;
  if (shape.vertices.size() < need)
    throw std::invalid_argument(shape.closed ? "a polygon needs at least 3 vertices" : "a line needs at least 2 vertices");
  for (const Vec2& v : shape.vertices)
    if (!v.allFinite()) throw std::invalid_argument("vertices must be finite");
  for_each_edge(shape, [](const Vec2& a, const Vec2& b) {
    if (a == b) throw std::invalid_argument("two consecutive vertices coincide");
  });
}

bool contains(const Polyline& shape, const Vec2& x) {
  if (!shape.closed) return false;
  bool inside = false;
  for_each_edge(shape, [&](const Vec2& a, const Vec2& b) {
    if ((a.y() > x.y()) != (b.y() > x.y()) &&
        x.x() < a.x() + (x.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  });
  return inside;
}

Vec2 closest_point(const Polyline& shape, const Vec2& x) {
  Vec2 best = shape.vertices.front();
  double best_d2 = std::numeric_limits<double>::infinity();
  for_each_edge(shape, [&](const Vec2& a, const Vec2& b) {
    const Vec2 e = b - a;
    const double s = std::clamp((x - a).dot(e) / e.squaredNorm(), 0.0, 1.0);
    const Vec2 c = a + s * e;
    const double d2 = (x - c).squaredNorm();
    if (d2 < best_d2) best_d2 = d2, best = c;
  });
  return best;
}

}  // namespace grainbank::mpm
