// Shared helpers of the DEM physics tests: a small-cell material, hand-built states and a cheap
// prepared cell. Nothing here copies numbers from the engine: expected values are derived in the tests.
#pragma once
#include <algorithm>
#include <cmath>
#include <string>
#include <numbers>
#include <vector>

#include "dem_sampler/cell/cell_state.hpp"
#include "dem_sampler/cell/dem_cell.hpp"
#include "dem_sampler/cell/material.hpp"
#include "dem_sampler/cell/preparation.hpp"

namespace grainbank::dem::test {

// The "reasonable material for small cells": 0.8-1.2 mm grains, k_n = 1e5 N/m, k_t = 5e4 N/m.
inline Material small_material(bool bonds = false) {
  Material m;
  m.density = 2650;
  m.contact.k_n = 1e5;
  m.contact.k_t = 5e4;
  m.contact.restitution = 0.5;
  m.contact.friction = 0.5;
  m.contact.contact_weight = bonds ? 0.5 : 1.0;
  if (bonds) {
    m.effects.bonds = true;
    m.bond.tensile_strength = 0.5;
    m.bond.shear_strength = 0.25;
    m.bond.exponent = 2;
    m.bond.bonding_distance = 0.05;
  }
  return m;
}

inline double sphere_mass(const Material& m, double r) { return m.density * 4.0 / 3.0 * std::numbers::pi * r * r * r; }

// A fresh state (no Verlet list yet): the DemCell constructor builds the list and the forces.
inline CellState fresh_state(const Mat3& h, const std::vector<Vec3>& x, const std::vector<double>& r,
                             const std::vector<Vec3>& v = {}, const std::vector<Vec3>& w = {}) {
  CellState st;
  st.h = h;
  st.h_reference = h;
  st.radius = r;
  const Mat3 hi = h.inverse();
  for (const Vec3& xi : x) st.reduced_position.push_back(hi * xi);
  st.velocity = v.empty() ? std::vector<Vec3>(r.size(), Vec3::Zero()) : v;
  st.angular_velocity = w.empty() ? std::vector<Vec3>(r.size(), Vec3::Zero()) : w;
  return st;
}

// Preparation spec of a small cell that prepares in about a second.
inline PreparationSpec small_spec(std::size_t spheres, std::uint64_t seed) {
  PreparationSpec s;
  s.spheres = spheres;
  s.min_diameter = 0.8e-3;
  s.max_diameter = 1.2e-3;
  s.pressure = 1e4;
  s.compression_friction = 0.1;
  s.pressure_tolerance = 0.02;
  s.unbalanced_force_tolerance = 0.02;
  s.inertial_number = 1e-2;
  s.seed = seed;
  return s;
}

inline double rel_diff(const Mat3& a, const Mat3& b) { return (a - b).norm() / std::max(a.norm(), b.norm()); }

// Simple shear x += γ y.
inline Mat3 simple_shear(double gamma) {
  Mat3 f = Mat3::Identity();
  f(0, 1) = gamma;
  return f;
}

inline Mat3 rotation_z(double angle) { return Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix(); }

// Exact equality of two cell states, array by array (bit-identical continuation).
inline bool states_identical(const CellState& a, const CellState& b, std::string* why = nullptr) {
  auto fail = [&](const char* w) {
    if (why) *why = w;
    return false;
  };
  if (a.h != b.h) return fail("h");
  if (a.h_reference != b.h_reference) return fail("h_reference");
  if (a.time != b.time) return fail("time");
  if (a.radius != b.radius) return fail("radius");
  if (a.reduced_position != b.reduced_position) return fail("reduced_position");
  if (a.velocity != b.velocity) return fail("velocity");
  if (a.angular_velocity != b.angular_velocity) return fail("angular_velocity");
  if (a.force != b.force) return fail("force");
  if (a.torque != b.torque) return fail("torque");
  if (a.pairs.size() != b.pairs.size()) return fail("pairs.size");
  for (std::size_t k = 0; k < a.pairs.size(); ++k) {
    const Pair &p = a.pairs[k], &q = b.pairs[k];
    if (p.i != q.i || p.j != q.j || p.image != q.image || p.damping != q.damping || p.ft != q.ft) return fail("pairs");
  }
  if (a.bonds.size() != b.bonds.size()) return fail("bonds.size");
  for (std::size_t k = 0; k < a.bonds.size(); ++k) {
    const Bond &p = a.bonds[k], &q = b.bonds[k];
    if (p.shear_displacement != q.shear_displacement || p.rest_gap != q.rest_gap || p.integrity != q.integrity)
      return fail("bonds");
  }
  if (a.rolling_moment != b.rolling_moment) return fail("rolling_moment");
  if (a.initial_bond_count != b.initial_bond_count) return fail("initial_bond_count");
  if (a.h_at_list_build != b.h_at_list_build) return fail("h_at_list_build");
  if (a.reduced_position_at_list_build != b.reduced_position_at_list_build) return fail("reduced_position_at_list_build");
  if (a.last_stress != b.last_stress) return fail("last_stress");
  if (a.last_active_pairs != b.last_active_pairs) return fail("last_active_pairs");
  if (a.last_pair_force_sum != b.last_pair_force_sum) return fail("last_pair_force_sum");
  return true;
}

}  // namespace grainbank::dem::test
