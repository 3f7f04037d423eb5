#include "mpm_solver/core/transfers.hpp"

#include "mpm_solver/core/parallel.hpp"

#include <omp.h>

#include <cmath>

namespace grainbank::mpm {

namespace {

// Runs scatter(p, sums) for every point index p < n in parallel, each thread into its own buffer,
// then adds the buffers into grid.sums (momentum only when only momentum was scattered).
template <bool MomentumOnly, class Scatter>
void scatter_points(Grid& grid, long n, ScatterBuffers& buffers, Scatter&& scatter) {
  const int threads = static_cast<int>(buffers.per_thread.size());
  if (threads == 1 || n < kMinParallelItems) {
    for (long p = 0; p < n; ++p) scatter(p, grid.sums);
    return;
  }
#pragma omp parallel num_threads(threads)
  {
    NodeSums& mine = buffers.per_thread[omp_get_thread_num()];
#pragma omp for schedule(static)
    for (long p = 0; p < n; ++p) scatter(p, mine);
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

// A point's momentum field m_p (v_p + C_p (x − x_p)), C_p = B_p D_p⁻¹, evaluated at the offsets
// x_i − x_p of its nodes.
struct AffineMomentum {
  Vec2 momentum;
  Mat2 gradient;
  AffineMomentum(const MaterialPoint& mp, double h)
      : momentum(mp.mass * mp.velocity), gradient(mp.mass / affine_inertia(h) * mp.affine_velocity) {}
  Vec2 at(const Stencil& s, int a, int b) const { return momentum + gradient * Vec2(s.dx[a], s.dy[b]); }
};

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
  const double h = grid.cell_size();
  const long n = static_cast<long>(points.size());
  scatter_points<false>(grid, n, buffers, [&points, &stencils, stride, h](long p, NodeSums& acc) {
    const MaterialPoint& mp = points[p];
    const Stencil& s = stencils[p];
    const AffineMomentum momentum(mp, h);
    const Mat2 vs = mp.volume * mp.stress.in_plane;
    for (int b = 0; b < 4; ++b) {
      const std::size_t row = s.first_node + b * stride;
      for (int a = 0; a < 4; ++a) {
        const double N = s.wx[a] * s.wy[b];
        const Vec2 grad(s.gx[a] * s.wy[b], s.wx[a] * s.gy[b]);
        acc.mass[row + a] += N * mp.mass;
        acc.momentum[row + a] += N * momentum.at(s, a, b);
        acc.force[row + a] -= vs * grad;
      }
    }
  });
}

ContactSpread contact_spread(const Grid& grid, const Vec2& x, const Vec2& normal, double spacing) {
  const double inv_h = 1 / grid.cell_size();
  const Stencil s = stencil_at(grid, x);
  ContactSpread spread{s.first_node, {}};
  double flux[4][4] = {};  // Σ_k ∇N_i · n h over the column, node (a, b) at flux[b][a]
  const int column = static_cast<int>(std::ceil(4 / (spacing * inv_h)));
  for (int k = 0; k <= column; ++k) {
    // The column's k-th point sits at k d n from x, i.e. at -dx[a] + k d n_x from node column a.
    SplineValue nx[4], ny[4];
    for (int a = 0; a < 4; ++a) nx[a] = cubic_bspline((k * spacing * normal.x() - s.dx[a]) * inv_h);
    for (int b = 0; b < 4; ++b) ny[b] = cubic_bspline((k * spacing * normal.y() - s.dy[b]) * inv_h);
    for (int b = 0; b < 4; ++b)
      for (int a = 0; a < 4; ++a)
        flux[b][a] += nx[a].slope * ny[b].value * normal.x() + nx[a].value * ny[b].slope * normal.y();
  }
  double total = 0;
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) total += flux[b][a];
  // ω_i = -d Σ_k ∇N_i · n; scaled to sum to one, the factor -d/h cancels.
  for (int b = 0; b < 4; ++b)
    for (int a = 0; a < 4; ++a) spread.weight[b][a] = flux[b][a] / total;
  return spread;
}

Vec2 material_velocity(const Grid& grid, const ContactSpread& spread) {
  const std::size_t stride = grid.nodes_x();
  Vec2 v = Vec2::Zero();
  for (int b = 0; b < 4; ++b) {
    const std::size_t row = spread.first_node + b * stride;
    for (int a = 0; a < 4; ++a) {
      const double m = grid.sums.mass[row + a];
      if (m > 0) v += (spread.weight[b][a] / m) * grid.sums.momentum[row + a];
    }
  }
  return v;
}

void add_contact_force(Grid& grid, const ContactSpread& spread, const Vec2& f) {
  const std::size_t stride = grid.nodes_x();
  for (int b = 0; b < 4; ++b) {
    const std::size_t row = spread.first_node + b * stride;
    for (int a = 0; a < 4; ++a) grid.sums.force[row + a] += spread.weight[b][a] * f;
  }
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
                       double dt, const VelocityTransfer& transfer, std::vector<Vec2>& fluctuations) {
  const std::size_t stride = grid.nodes_x();
  const bool affine = transfer.affine(), split = transfer.splits_fluctuations();
  const double kept = transfer.kept_share(dt);
  const long n = static_cast<long>(points.size());
  if (split) fluctuations.resize(points.size());
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (long p = 0; p < n; ++p) {
    const Stencil& s = stencils[p];
    Vec2 v = Vec2::Zero(), a = Vec2::Zero();
    double b00 = 0, b01 = 0, b10 = 0, b11 = 0;  // B_p as scalars (see velocity_gradient)
    for (int b = 0; b < 4; ++b) {
      const std::size_t row = s.first_node + b * stride;
      for (int i = 0; i < 4; ++i) {
        const double N = s.wx[i] * s.wy[b];
        const Vec2 v_new = grid.velocity[row + i] + dt * grid.acceleration[row + i];
        const Vec2 Nv = N * v_new;
        v += Nv;
        a += N * grid.acceleration[row + i];
        b00 += Nv.x() * s.dx[i], b01 += Nv.x() * s.dy[b];
        b10 += Nv.y() * s.dx[i], b11 += Nv.y() * s.dy[b];
      }
    }
    MaterialPoint& mp = points[p];
    mp.position += dt * v;
    const Vec2 fluctuation = mp.velocity + dt * a - v;
    if (split) {
      fluctuations[p] = fluctuation;
      mp.velocity = v;
    } else {
      mp.velocity = v + kept * fluctuation;
    }
    if (affine) mp.affine_velocity << b00, b01, b10, b11;
  }
}

void blend_in_fluctuations(Grid& grid, std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                           const std::vector<Vec2>& fluctuations, double dt, const VelocityTransfer& transfer,
                           ScatterBuffers& buffers) {
  std::fill(grid.sums.momentum.begin(), grid.sums.momentum.end(), Vec2::Zero());
  const std::size_t stride = grid.nodes_x();
  const long n = static_cast<long>(points.size());
  scatter_points<true>(grid, n, buffers, [&](long p, NodeSums& acc) {
    const Stencil& s = stencils[p];
    const Vec2 momentum = points[p].mass * fluctuations[p];
    for (int b = 0; b < 4; ++b) {
      const std::size_t row = s.first_node + b * stride;
      for (int a = 0; a < 4; ++a) acc.momentum[row + a] += (s.wx[a] * s.wy[b]) * momentum;
    }
  });
  // The nodes' fluctuation velocities, in place of their momenta: one division per node, not per
  // point and node.
  const long nodes = static_cast<long>(grid.node_count());
#pragma omp parallel for schedule(static) if (nodes >= kMinParallelItems)
  for (long k = 0; k < nodes; ++k) {
    const double m = grid.sums.mass[k];
    grid.sums.momentum[k] = m > 0 ? Vec2(grid.sums.momentum[k] / m) : Vec2::Zero();
  }
  const double kept_carried = transfer.kept_share(dt), kept_rough = transfer.kept_rough_share(dt);
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (long p = 0; p < n; ++p) {
    const Stencil& s = stencils[p];
    Vec2 carried = Vec2::Zero();
    for (int b = 0; b < 4; ++b) {
      const std::size_t row = s.first_node + b * stride;
      for (int a = 0; a < 4; ++a) carried += (s.wx[a] * s.wy[b]) * grid.sums.momentum[row + a];
    }
    points[p].velocity += kept_carried * carried + kept_rough * (fluctuations[p] - carried);
  }
}

void remap_velocities(Grid& grid, const std::vector<MaterialPoint>& points, const std::vector<Stencil>& stencils,
                      ScatterBuffers& buffers) {
  std::fill(grid.sums.momentum.begin(), grid.sums.momentum.end(), Vec2::Zero());
  const std::size_t stride = grid.nodes_x();
  const double h = grid.cell_size();
  scatter_points<true>(grid, static_cast<long>(points.size()), buffers, [&points, &stencils, stride, h](long p, NodeSums& acc) {
    const Stencil& s = stencils[p];
    const AffineMomentum momentum(points[p], h);
    for (int b = 0; b < 4; ++b) {
      const std::size_t row = s.first_node + b * stride;
      for (int a = 0; a < 4; ++a) acc.momentum[row + a] += (s.wx[a] * s.wy[b]) * momentum.at(s, a, b);
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
