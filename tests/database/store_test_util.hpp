// Shared helpers of the store tests: a temporary library directory, a small material with every
// effect on (so every CellState array is exercised), a small deformed cell, and exact comparisons.
#pragma once
#include <bit>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "dem_sampler/cell/dem_cell.hpp"
#include "dem_sampler/cell/preparation.hpp"
#include "database/store/library.hpp"
#include "common/temporary_directory.hpp"

namespace grainbank::db::test {

using TempDir = grainbank::TemporaryDirectory;

// 0.8-1.2 mm grains, modest stiffness, bonds + rolling + kinetic stress on.
inline dem::Material small_material() {
  dem::Material m;
  m.density = 2650;
  m.contact.k_n = 1e5;
  m.contact.k_t = 5e4;
  m.contact.restitution = 0.5;
  m.contact.friction = 0.5;
  m.contact.contact_weight = 0.5;
  m.bond.tensile_strength = 0.5;
  m.bond.shear_strength = 0.25;
  m.bond.exponent = 2;
  m.bond.bonding_distance = 0.05;
  m.rolling.stiffness = 1e-3;
  m.rolling.friction = 0.1;
  m.effects = dem::Effects{true, true, true};
  return m;
}

inline dem::PreparationSpec small_spec() {
  dem::PreparationSpec s;
  s.spheres = 40;
  s.min_diameter = 0.8e-3;
  s.max_diameter = 1.2e-3;
  s.pressure = 1e4;
  s.initial_solid_fraction = 0.3;
  s.seed = 7;
  return s;
}

inline dem::Substepping substepping() {
  dem::Substepping q;
  q.q_t = 0.1;
  q.q_n = 20;
  return q;
}

inline double increment_duration(const dem::DemCell& cell) { return 20 * cell.time_step(0.1); }

// A random gas compressed until it is dense and bonded, then sheared a little: contacts, bonds,
// rolling moments and tangential history are all non-trivial.
inline dem::DemCell small_cell() {
  dem::DemCell cell = dem::random_gas(small_material(), small_spec());
  const dem::Mat3 squeeze = dem::Vec3(0.97, 0.97, 0.97).asDiagonal();
  for (int k = 0; k < 20 && cell.measures().solid_fraction < 0.6; ++k)
    cell.advance(squeeze, increment_duration(cell), substepping());
  cell.create_bonds(small_material().bond.bonding_distance);
  return cell;
}

inline dem::Mat3 shear_increment() {
  dem::Mat3 F = dem::Mat3::Identity();
  F(0, 1) = 2e-3;
  F(1, 1) = 0.999;
  return F;
}

inline bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
template <class M>
bool same_bits(const M& a, const M& b) {
  for (int k = 0; k < a.size(); ++k)
    if (!same_bits(a.data()[k], b.data()[k])) return false;
  return true;
}
template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (!same_bits(a[k], b[k])) return false;
  return true;
}

// Empty when the states are bit-identical, else the first differing field.
inline std::string first_difference(const dem::CellState& a, const dem::CellState& b) {
  if (!same_bits(a.h, b.h)) return "h";
  if (!same_bits(a.h_reference, b.h_reference)) return "h_reference";
  if (!same_bits(a.time, b.time)) return "time";
  if (!same_bits(a.radius, b.radius)) return "radius";
  if (!same_bits(a.reduced_position, b.reduced_position)) return "reduced_position";
  if (!same_bits(a.velocity, b.velocity)) return "velocity";
  if (!same_bits(a.angular_velocity, b.angular_velocity)) return "angular_velocity";
  if (!same_bits(a.force, b.force)) return "force";
  if (!same_bits(a.torque, b.torque)) return "torque";
  if (a.pairs.size() != b.pairs.size()) return "pairs.size";
  for (std::size_t k = 0; k < a.pairs.size(); ++k) {
    const dem::Pair &p = a.pairs[k], &q = b.pairs[k];
    if (p.i != q.i || p.j != q.j || p.image != q.image || !same_bits(p.damping, q.damping) || !same_bits(p.ft, q.ft))
      return "pairs[" + std::to_string(k) + "]";
  }
  if (a.bonds.size() != b.bonds.size()) return "bonds.size";
  for (std::size_t k = 0; k < a.bonds.size(); ++k) {
    const dem::Bond &p = a.bonds[k], &q = b.bonds[k];
    if (!same_bits(p.shear_displacement, q.shear_displacement) || !same_bits(p.rest_gap, q.rest_gap) ||
        p.integrity != q.integrity)
      return "bonds[" + std::to_string(k) + "]";
  }
  if (!same_bits(a.rolling_moment, b.rolling_moment)) return "rolling_moment";
  if (a.initial_bond_count != b.initial_bond_count) return "initial_bond_count";
  if (!same_bits(a.h_at_list_build, b.h_at_list_build)) return "h_at_list_build";
  if (!same_bits(a.reduced_position_at_list_build, b.reduced_position_at_list_build))
    return "reduced_position_at_list_build";
  if (!same_bits(a.last_stress, b.last_stress)) return "last_stress";
  if (a.last_active_pairs != b.last_active_pairs) return "last_active_pairs";
  if (!same_bits(a.last_pair_force_sum, b.last_pair_force_sum)) return "last_pair_force_sum";
  return "";
}

// A record with distinct, non-round values in every column.
inline Record sample_record(int k) {
  Record r;
  r.time = 1e-3 * k + 1.0 / 3.0;
  for (int i = 0; i < 9; ++i) {
    r.F.data()[i] = (i % 4 == 0 ? 1.0 : 0.0) + 1e-4 * (k + i) / 7.0;
    r.L.data()[i] = 0.1 * (i - 4) + k / 11.0;
  }
  for (int i = 0; i < 6; ++i) r.stress[i] = -1e4 * (i + 1) - k / 3.0;
  r.damage = k / 100.0;
  r.solid_fraction = 0.6 + k / 1e4;
  r.coordination = 4 + k / 17.0;
  r.bonds = 100 - k;
  r.kinetic_energy = 1e-9 * (k + 1) / 3.0;
  for (std::size_t i = 0; i < kKeySize; ++i) r.key[i] = (k + 1.0) * (i + 1.0) / 13.0;
  return r;
}

}  // namespace grainbank::db::test
