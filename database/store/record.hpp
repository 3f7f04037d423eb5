// One record of a path (DESIGN.md, "Strain-rate paths and the library"): the cell's response after a
// recording interval, and its state key. Stored as one row of 37 doubles in the path's records table;
// the column names and units are written next to the data as HDF5 attributes.
#pragma once
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "dem_sampler/cell/types.hpp"

namespace grainbank::db {

// Symmetric stress in the order xx yy zz xy xz yz, tension-positive [Pa].
using Stress6 = std::array<double, 6>;
// State key: Hencky strain (xx, yy, xy) and rotated strain rate (xx, yy, xy) in the material frame,
// then damage, each divided by its scale (see the key definition in the catalogue meta).
inline constexpr std::size_t kKeySize = 7;
using StateKey = std::array<double, kKeySize>;

struct Record {
  double time = 0;                  // cell time [s]
  dem::Mat3 F = dem::Mat3::Identity();  // deformation gradient h h_0⁻¹
  dem::Mat3 L = dem::Mat3::Zero();  // imposed velocity gradient [1/s]
  Stress6 stress{};                 // tension-positive [Pa]
  double damage = 0;                // D = 1 - N_b / N_b(0)
  double solid_fraction = 0;        // φ
  double coordination = 0;          // Z
  std::int64_t bonds = 0;           // N_b (stored as a double: exact below 2^53)
  double kinetic_energy = 0;        // of the fluctuations [J]
  StateKey key{};
  bool operator==(const Record&) const = default;
};

// Symmetric part of a 3×3 stress, in Stress6 order.
Stress6 to_stress6(const dem::Mat3& stress);
dem::Mat3 from_stress6(const Stress6& stress);

// Column names ("t", "F_xx", ..., "sigma_xy", ..., "key_damage") and units, row-major for F and L.
const std::vector<std::string>& record_column_names();
const std::vector<std::string>& record_column_units();
inline constexpr std::size_t kRecordColumns = 37;

void append_record_row(const Record& record, std::vector<double>& rows);
Record record_from_row(const double* row);

}  // namespace grainbank::db
