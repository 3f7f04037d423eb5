// Sampling states, not paths (issue 13, item 5): paths that bring the template to states along
// compression, shear, extension (bond-breaking) and oedometric compression (the K0 state of any
// deposit under its own weight) and then probe each state in a star of loading
// directions, so that a library covers the material's stress space, unloading included, and the
// state-keyed surrogate (database/surrogate) finds neighbours in every direction a material point
// may load a state.
//
// One path per (base, depth, probe rate):
// 1. the base segment: in-plane isotropic compression D = −r I₂/√2, simple shear L = √2 r [[0,1],[0,0]]
//    (|D| = r), in-plane isotropic extension D = +r I₂/√2, oedometric compression along y
//    D_yy = −r, or simple shear under the held mean pressure base_pressure (mixed control,
//    path_input.hpp: the steady flow of a point under a free surface, which reaches its critical
//    state, where simple shear at constant volume builds pressure without end), at |D| = base_rate
//    for depth/base_rate;
// 2. for each probe direction, `probe_strain` of loading at |D| = rate, then the same strain back
//    (−D, the unloading response), in the order ψ outer, β inner.
// A probe direction is D = a I₂ + b R(θ) diag(1, −1) R(θ)ᵀ with plane strain (D_zz = 0), scaled to
// |D| = rate, with
//    ψ = atan(tr D / |dev D|) (3-D norms, as the surrogate's key): tan ψ = 2a / √(2a²/3 + 2b²), so
//      plane strain reaches |ψ| ≤ atan √6 ≈ 67.79° (in-plane isotropic loading) and no further;
//    β the angle from the base state's in-plane principal stress axis (its least compressive one) to
//      D's largest stretching axis θ. For the shear base that axis is taken at +45°, the stretching
//      axis of simple shear (coaxial flow at the critical state: an approximation before it), for
//      the oedometric base x (compressed along y, it is least compressed along x); the
//      compression and extension bases leave the stress isotropic in the plane, where β is undefined
//      (the surrogate's key sets β = 0): their probes use β = 0 only, so no probe repeats another.
// Same spec, same paths, on every machine.
#pragma once
#include <vector>

#include "dem_sampler/sampler/path_plan.hpp"

namespace grainbank::sampler {

enum class ProbeBase { compression, shear, extension, oedometric, held_shear };

struct ProbeSpec {
  std::vector<ProbeBase> bases;
  std::vector<double> depths;     // strain along the base, Σ |D| dt (> 0)
  double base_rate = 0;           // |D| of the base [1/s]
  double base_pressure = 0;       // the held_shear base's mean pressure [Pa], > 0 if it is used
  std::vector<double> psi;        // [rad], |ψ| ≤ kMaxPlaneStrainPsi
  std::vector<double> beta;       // [rad]
  std::vector<double> rates;      // |D| of the probes [1/s]
  double probe_strain = 0;        // of each probe and of its return
  double record_interval = 0;     // [s]
  long snapshot_interval = 0;
  dem::Substepping substepping;
};

// atan √6: the dilatancy angle of in-plane isotropic loading under plane strain.
extern const double kMaxPlaneStrainPsi;

// The in-plane D (3×3, zeros outside the plane) of a probe direction, |D| = rate.
dem::Mat3 probe_direction(double psi, double axis_angle, double rate);

// Throws std::invalid_argument naming the first bad field.
std::vector<PathPlan> probe_paths(const ProbeSpec& spec);

// "compression" | "shear" | "extension" | "oedometric" | "held_shear"
ProbeBase probe_base_from(const std::string& name);

}  // namespace grainbank::sampler
