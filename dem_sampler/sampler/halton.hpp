// The Halton low-discrepancy sequence: point i in dimension d is the radical inverse of i in the d-th
// prime base. Deterministic, no state, so any path of a generator can be recomputed on its own.
#pragma once
#include <array>
#include <cstdint>
#include <stdexcept>

namespace grainbank::sampler {

inline constexpr std::array<std::uint64_t, 24> kHaltonBases = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29, 31, 37,
                                                               41, 43, 47, 53, 59, 61, 67, 71, 73, 79, 83, 89};

// In [0, 1); index 0 is the origin in every dimension (generators start at 1).
inline double halton(std::uint64_t index, std::size_t dimension) {
  if (dimension >= kHaltonBases.size()) throw std::out_of_range("halton: dimension beyond the tabulated primes");
  const std::uint64_t base = kHaltonBases[dimension];
  double value = 0, scale = 1.0 / static_cast<double>(base);
  for (; index > 0; index /= base, scale /= static_cast<double>(base))
    value += static_cast<double>(index % base) * scale;
  return value;
}

}  // namespace grainbank::sampler
