// Global measures of the flow for the time series: energy, extent and speed of the material.
#pragma once
#include <vector>

#include "mpm_solver/core/material_point.hpp"

namespace grainbank::mpm {

struct FlowMeasures {
  double kinetic_energy = 0;  // Σ ½ m |v|² [J/m]
  Vec2 momentum = Vec2::Zero();  // Σ m v [kg/s per m]
  double front = 0;           // largest x of a point [m] (runout front of a flow going +x)
  double max_height = 0;      // largest y of a point [m]
  double max_speed = 0;       // largest |v| [m/s]
};

FlowMeasures measure_flow(const std::vector<MaterialPoint>& points);

}  // namespace grainbank::mpm
