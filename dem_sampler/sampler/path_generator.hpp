// Generated strain-rate paths (DESIGN.md, "Strain-rate paths and the library"): quasi-random
// directions in in-plane strain-rate space, log-uniform rate magnitudes, and direction changes along
// each path so that the library samples loading history (reversals, rotations of principal axes).
//
// In-plane L = D + W. D is spanned by the Frobenius-orthonormal volumetric I/√2, deviatoric
// diag(1,-1)/√2 and shear [[0,1],[1,0]]/√2 parts; a direction is a point of the unit sphere of these
// three (volumetric part scaled by `volumetric`, then renormalised). W = spin content × rate ×
// [[0,1],[-1,0]]/√2. Path i uses Halton point start + i + 1: dimensions 0-1 direction, 2 rate,
// 3 spin, then two per direction change. Same spec, same paths, on every machine.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "dem_sampler/sampler/path_plan.hpp"

namespace grainbank::sampler {

enum class DirectionChange {
  reversal,  // L -> -L
  rotation,  // principal axes of D turned by an angle in [9°, 81°], W kept
  fresh,     // a new direction from the sequence, same rate
};

struct GeneratorSpec {
  long count = 0;
  std::uint64_t start = 0;               // offset into the sequence: disjoint sets use disjoint ranges
  double min_rate = 0, max_rate = 0;     // ‖sym L‖ [1/s], log-uniform in [min, max]
  double strain = 0;                     // per path: Σ ‖sym L‖ duration, split evenly over segments
  int segments = 1;                      // 1 + number of direction changes, at most kMaxSegments
  std::vector<DirectionChange> changes{DirectionChange::reversal, DirectionChange::rotation};  // cycled
  double volumetric = 1;                 // weight of the volumetric direction component, in [0, 1]
  double spin = 0;                       // |W| at most spin × ‖D‖, in [0, 1]
  double record_interval = 0;            // [s]
  long snapshot_interval = 0;
  dem::Substepping substepping;
};

inline constexpr int kMaxSegments = 10;

std::vector<PathPlan> generate_paths(const GeneratorSpec& spec);

DirectionChange direction_change_from(const std::string& name);  // "reversal" | "rotation" | "fresh"

}  // namespace grainbank::sampler
