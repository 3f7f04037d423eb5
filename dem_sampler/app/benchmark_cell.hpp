// The standard benchmark cell of shared/peers/README.md, built with this engine: 1331 frictional
// spheres, diameters uniform in [0.8, 1.2] d, solid fraction 0.61, linear spring-dashpot contacts with
// μ = 0.5 (LAMMPS gran/hooke/history parameters in reduced units), sheared at constant volume.
#pragma once
#include <cstddef>
#include <functional>
#include <string>

#include "dem_sampler/cell/dem_cell.hpp"

namespace grainbank::app {

struct BenchmarkOptions {
  std::size_t spheres = 1331;
  bool bonds = false;
  long shear_steps = 30000;
  double shear_rate = 0.01;   // γ̇ in reduced units, as the LAMMPS script
  std::uint64_t seed = 12345;
};

struct BenchmarkResult {
  double particle_steps_per_second = 0;
  double shear_seconds = 0;
  double contacts_per_sphere = 0;    // pairs in contact per sphere (half list, like LAMMPS neighbours)
  double neighbours_per_sphere = 0;  // Verlet pairs per sphere
  double bytes_per_sphere = 0;
  double solid_fraction = 0;
  double pressure = 0;
  long list_builds = 0, flips = 0;
  std::size_t bonds = 0;
};

BenchmarkResult run_benchmark(const BenchmarkOptions& options);

}  // namespace grainbank::app
