#include "transfers.hpp"

#include "parallel.hpp"

#include <omp.h>

namespace grainbank::mpm {

namespace {

// Runs scatter(point, stencil, sums) for every point in parallel, each thread into its own buffer,
// then adds the buffers into grid.sums (momentum only when only momentum was scattered).
template <bool MomentumOnly, class Scatter>
void scatter_points(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                    ScatterBuffers& buffers, Scatter&& scatter) {
  const long n = static_cast<long>(points.size());
  const int threads = static_cast<int>(buffers.per_thread.size());
  if (threads == 1 || n < kMinParallelItems) {
    for (long p = 0; p < n; ++p) scatter(points[p], stencils[p], grid.sums);
    return;
  }
#pragma omp parallel num_threads(threads)
  {
    NodeSums& mine = buffers.per_thread[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (long p = 0; p < n; ++p) scatter(points[p], stencils[p], mine);
  }
  const long nodes = static_cast<long>(grid.node_count());
#pragma omp parallel for schedule(static) num_threads(threads) if (nodes >= kMinParallelItems)
  for (long k = 0; k < nodes; ++k) {
    for (NodeSums& b : buffers.per_thread) {
      grid.sums.momentum[k] += b.momentum[k];
      b.momentum[k].setZero();
      if constexpr (!MomentumOnly) {
        grid.sums.mass[k] += b.mass[k];
        grid.sums.force[k] += b.force[k];
        b.mass[k] = 0;
        b.force[k].setZero();
      }
    }
  }
}

}  // namespace

ScatterBuffers::ScatterBuffers(std::size_t nodes) : per_thread(std::max(omp_get_max_threads(), 1)) {
  if (per_thread.size() > 1)
    for (NodeSums& b : per_thread) b.resize(nodes);
}

void compute_stencils(const Grid& grid, const std::vector<MaterialPoint>& points, std::vector<Stencil>& stencils) {
  stencils.resize(points.size());
  const long n = static_cast<long>(points.size());
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (long p = 0; p < n; ++p) stencils[p] = stencil_at(grid, points[p].position);
}

void particles_to_grid(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                       ScatterBuffers& buffers) {
  grid.sums.clear();
  const std::size_t stride = grid.nodes_x();
  scatter_points<false>(grid, points, stencils, buffers, [stride](const MaterialPoint& mp, const Stencil& s, NodeSums& acc) {
    const Vec2 momentum = mp.mass * mp.velocity;
    const Mat2 vs = mp.volume * mp.stress.in_plane;
    for (int b = 0; b < 4; ++b) {
      const std::size_t row = s.first_node + b * stride;
      for (int a = 0; a < 4; ++a) {
        const double N = s.wx[a] * s.wy[b];
        const Vec2 grad(s.gx[a] * s.wy[b], s.wx[a] * s.gy[b]);
        acc.mass[row + a] += N * mp.mass;
        acc.momentum[row + a] += N * momentum;
        acc.force[row + a] += N * mp.external_force - vs * grad;
      }
    }
  });
}

void update_grid(Grid& grid, const Vec2& gravity) {
  const long nodes = static_cast<long>(grid.node_count());
#pragma omp parallel for schedule(static) if (nodes >= kMinParallelItems)
  for (long k = 0; k < nodes; ++k) {
    const double m = grid.sums.mass[k];
    if (m > 0) {
      grid.velocity[k] = grid.sums.momentum[k] / m;
      grid.acceleration[k] = grid.sums.force[k] / m + gravity;
    } else {
      grid.velocity[k].setZero();
      grid.acceleration[k].setZero();
    }
  }
}

void grid_to_particles(const Grid& grid, std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                       double dt, double flip) {
  const std::size_t stride = grid.nodes_x();
  const long n = static_cast<long>(points.size());
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (long p = 0; p < n; ++p) {
    const Stencil& s = stencils[p];
    Vec2 v = Vec2::Zero(), a = Vec2::Zero();
    for (int b = 0; b < 4; ++b) {
      const std::size_t row = s.first_node + b * stride;
      for (int i = 0; i < 4; ++i) {
        const double N = s.wx[i] * s.wy[b];
        v += N * grid.velocity[row + i];
        a += N * grid.acceleration[row + i];
      }
    }
    MaterialPoint& mp = points[p];
    mp.position += dt * (v + 0.5 * dt * a);
    mp.velocity = flip * (mp.velocity + dt * a) + (1 - flip) * (v + dt * a);
  }
}

void remap_velocities(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                      ScatterBuffers& buffers) {
  std::fill(grid.sums.momentum.begin(), grid.sums.momentum.end(), Vec2::Zero());
  const std::size_t stride = grid.nodes_x();
  scatter_points<true>(grid, points, stencils, buffers, [stride](const MaterialPoint& mp, const Stencil& s, NodeSums& acc) {
    const Vec2 momentum = mp.mass * mp.velocity;
    for (int b = 0; b < 4; ++b) {
      const std::size_t row = s.first_node + b * stride;
      for (int a = 0; a < 4; ++a) acc.momentum[row + a] += (s.wx[a] * s.wy[b]) * momentum;
    }
  });
  const long nodes = static_cast<long>(grid.node_count());
#pragma omp parallel for schedule(static) if (nodes >= kMinParallelItems)
  for (long k = 0; k < nodes; ++k) {
    const double m = grid.sums.mass[k];
    grid.velocity[k] = m > 0 ? Vec2(grid.sums.momentum[k] / m) : Vec2::Zero();
  }
}

Mat2 velocity_gradient(const Grid& grid, const Stencil& s) {
  const std::size_t stride = grid.nodes_x();
  // Four scalar sums: Eigen's outer-product update of a Mat2 here cost 5× the G2P gather.
  double l00 = 0, l01 = 0, l10 = 0, l11 = 0;
  for (int b = 0; b < 4; ++b) {
    const std::size_t row = s.first_node + b * stride;
    for (int a = 0; a < 4; ++a) {
      const double dx = s.gx[a] * s.wy[b], dy = s.wx[a] * s.gy[b];
      const Vec2& v = grid.velocity[row + a];
      l00 += v.x() * dx, l01 += v.x() * dy;
      l10 += v.y() * dx, l11 += v.y() * dy;
    }
  }
  Mat2 L;
  L << l00, l01, l10, l11;
  return L;
}

}  // namespace grainbank::mpm
