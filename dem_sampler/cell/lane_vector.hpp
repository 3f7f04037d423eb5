// A 3-vector of plain doubles, the type the vectorized loops and the interaction law compute with:
// when several pairs (or spheres) advance at once, each vector is one lane of three SIMD registers.
// Eigen stays outside those loops because its expression templates build temporaries holding
// references, which the vectorizer cannot give each lane.
#pragma once
#include <cstddef>

#include "dem_sampler/cell/types.hpp"

// The vectorized loops' attribute. A portable build (GRAINBANK_NATIVE off, on x86-64) compiles them
// twice, for AVX2 with FMA and for the baseline, and picks one when the program starts.
#if defined(GRAINBANK_KERNEL_CLONES)
#define GRAINBANK_VECTOR_LOOP [[gnu::flatten, gnu::target_clones("arch=x86-64-v3", "default")]]
#else
#define GRAINBANK_VECTOR_LOOP [[gnu::flatten]]
#endif

namespace grainbank::dem {

struct LaneVec {
  double x = 0, y = 0, z = 0;

  LaneVec() = default;
  LaneVec(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}
  explicit LaneVec(const Vec3& v) : x(v[0]), y(v[1]), z(v[2]) {}
  LaneVec& operator+=(const LaneVec& b) { return *this = {x + b.x, y + b.y, z + b.z}; }
  LaneVec& operator-=(const LaneVec& b) { return *this = {x - b.x, y - b.y, z - b.z}; }
};

inline LaneVec operator+(const LaneVec& a, const LaneVec& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline LaneVec operator-(const LaneVec& a, const LaneVec& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline LaneVec operator*(double s, const LaneVec& a) { return {s * a.x, s * a.y, s * a.z}; }
inline LaneVec operator*(const LaneVec& a, double s) { return s * a; }
inline double dot(const LaneVec& a, const LaneVec& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline double squared_norm(const LaneVec& a) { return dot(a, a); }
inline LaneVec cross(const LaneVec& a, const LaneVec& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// mask ? a : b, component by component: a select, not a branch.
inline LaneVec select(bool mask, const LaneVec& a, const LaneVec& b) {
  return {mask ? a.x : b.x, mask ? a.y : b.y, mask ? a.z : b.z};
}
// Element k of an array of 3-vectors stored x, y, z, x, y, z, … (as std::vector<Vec3> is).
inline LaneVec load_lane(const double* xyz, std::size_t k) { return {xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]}; }
inline void store_lane(double* xyz, std::size_t k, const LaneVec& v) {
  xyz[3 * k] = v.x;
  xyz[3 * k + 1] = v.y;
  xyz[3 * k + 2] = v.z;
}
inline LaneVec times(const Mat3& m, const LaneVec& a) {
  return {m(0, 0) * a.x + m(0, 1) * a.y + m(0, 2) * a.z, m(1, 0) * a.x + m(1, 1) * a.y + m(1, 2) * a.z,
          m(2, 0) * a.x + m(2, 1) * a.y + m(2, 2) * a.z};
}

}  // namespace grainbank::dem
