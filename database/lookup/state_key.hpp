// The state key of DESIGN.md ("Nearest-state lookup"): where a cell state sits in the library's
// 7-D key space, and the frame change between a lab frame and the cell's material frame.
//
// Promise: the key depends only on the material (rotation-free) part of the kinematics. For
// F = R U (polar decomposition) and L with stretching D = sym L:
//   key = ( E_xx, E_yy, E_xy ) / strain,  ( D̂_xx, D̂_yy, D̂_xy ) / rate,  damage / damage
// with E = ½ ln(FᵀF) = ln U (Hencky strain) and D̂ = Rᵀ D R, scales from KeyScales. A superposed
// rigid rotation Q (F → Q F, D → Q D Qᵀ) leaves the key unchanged; the stress that belongs to the
// key is the material-frame stress σ̂ = Rᵀ σ R, and R σ̂ Rᵀ turns it back.
#pragma once
#include "dem_sampler/cell/types.hpp"
#include "database/store/key_definition.hpp"
#include "database/store/record.hpp"

namespace grainbank::lookup {

struct PolarDecomposition {
  dem::Mat3 R;       // rotation, det R = +1
  dem::Mat3 U;       // right stretch, symmetric positive definite
  dem::Mat3 hencky;  // ln U = ½ ln(FᵀF)
};

// Whether F has a polar decomposition here: finite, with det F > 0.
bool has_polar_decomposition(const dem::Mat3& F);

// Throws std::invalid_argument unless has_polar_decomposition(F).
PolarDecomposition polar_decomposition(const dem::Mat3& F);

db::StateKey state_key(const PolarDecomposition& polar, const dem::Mat3& L, double damage, const db::KeyScales& scales);
db::StateKey state_key(const dem::Mat3& F, const dem::Mat3& L, double damage, const db::KeyScales& scales);
// The key of a stored record, recomputed from its F, L and damage (the stored key column is not
// trusted: it may have been written with other scales).
db::StateKey state_key(const db::Record& record, const db::KeyScales& scales);

// σ̂ = Rᵀ σ R and back σ = R σ̂ Rᵀ.
dem::Mat3 to_material_frame(const dem::Mat3& stress, const dem::Mat3& R);
dem::Mat3 to_lab_frame(const dem::Mat3& material_stress, const dem::Mat3& R);

// Strain rate at which a granular flow with grain diameter d [m], pressure p [Pa] and grain density
// ρ [kg/m³] reaches the inertial number I: γ̇ = I sqrt(p/ρ) / d. A natural KeyScales::rate: rates
// differing by less than it give responses of the same (quasi-static or inertial) regime.
double inertial_rate_scale(double inertial_number, double pressure, double density, double diameter);

}  // namespace grainbank::lookup
