// What the state-keyed surrogate knows of a material point or a DEM cell (issue 13): the state the
// point carries and integrates itself, and the constants that make that state dimensionless.
// Stress is tension-positive [Pa]; p = −tr σ / 3 is positive in compression.
#pragma once
#include "dem_sampler/cell/types.hpp"

namespace grainbank::surrogate {

struct PointState {
  dem::Mat3 stress = dem::Mat3::Zero();  // Cauchy stress σ, symmetric, tension-positive [Pa]
  double solid_fraction = 0;             // φ
  double coordination = 0;               // Z
  double damage = 0;                     // D = 1 − N_b / N_b(0)
};

// Constants of one dataset (one library): they fix the meaning of the features and of the
// normalized answers, so every sample of an index and every query use the same ones.
struct FeatureConstants {
  double p_ref = 0;     // reference pressure of ln(p/p_ref) [Pa] > 0 (a library: its templates' p)
  double p_floor = 0;   // pressures below it (tension, loose cells) count as p_floor [Pa] > 0
  double diameter = 0;  // mean grain diameter d of the inertial number [m] > 0
  double density = 0;   // grain density ρ [kg/m³] > 0
};

// Throws std::invalid_argument naming the first constant that is not a positive finite number.
void check(const FeatureConstants& constants);

// The pressure every normalization uses: max(p, p_floor). Never ≤ 0, so no feature and no answer is
// ever NaN or infinite, whatever the state (a tensile cell included).
double effective_pressure(const dem::Mat3& stress, const FeatureConstants& constants);

}  // namespace grainbank::surrogate
