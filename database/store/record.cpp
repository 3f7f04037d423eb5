#include "database/store/record.hpp"

#include <cmath>

namespace grainbank::db {
namespace {

constexpr const char* kAxes = "xyz";
constexpr int kStressIndex[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {0, 2}, {1, 2}};

std::vector<std::string> make_names() {
  std::vector<std::string> names{"t"};
  for (const char* tensor : {"F", "L"})
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) names.push_back(std::string(tensor) + "_" + kAxes[i] + kAxes[j]);
  for (const auto& ij : kStressIndex) names.push_back(std::string("sigma_") + kAxes[ij[0]] + kAxes[ij[1]]);
  for (const char* name : {"damage", "solid_fraction", "coordination", "bonds", "kinetic_energy", "key_hencky_xx",
                           "key_hencky_yy", "key_hencky_xy", "key_rate_xx", "key_rate_yy", "key_rate_xy", "key_damage"})
    names.emplace_back(name);
  return names;
}

std::vector<std::string> make_units() {
  std::vector<std::string> units{"s"};
  units.insert(units.end(), 9, "1");
  units.insert(units.end(), 9, "1/s");
  units.insert(units.end(), 6, "Pa");
  for (const char* unit : {"1", "1", "1", "1", "J"}) units.emplace_back(unit);
  units.insert(units.end(), kKeySize, "1 (scaled)");
  return units;
}

}  // namespace

Stress6 to_stress6(const dem::Mat3& stress) {
  Stress6 out;
  for (int k = 0; k < 6; ++k) {
    const auto [i, j] = kStressIndex[k];
    out[k] = i == j ? stress(i, i) : 0.5 * (stress(i, j) + stress(j, i));
  }
  return out;
}

dem::Mat3 from_stress6(const Stress6& stress) {
  dem::Mat3 out;
  for (int k = 0; k < 6; ++k) {
    const auto [i, j] = kStressIndex[k];
    out(i, j) = out(j, i) = stress[k];
  }
  return out;
}

const std::vector<std::string>& record_column_names() {
  static const std::vector<std::string> names = make_names();
  return names;
}

const std::vector<std::string>& record_column_units() {
  static const std::vector<std::string> units = make_units();
  return units;
}

void append_record_row(const Record& r, std::vector<double>& rows) {
  rows.push_back(r.time);
  for (const dem::Mat3* m : {&r.F, &r.L})
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) rows.push_back((*m)(i, j));
  rows.insert(rows.end(), r.stress.begin(), r.stress.end());
  for (double v : {r.damage, r.solid_fraction, r.coordination, static_cast<double>(r.bonds), r.kinetic_energy})
    rows.push_back(v);
  rows.insert(rows.end(), r.key.begin(), r.key.end());
}

Record record_from_row(const double* row) {
  Record r;
  r.time = *row++;
  for (dem::Mat3* m : {&r.F, &r.L})
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) (*m)(i, j) = *row++;
  for (double& s : r.stress) s = *row++;
  r.damage = *row++;
  r.solid_fraction = *row++;
  r.coordination = *row++;
  r.bonds = std::llround(*row++);
  r.kinetic_energy = *row++;
  for (double& k : r.key) k = *row++;
  return r;
}

}  // namespace grainbank::db
