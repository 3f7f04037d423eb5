// How the k nearest records of a query become one answer (lookup_index.hpp): weights 1/d², so the
// answer stays within the range of its neighbours' responses. A neighbour at the query's own state
// (distance ≤ 1e-12) answers alone, exactly. The estimated error is the weighted RMS deviation of
// the neighbours' stresses from the blend (Frobenius norm, Pa).
//
// Why not a local linear fit (a weighted least-squares plane through the neighbours): tried on the
// cohesive column (README, "cache and hybrid"), it was no more accurate once kept within the
// neighbours' range, and without that limit it extrapolated the noise of the DEM stresses into
// answers many times the stored ones.
#pragma once
#include <span>

#include "database/lookup/lookup_types.hpp"

namespace grainbank::lookup {

struct Neighbour {
  const RecordResponse* response;
  double distance;  // to the query, key units; neighbours are sorted by it
};

struct Blended {
  RecordResponse response;  // the material-frame stress and measures at the query
  double estimated_error = 0;
};

// `neighbours` must not be empty.
Blended blend(std::span<const Neighbour> neighbours);

}  // namespace grainbank::lookup
