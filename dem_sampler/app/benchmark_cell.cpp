#include "dem_sampler/app/benchmark_cell.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "dem_sampler/cell/preparation.hpp"

namespace grainbank::app {
namespace {

using dem::Mat3;

constexpr double kStiffness = 10000;       // LAMMPS k_n
constexpr double kDensity = 1.9099;        // m = 1 for d = 1
constexpr double kTimeStep = 0.001;
constexpr double kTargetSolidFraction = 0.609;  // 725 / 10.6³ in the LAMMPS script

dem::Material benchmark_material(bool bonds) {
  dem::Material m;
  m.density = kDensity;
  m.contact.k_n = kStiffness;
  m.contact.k_t = 2.0 / 7.0 * kStiffness;  // LAMMPS default k_t
  // LAMMPS γ_n = 50 (per unit effective mass): ζ = γ_n sqrt(m_ij / k_n) / 2 with m_ij = 1/2.
  const double zeta = 50 * std::sqrt(0.5 / kStiffness) / 2;
  m.contact.restitution = std::exp(-std::numbers::pi * zeta / std::sqrt(1 - zeta * zeta));
  m.contact.friction = 0.5;
  m.contact.contact_weight = bonds ? 0.5 : 1.0;
  if (bonds) {
    m.effects.bonds = true;
    m.bond.tensile_strength = 1e9;  // unbreakable: measures the cost of carrying bonds
    m.bond.shear_strength = 1e9;
    m.bond.bonding_distance = 0.05;
  }
  return m;
}

}  // namespace

BenchmarkResult run_benchmark(const BenchmarkOptions& o) {
  const dem::Material material = benchmark_material(o.bonds);
  dem::PreparationSpec spec;
  spec.spheres = o.spheres;
  spec.min_diameter = 0.8;
  spec.max_diameter = 1.2;
  spec.pressure = 1;  // only used by the spec check; this cell is compressed to a solid fraction
  spec.seed = o.seed;
  spec.skin = 0.2;    // LAMMPS "neighbor 0.2 bin"
  dem::DemCell cell = dem::random_gas(material, spec);

  // Isotropic compression to the target solid fraction, then relaxation (as the LAMMPS script).
  cell.set_local_damping(0.3);
  const double squeeze = -2.0;  // strain rate while compressing
  while (cell.measures().solid_fraction < kTargetSolidFraction)
    cell.step_with_velocity_gradient(squeeze * Mat3::Identity(), kTimeStep);
  for (int k = 0; k < 5000; ++k) cell.step_with_velocity_gradient(Mat3::Zero(), kTimeStep);
  cell.set_local_damping(0);
  BenchmarkResult r;
  if (o.bonds) r.bonds = static_cast<std::size_t>(cell.create_bonds(material.bond.bonding_distance));

  // Simple shear at constant volume, driven the way the MPM drives a cell: increments of 100 steps
  // with the stress regressed over the last fifth of each.
  dem::Substepping q;
  q.q_t = 0.05;  // δt_crit(Q_t) > 0.001 so that Q_n sets exactly 100 steps of 0.001
  q.q_n = 100;
  q.q_sigma = 0.2;
  const double increment_duration = q.q_n * kTimeStep;
  Mat3 increment = Mat3::Identity();
  increment(0, 1) = o.shear_rate * increment_duration;
  const long increments = std::max(1L, o.shear_steps / q.q_n);
  const long builds_before = cell.list_builds();
  const auto start = std::chrono::steady_clock::now();
  for (long k = 0; k < increments; ++k) cell.advance(increment, increment_duration, q);
  r.shear_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const double n = static_cast<double>(cell.size());
  r.particle_steps_per_second = n * static_cast<double>(increments * q.q_n) / r.shear_seconds;
  r.contacts_per_sphere = static_cast<double>(cell.contact_count()) / n;
  r.neighbours_per_sphere = static_cast<double>(cell.pair_count()) / n;
  r.bytes_per_sphere = static_cast<double>(cell.memory_bytes()) / n;
  const dem::CellMeasures m = cell.measures();
  r.solid_fraction = m.solid_fraction;
  r.pressure = dem::pressure_of(m.stress);
  r.list_builds = cell.list_builds() - builds_before;
  r.flips = cell.flips();
  return r;
}

}  // namespace grainbank::app
